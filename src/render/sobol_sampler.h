// Owen-scrambled Sobol' samples, padded in 1D and 2D sets, for the path tracer.
//
// Construction (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)):
//  - Each call consumes the next dimension(s): next1() one, next2() two. Dimension set d
//    (starting at the current dimension) gets its own seeds, hashed from (pixel, seed, d).
//  - The sample index is first shuffled: it goes through a nested uniform (Owen) scramble
//    with the set's shuffle seed. An Owen scramble of the index maps the first 2^k indices
//    onto one aligned block of 2^k indices, so every prefix of 2^k samples is still a
//    whole Sobol' block, while pixels and dimension sets see the blocks in unrelated
//    orders (this is what decorrelates the padded sets and neighbouring pixels).
//  - 2D sets take Sobol' dimensions 0 and 1 (a (0,2)-sequence), 1D sets dimension 0 (the
//    van der Corput sequence); each coordinate is then Owen-scrambled with its own seed.
//    Owen scrambling keeps the net property, so the first 2^k samples of a 2D set have
//    exactly one point in every elementary interval of area 2^-k (all shapes), and
//    converge like O(N^-1.5) on smooth integrands (Owen 1997).
//  - The Owen scramble is the hash of Laine & Karras 2011 ("Stratified Sampling for
//    Stochastic Transparency", EGSR) with the multipliers of Burley 2020: on the
//    bit-reversed value, adding a seed and x ^= x * even flip each bit as a function of
//    the bits below it only, which after reversal is a nested uniform scramble.
// Every value is a pure function of (x, y, sample index, seed, dimension); no state is
// shared between pixels. Values are 24-bit floats in [0, 1), never 1.
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec2.hpp>

namespace lancer {

namespace sobol {

constexpr std::uint32_t reverse_bits(std::uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
  return __builtin_bswap32(v);  // the bytes in reverse order: one instruction
}

// Generator matrix columns of Sobol' dimension 1 (the second), as 32-bit direction
// numbers v_k = m_k / 2^k. Joe & Kuo (2008, new-joe-kuo-6.21201) give this dimension the
// primitive polynomial x + 1 (degree s = 1, no inner coefficients) and m_1 = 1; the
// recurrence m_k = 2 m_{k-1} xor m_{k-1} then gives 1, 3, 5, 15, 17, ... (Pascal's
// triangle mod 2).
constexpr std::array<std::uint32_t, 32> second_dimension_directions() {
  std::array<std::uint32_t, 32> v{};
  std::uint32_t m = 1;
  for (int k = 1; k <= 32; ++k) {
    if (k > 1) m = (m << 1) ^ m;
    v[static_cast<std::size_t>(k - 1)] = m << (32 - k);
  }
  return v;
}

// Unscrambled Sobol' value of `index` in dimension 0 (van der Corput) or 1, as 0.32 fixed point.
constexpr std::uint32_t sobol_dimension0(std::uint32_t index) { return reverse_bits(index); }
std::uint32_t sobol_dimension1(std::uint32_t index);
// The same in the bit-reversed domain: reverse_bits(sobol_dimension1(reverse_bits(r))).
std::uint32_t reversed_sobol_dimension1(std::uint32_t reversed_index);

// Laine-Karras style permutation of a bit-reversed value: output bit b is input bit b
// xor a function of the bits below b and the seed. Multipliers from Burley 2020.
constexpr std::uint32_t laine_karras_permutation(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Nested uniform (Owen) scramble of a 0.32 fixed-point value: bit b (from the top) is
// flipped according to the bits above it.
constexpr std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

// The top 24 bits as a float: exact, in [0, 1), 0xFFFFFFFF gives 1 - 2^-24.
constexpr float to_unit_float(std::uint32_t bits) {
  return static_cast<float>(bits >> 8) * (1.0f / 16777216.0f);
}

}  // namespace sobol

class SobolSampler {
 public:
  SobolSampler(std::uint32_t x, std::uint32_t y, std::uint32_t sample_index, std::uint64_t seed);

  // One dimension: an Owen-scrambled, index-shuffled van der Corput value.
  float next1() { return get1(dimension_++); }
  // Two dimensions: an Owen-scrambled, index-shuffled point of Sobol' dimensions (0, 1).
  glm::vec2 next2() {
    const glm::vec2 v = get2(dimension_);
    dimension_ += 2;
    return v;
  }
  // Moves past `count` dimensions without computing them; get1/get2 compute any of them
  // later, or not at all when a path does not use them.
  void skip(std::uint32_t count) { dimension_ += count; }

  // The value next1() gives when dimension() is `dim`, and next2()'s for dims dim, dim + 1:
  // pure functions of the dimension, whatever was drawn before. Values drawn ahead
  // (take_ahead) are returned as they are: they are the same values.
  float get1(std::uint32_t dim) const {
    if (dim != kNoDimension) {
      if (dim == ahead_.dim1[0]) return ahead_.v1[0];
      if (dim == ahead_.dim1[1]) return ahead_.v1[1];
    }
    return compute1(dim);
  }
  glm::vec2 get2(std::uint32_t dim) const {
    if (dim != kNoDimension) {
      if (dim == ahead_.dim2[0]) return ahead_.v2[0];
      if (dim == ahead_.dim2[1]) return ahead_.v2[1];
    }
    return compute2(dim);
  }

  // The next dimension to be consumed (next1 advances it by 1, next2 by 2).
  std::uint32_t dimension() const { return dimension_; }

  // Drawing ahead (render/sobol_batch.h: many samplers' values at once, several per
  // vector): what the batch reads of this sampler, and the values it leaves here, which
  // get1(dim1[k]) and get2(dim2[k]) then return (kNoDimension: none).
  static constexpr std::uint32_t kNoDimension = 0xFFFFFFFFu;
  struct Keys {
    std::uint64_t shuffle, scramble;
    std::uint32_t reversed_index;
  };
  Keys keys() const { return {shuffle_key_, scramble_key_, reversed_index_}; }
  void take_ahead(const std::uint32_t dim1[2], const float v1[2], const std::uint32_t dim2[2], const glm::vec2 v2[2]) {
    for (int k = 0; k < 2; ++k) {
      ahead_.dim1[k] = dim1[k];
      ahead_.v1[k] = v1[k];
      ahead_.dim2[k] = dim2[k];
      ahead_.v2[k] = v2[k];
    }
  }

 private:
  float compute1(std::uint32_t dim) const;
  glm::vec2 compute2(std::uint32_t dim) const;
  // 64 hashed bits for dimension set `dim` of this pixel's stream `key` (shuffle or scramble).
  static std::uint64_t set_hash(std::uint32_t dim, std::uint64_t key);

  std::uint64_t shuffle_key_ = 0;   // the index shuffles' stream
  std::uint64_t scramble_key_ = 0;  // the value scrambles' stream
  std::uint32_t reversed_index_ = 0;  // reverse_bits(sample index)
  std::uint32_t dimension_ = 0;
  struct Ahead {
    std::uint32_t dim1[2] = {kNoDimension, kNoDimension};
    float v1[2] = {0.0f, 0.0f};
    std::uint32_t dim2[2] = {kNoDimension, kNoDimension};
    glm::vec2 v2[2] = {glm::vec2(0.0f), glm::vec2(0.0f)};
  } ahead_;
};

namespace sobol {
// reversed_sobol_dimension1's byte table k (0 to 3, 256 entries), for the batch draw.
const std::uint32_t* reversed_second_dimension_table(int k);
}  // namespace sobol

}  // namespace lancer
