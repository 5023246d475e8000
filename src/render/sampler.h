// Counter-based random numbers for rendering.
//
// Every value is a pure function of (pixel x, pixel y, sample index, seed, dimension):
// no state is shared between pixels, so an image is bit-identical whatever the thread
// count, tile size or tile order. The mixing function is the splitmix64 finaliser
// (Steele, Lea & Flood, "Fast Splittable Pseudorandom Number Generators", OOPSLA 2014),
// applied once per key component so that neighbouring keys give unrelated streams.
#pragma once

#include <cstdint>

#include "simd/splitmix64.h"

namespace lancer {

// splitmix64's output function (simd/splitmix64.h).
constexpr std::uint64_t mix64(std::uint64_t z) { return splitmix64_mix(z); }

// The top 24 bits as a float in [0, 1): exactly representable, never 1.
constexpr float to_unit_float(std::uint64_t bits) {
  return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);
}

// The random stream of one pixel sample. Dimensions are numbered 0, 1, 2, ... in the
// order the integrator asks for them; next() returns the value of the next dimension.
class PixelSampler {
 public:
  PixelSampler(std::uint32_t x, std::uint32_t y, std::uint32_t sample, std::uint64_t seed) {
    constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;
    std::uint64_t k = mix64(seed + kGolden);
    k = mix64(k ^ ((static_cast<std::uint64_t>(y) << 32) | x));
    key_ = mix64(k ^ (static_cast<std::uint64_t>(sample) * kGolden));
  }

  // Value of dimension `dim`, independent of how many values were drawn before.
  float get(std::uint32_t dim) const {
    return to_unit_float(mix64(key_ + (static_cast<std::uint64_t>(dim) + 1) * 0xD1B54A32D192ED03ull));
  }
  float next() { return get(dimension_++); }
  std::uint32_t dimension() const { return dimension_; }

 private:
  std::uint64_t key_ = 0;
  std::uint32_t dimension_ = 0;
};

}  // namespace lancer
