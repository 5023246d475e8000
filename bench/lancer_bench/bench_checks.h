// The answers lancer-bench compares before it times anything: a benchmark whose rays do
// not find the same triangles measures different work.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "accel/ray.h"

namespace lancer::bench {

// Two closest hits count as the same t when they differ by at most this, relative to t
// (Embree's Möller–Trumbore and Lancer's watertight kernel round differently),
inline constexpr float kSameTRelative = 1e-4f;
// or, on the same triangle, by at most this fraction of the scene's largest extent, as a
// distance along the ray: a hit a short way from the ray's origin (a bounce ray meeting the
// next face) differs by the rounding of the coordinates, which is absolute, not relative to
// t. (rings-5's diffuse rays: 41 such pairs, 1e-6 apart at t = 0.004 in a scene 30 wide,
// counted as disagreements before.) Not for a tie: another triangle just past the one hit
// is a different answer.
inline constexpr float kSameTExtent = 1e-6f;

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

// Lancer's closest hits of `rays` against Embree's: the same triangle with the same t, a tie
// (another triangle at the same t), or a disagreement. `scene_extent` is the scene's largest
// extent (kSameTExtent).
Agreement compare_closest(std::span<const Ray> rays, std::span<const Hit> lancer, std::span<const Hit> embree,
                          float scene_extent);

// Occlusion answers: every difference is a disagreement (there are no ties).
Agreement compare_occlusion(std::span<const std::uint8_t> lancer, std::span<const std::uint8_t> embree);

// Same triangle and bit-identical t, u and v.
bool same_hit_bits(const Hit& a, const Hit& b);

// How many answers differ bit for bit; `first` gets the first index that does.
std::size_t count_bit_differences(std::span<const Hit> a, std::span<const Hit> b, std::size_t& first);
std::size_t count_bit_differences(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b, std::size_t& first);

}  // namespace lancer::bench
