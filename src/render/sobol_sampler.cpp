#include "render/sobol_sampler.h"

#include "simd/splitmix64.h"

namespace lancer {

namespace sobol {

namespace {
constexpr std::array<std::uint32_t, 32> kSecondDimension = second_dimension_directions();
}  // namespace

// x = C * bits(index): xor of the generator columns of the index's set bits.
std::uint32_t sobol_dimension1(std::uint32_t index) {
  std::uint32_t x = 0;
  for (std::size_t bit = 0; index != 0; index >>= 1, ++bit)
    if (index & 1u) x ^= kSecondDimension[bit];
  return x;
}

}  // namespace sobol

namespace {
constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;
constexpr std::uint64_t kShuffleSalt = 0x5F1E1D0A3C2B4E6Dull;
constexpr std::uint64_t kScrambleSalt = 0xC3A5C85C97CB3127ull;
}  // namespace

// The key depends on pixel and seed only: the sample index must stay outside the hash,
// since the stratification is over the index.
SobolSampler::SobolSampler(std::uint32_t x, std::uint32_t y, std::uint32_t sample_index, std::uint64_t seed)
    : index_(sample_index) {
  const std::uint64_t k = splitmix64_mix(seed + kGolden);
  pixel_key_ = splitmix64_mix(k ^ ((static_cast<std::uint64_t>(y) << 32) | x));
}

std::uint64_t SobolSampler::set_hash(std::uint32_t dim, std::uint64_t salt) const {
  return splitmix64_mix(splitmix64_mix(pixel_key_ ^ salt) + (static_cast<std::uint64_t>(dim) + 1) * kGolden);
}

float SobolSampler::next1() {
  const std::uint32_t dim = dimension_++;
  const std::uint64_t shuffle = set_hash(dim, kShuffleSalt);
  const std::uint64_t scramble = set_hash(dim, kScrambleSalt);
  const std::uint32_t index = sobol::owen_scramble(index_, static_cast<std::uint32_t>(shuffle));
  const std::uint32_t v = sobol::owen_scramble(sobol::sobol_dimension0(index), static_cast<std::uint32_t>(scramble));
  return sobol::to_unit_float(v);
}

glm::vec2 SobolSampler::next2() {
  const std::uint32_t dim = dimension_;
  dimension_ += 2;
  const std::uint64_t shuffle = set_hash(dim, kShuffleSalt);
  const std::uint64_t scramble = set_hash(dim, kScrambleSalt);  // two 32-bit seeds
  const std::uint32_t index = sobol::owen_scramble(index_, static_cast<std::uint32_t>(shuffle));
  const std::uint32_t a = sobol::owen_scramble(sobol::sobol_dimension0(index), static_cast<std::uint32_t>(scramble));
  const std::uint32_t b =
      sobol::owen_scramble(sobol::sobol_dimension1(index), static_cast<std::uint32_t>(scramble >> 32));
  return {sobol::to_unit_float(a), sobol::to_unit_float(b)};
}

}  // namespace lancer
