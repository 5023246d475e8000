// Shadow rays from a shading point towards a light, the same for every integrator.
#pragma once

#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "accel/ray_offset.h"
#include "scene/scene.h"

namespace lancer {

// Shadow rays towards a point stop this fraction short of it, so the light's own surface
// is never counted as an occluder.
inline constexpr float kShadowShorten = 1e-4f;

// Where a shadow ray goes, before its origin is known: to the point `target` (towards) or
// along the direction `target`, up to tfar. Its origin is SurfaceOffset::origin_towards
// (target) or origin(target) (the path tracer solves a bounce's origins in one batch).
struct ShadowAim {
  glm::vec3 target{0.0f};
  bool towards = false;
  float tfar = kInfinity;
};

// The shadow ray of `aim` from `origin`, at shutter time `time` (its path's).
inline Ray shadow_ray(const ShadowAim& aim, const glm::vec3& origin, float time) {
  Ray shadow;
  shadow.org = origin;
  shadow.time = time;
  shadow.dir = aim.towards ? aim.target - origin : aim.target;
  shadow.tfar = aim.tfar;
  return shadow;
}

inline glm::vec3 shadow_origin(const SurfaceOffset& leave, const ShadowAim& aim) {
  return aim.towards ? leave.origin_towards(aim.target) : leave.origin(aim.target);
}

// Towards a point on an emissive triangle, aimed at the point lifted off the light's
// surface (Wächter & Binder) so that the light's triangle is not hit.
inline ShadowAim aim_at_area_light(const glm::vec3& light_point, const glm::vec3& light_normal) {
  return {offset_ray_origin(light_point, light_normal), true, 1.0f - kShadowShorten};
}

// Along the unit direction `dir`, without bound (the environment, a directional light).
inline ShadowAim aim_along(const glm::vec3& dir) { return {dir, false, kInfinity}; }

// Towards a KHR_lights_punctual light: along wi (unit, towards the light) without bound for
// a directional light, up to the light's position otherwise.
inline ShadowAim aim_at_punctual(const PunctualLight& light, const glm::vec3& wi) {
  if (light.type == LightType::Directional) return aim_along(wi);
  return {light.position, true, 1.0f - kShadowShorten};
}

inline Ray shadow_ray_to_area_light(const SurfaceOffset& leave, const glm::vec3& light_point,
                                    const glm::vec3& light_normal) {
  const ShadowAim aim = aim_at_area_light(light_point, light_normal);
  return shadow_ray(aim, shadow_origin(leave, aim), leave.time());
}

inline Ray shadow_ray_to_punctual(const SurfaceOffset& leave, const PunctualLight& light, const glm::vec3& wi) {
  const ShadowAim aim = aim_at_punctual(light, wi);
  return shadow_ray(aim, shadow_origin(leave, aim), leave.time());
}

}  // namespace lancer
