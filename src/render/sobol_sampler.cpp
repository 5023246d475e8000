#include "render/sobol_sampler.h"

#include "simd/splitmix64.h"

namespace lancer {

namespace sobol {

namespace {

// Dimension 1's matrix conjugated by the bit reversal R: R C R, which maps the reversed
// index to the reversed Sobol' value. The sampler works on reversed values (that is where
// the Laine-Karras permutation acts), so this saves two reversals per value.
//
// A product with a GF(2) matrix is the xor of the products of the input's four bytes:
// table[k][b] = (R C R)(b << 8k), 4 KiB in all. Four loads replace a loop over the input's
// 32 bits whose branches (the shuffled index is random in every bit) cost most of a path
// tracer's sampling time.
using ByteTables = std::array<std::array<std::uint32_t, 256>, 4>;

constexpr ByteTables reversed_second_dimension_tables() {
  const std::array<std::uint32_t, 32> columns = second_dimension_directions();
  ByteTables t{};
  for (std::size_t k = 0; k < 4; ++k)
    for (std::uint32_t b = 0; b < 256; ++b) {
      std::uint32_t x = 0;
      for (std::size_t bit = 0; bit < 8; ++bit)  // input bit 8k + bit of R(index) is index bit 31 - 8k - bit
        if (b & (1u << bit)) x ^= columns[31 - (8 * k + bit)];
      t[k][b] = reverse_bits(x);
    }
  return t;
}

constexpr ByteTables kReversedSecondDimension = reversed_second_dimension_tables();

}  // namespace

std::uint32_t reversed_sobol_dimension1(std::uint32_t reversed_index) {
  const ByteTables& t = kReversedSecondDimension;
  const std::uint32_t r = reversed_index;
  return t[0][r & 0xFFu] ^ t[1][(r >> 8) & 0xFFu] ^ t[2][(r >> 16) & 0xFFu] ^ t[3][r >> 24];
}

const std::uint32_t* reversed_second_dimension_table(int k) {
  return kReversedSecondDimension[static_cast<std::size_t>(k)].data();
}

std::uint32_t sobol_dimension1(std::uint32_t index) {
  return reverse_bits(reversed_sobol_dimension1(reverse_bits(index)));
}

}  // namespace sobol

namespace {
constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;
constexpr std::uint64_t kShuffleSalt = 0x5F1E1D0A3C2B4E6Dull;
constexpr std::uint64_t kScrambleSalt = 0xC3A5C85C97CB3127ull;
}  // namespace

// The keys depend on pixel and seed only: the sample index must stay outside the hash,
// since the stratification is over the index. The two salted keys are hashed once here
// rather than once per dimension set.
SobolSampler::SobolSampler(std::uint32_t x, std::uint32_t y, std::uint32_t sample_index, std::uint64_t seed)
    : reversed_index_(sobol::reverse_bits(sample_index)) {
  const std::uint64_t k = splitmix64_mix(seed + kGolden);
  const std::uint64_t pixel_key = splitmix64_mix(k ^ ((static_cast<std::uint64_t>(y) << 32) | x));
  shuffle_key_ = splitmix64_mix(pixel_key ^ kShuffleSalt);
  scramble_key_ = splitmix64_mix(pixel_key ^ kScrambleSalt);
}

std::uint64_t SobolSampler::set_hash(std::uint32_t dim, std::uint64_t key) {
  return splitmix64_mix(key + (static_cast<std::uint64_t>(dim) + 1) * kGolden);
}

// The definitions in the header, rewritten in the bit-reversed domain so that fewer
// reversals are made (P = laine_karras_permutation, R = reverse_bits, R R = identity):
//   shuffled index: i' = owen_scramble(i, s) = R P(R i, s) = R y, with y = P(R i, s);
//   dimension 0:    owen_scramble(sobol_dimension0(i'), t) = R P(R R i', t) = R P(R y, t);
//   dimension 1:    owen_scramble(C i', t) = R P(R C R y, t) = R P(reversed_sobol_dimension1(y), t).
// The values are bit for bit the same (SobolSampler tests).
float SobolSampler::compute1(std::uint32_t dim) const {
  const auto shuffle = static_cast<std::uint32_t>(set_hash(dim, shuffle_key_));
  const auto scramble = static_cast<std::uint32_t>(set_hash(dim, scramble_key_));
  const std::uint32_t y = sobol::laine_karras_permutation(reversed_index_, shuffle);
  return sobol::to_unit_float(sobol::reverse_bits(sobol::laine_karras_permutation(sobol::reverse_bits(y), scramble)));
}

glm::vec2 SobolSampler::compute2(std::uint32_t dim) const {
  const auto shuffle = static_cast<std::uint32_t>(set_hash(dim, shuffle_key_));
  const std::uint64_t scramble = set_hash(dim, scramble_key_);  // two 32-bit seeds
  const std::uint32_t y = sobol::laine_karras_permutation(reversed_index_, shuffle);
  const std::uint32_t a =
      sobol::laine_karras_permutation(sobol::reverse_bits(y), static_cast<std::uint32_t>(scramble));
  const std::uint32_t b =
      sobol::laine_karras_permutation(sobol::reversed_sobol_dimension1(y), static_cast<std::uint32_t>(scramble >> 32));
  return {sobol::to_unit_float(sobol::reverse_bits(a)), sobol::to_unit_float(sobol::reverse_bits(b))};
}

}  // namespace lancer
