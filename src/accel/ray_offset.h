// Robust origins for secondary rays.
//
// Follows Wächter & Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
// Ray Tracing Gems, chapter 6, 2019: move the hit point along the geometric normal by a
// fixed number of float ulps (so the offset scales with the magnitude of the coordinate),
// and by a small absolute amount near the origin where ulps become tiny.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

namespace lancer {

// `n` is the geometric normal, facing the side the new ray leaves from.
inline glm::vec3 offset_ray_origin(const glm::vec3& p, const glm::vec3& n) {
  constexpr float kOriginZone = 1.0f / 32.0f;  // below this |coordinate|, offset absolutely
  constexpr float kFloatScale = 1.0f / 65536.0f;
  constexpr float kIntScale = 256.0f;
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    const auto ulps = static_cast<std::int32_t>(kIntScale * n[i]);
    const auto bits = std::bit_cast<std::int32_t>(p[i]);
    const float moved = std::bit_cast<float>(bits + (p[i] < 0.0f ? -ulps : ulps));
    out[i] = std::fabs(p[i]) < kOriginZone ? p[i] + kFloatScale * n[i] : moved;
  }
  return out;
}

// The same for a point on a triangle whose vertices reach `triangle_scale` (the largest
// |coordinate| among them), pushed at least kTriangleScaleOffset * triangle_scale along n.
// Wächter & Binder size the offset by the point alone, which assumes the intersection
// test's error does too; but the watertight test's error grows with the vertices, so a
// ray leaving a 100 m mirror near the origin re-hits the mirror from a point a few |p|
// ulps away (seen in 15 % of such reflections). The floor of 2^-16 of the triangle's reach
// is far above that error and, for a scene of metres, a hundredth of a millimetre.
inline constexpr float kTriangleScaleOffset = 1.0f / 65536.0f;
inline glm::vec3 offset_ray_origin(const glm::vec3& p, const glm::vec3& n, float triangle_scale) {
  const glm::vec3 moved = offset_ray_origin(p, n);
  const glm::vec3 floor = p + (kTriangleScaleOffset * triangle_scale) * n;
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    // Whichever moved p further along n on this axis.
    out[i] = std::fabs(floor[i] - p[i]) > std::fabs(moved[i] - p[i]) ? floor[i] : moved[i];
  }
  return out;
}

}  // namespace lancer
