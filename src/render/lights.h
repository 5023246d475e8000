// The lights a shading point is lit by: KHR_lights_punctual lights and emissive triangles.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "scene/scene.h"

namespace lancer {

// What a punctual light delivers at a point: the unit direction towards the light, the
// distance (infinite for directional lights) and the irradiance on a surface facing the
// light, per colour channel (W/m^2 in the extension's photometric-as-radiometric units).
struct PunctualIncidence {
  glm::vec3 wi{0.0f};
  float distance = 0.0f;
  glm::vec3 irradiance{0.0f};
};

// KHR_lights_punctual: point lights give I/d^2, spot lights add the extension's smooth
// angular falloff between the inner and outer cone, directional lights give I (lux).
// A range > 0 applies the window the extension recommends, max(min(1 - (d/range)^4, 1), 0).
PunctualIncidence illuminate(const PunctualLight& light, const glm::vec3& p);

// The distance window the KHR_lights_punctual extension recommends for a finite range:
// 1 when range <= 0 (no range). illuminate() applies it; a photon tracer applies it at the
// distance its photon first hits something.
float range_window(float distance, float range);

// The extension's spot falloff toward the unit direction `to_point` (from the light): a
// linear ramp in cos(angle) between the outer and inner cones, squared; 0 outside the outer
// cone and for a light without a direction. illuminate() multiplies the intensity by it.
float spot_falloff(const PunctualLight& light, const glm::vec3& to_point);

// One emissive triangle, emitting on its front side (the side cross(e1, e2) points to), or
// on both when its material is double-sided (render/shading_inputs.h, emits_toward).
struct EmissiveTriangle {
  std::uint32_t prim = 0;
  std::uint32_t instance = kNoHit;        // drawn through (Hit::instance), kNoHit: world space
  glm::vec3 a{0.0f}, e1{0.0f}, e2{0.0f};  // p = a + s e1 + t e2
  glm::vec3 normal{0.0f};                 // unit, front side
  float area = 0.0f;
  glm::vec3 radiance{0.0f};  // the material's factor x strength, before any texture
  bool two_sided = false;
  // Emitted power / pi: area x the mean luminance of the radiance over the triangle
  // (texture and coverage included), twice that when two-sided. What sample() picks by.
  double power = 0.0;
};

struct AreaLightSample {
  glm::vec3 point{0.0f};
  glm::vec3 normal{0.0f};  // the light's front side
  bool two_sided = false;  // it emits from the back side too
  glm::vec3 radiance{0.0f};
  float pdf_area = 0.0f;   // per unit area, including the choice of the triangle
  std::uint32_t prim = 0;  // the triangle, and the point's barycentrics (Hit's u, v)
  float b1 = 0.0f, b2 = 0.0f;
  std::uint32_t instance = kNoHit;  // the triangle's instance (Hit::instance)
};

// All emissive triangles of a scene (each drawing of an instanced one), chosen in proportion to their power (area times the
// luminance of the emitted radiance, averaged over the triangle where an emissive texture
// or a coverage varies it) and sampled uniformly in area. A triangle whose estimated
// power is 0 (its texture black wherever it was looked at) is not a light: paths that
// hit it by BSDF sampling count its emission in full (pdf_area is 0), so leaving it out
// costs noise at worst, never bias.
class AreaLights {
 public:
  explicit AreaLights(const Scene& scene);

  bool empty() const { return lights_.empty(); }
  std::size_t size() const { return lights_.size(); }
  const EmissiveTriangle& light(std::size_t i) const { return lights_[i]; }
  // Probability that sample() picks light i.
  float pick_probability(std::size_t i) const;

  // u_pick, u1, u2 in [0, 1). Must not be called when empty().
  AreaLightSample sample(float u_pick, float u1, float u2) const;
  // The area density sample() gives points of triangle `prim` drawn through `instance` (0
  // when it is not a light): what a path that hits the light by BSDF sampling needs for
  // multiple importance sampling.
  float pdf_area(std::uint32_t prim, std::uint32_t instance = kNoHit) const;

 private:
  std::vector<EmissiveTriangle> lights_;
  std::vector<double> cdf_;  // cdf_[i]: total power of lights 0..i, cdf_.back() == total
  // Where a drawn triangle's light is: per scene triangle, its rank among the emissive
  // triangles of its mesh (-1: not emissive); per instance, where its ranks start in
  // light_slot_; per drawn emissive triangle, the index into lights_ or -1.
  std::vector<std::int32_t> emissive_rank_;
  std::vector<std::size_t> instance_first_;
  std::vector<std::int32_t> light_slot_;
  bool instanced_ = false;
  std::int32_t light_index(std::uint32_t prim, std::uint32_t instance) const;
};

}  // namespace lancer
