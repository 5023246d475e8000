// The answers lancer-bench compares before it times anything: a benchmark whose rays do
// not find the same triangles measures different work.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "accel/ray.h"

namespace lancer::bench {

// Two closest hits count as the same t when they differ by at most this, relative to t
// (Embree's Möller–Trumbore and Lancer's watertight kernel round differently).
inline constexpr float kSameTRelative = 1e-4f;

// More disagreements than this fraction of the rays (0.1%) means the two tracers do not
// trace the same scene: the row is not timed.
inline constexpr double kMaxDisagreementFraction = 1e-3;

struct Agreement {
  std::size_t compared = 0;
  std::size_t ties = 0;           // both hit, other triangle, same t
  std::size_t disagreements = 0;  // one misses, or different t
  std::size_t first_disagreement = static_cast<std::size_t>(-1);

  bool acceptable() const {
    return static_cast<double>(disagreements) <= kMaxDisagreementFraction * static_cast<double>(compared);
  }
};

// Lancer's closest hits against Embree's: the same triangle with the same t, a tie
// (another triangle at the same t), or a disagreement.
Agreement compare_closest(std::span<const Hit> lancer, std::span<const Hit> embree);

// Occlusion answers: every difference is a disagreement (there are no ties).
Agreement compare_occlusion(std::span<const std::uint8_t> lancer, std::span<const std::uint8_t> embree);

// Same triangle and bit-identical t, u and v.
bool same_hit_bits(const Hit& a, const Hit& b);

// How many answers differ bit for bit; `first` gets the first index that does.
std::size_t count_bit_differences(std::span<const Hit> a, std::span<const Hit> b, std::size_t& first);
std::size_t count_bit_differences(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b, std::size_t& first);

}  // namespace lancer::bench
