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

// Towards a point on an emissive triangle, aimed at the point lifted off the light's
// surface (Wächter & Binder) so that the light's triangle is not hit.
inline Ray shadow_ray_to_area_light(const SurfaceOffset& leave, const glm::vec3& light_point,
                                    const glm::vec3& light_normal) {
  Ray shadow;
  const glm::vec3 end = offset_ray_origin(light_point, light_normal);
  shadow.org = leave.origin_towards(end);
  shadow.dir = end - shadow.org;
  shadow.tfar = 1.0f - kShadowShorten;
  return shadow;
}

// Towards a KHR_lights_punctual light: along wi (unit, towards the light) without bound for
// a directional light, up to the light's position otherwise.
inline Ray shadow_ray_to_punctual(const SurfaceOffset& leave, const PunctualLight& light, const glm::vec3& wi) {
  Ray shadow;
  if (light.type == LightType::Directional) {
    shadow.org = leave.origin(wi);
    shadow.dir = wi;
  } else {
    shadow.org = leave.origin_towards(light.position);
    shadow.dir = light.position - shadow.org;
    shadow.tfar = 1.0f - kShadowShorten;
  }
  return shadow;
}

}  // namespace lancer
