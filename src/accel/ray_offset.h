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

}  // namespace lancer
