// Next-event estimation's light sample: a point on the emissive triangles as a shading
// point sees it. The one light-sampling routine of every integrator (path, Whitted, and
// the photon mapper to come), so they agree on the geometry, the densities and the
// radiance of textured emitters.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/lights.h"
#include "scene/scene.h"

namespace lancer {

struct LightSample {
  AreaLightSample point;  // where on which triangle, its emitting side's normal, area density
  glm::vec3 wi{0.0f};     // unit, from the shading point towards point.point
  float dist2 = 0.0f;     // squared distance between them
  float cos_l = 0.0f;     // cos between point.normal and -wi
  // Radiance the point sends towards the shading point: the triangle's emission with its
  // emissive texture at the point (glTF emissiveFactor x strength x texture).
  glm::vec3 radiance{0.0f};
  bool valid = false;  // a usable sample: distinct points, an emitting side faces p
  // The sample's density per unit solid angle at the shading point.
  float pdf_solid_angle() const { return point.pdf_area * dist2 / cos_l; }
};

// A sample of `lights` (not empty) from shading point p with sample values u_pick, u.
// Invalid (nothing to add) when the point coincides with p, has no density, or p lies
// behind the emitting side.
LightSample sample_area_light(const Scene& scene, const AreaLights& lights, const glm::vec3& p, float u_pick,
                              glm::vec2 u);

// The radiance the point `s` of an emissive triangle sends in the unit direction `w`, which
// must leave an emitting side: the triangle's emission (s.radiance) times its emissive
// texture and coverage at the point, as evaluate_shading sees the light there. What both
// next-event estimation (sample_area_light) and photons leaving the lights (render/
// light_emission.h) carry, so the two directions of light transport agree on textured lights.
glm::vec3 area_light_radiance(const Scene& scene, const AreaLightSample& s, const glm::vec3& w);

}  // namespace lancer
