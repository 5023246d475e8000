// Photons leaving the lights: the first step of photon mapping (render/sppm, to come).
//
// Every light of a scene is one emitter: all emissive triangles together (AreaLights, which
// then picks a triangle by its own power distribution), each KHR_lights_punctual light, and
// the environment. An emitter is picked in proportion to its emitted power (luminance), a
// position and a direction are sampled on it, and the photon carries
//   power = Le |cos| / (p_pick p_position p_direction)  (per RGB channel),
// so that the mean of `power` over samples is the scene's total emitted power (W, in the
// glTF units the path tracer reads: radiance for emitters, candela for point and spot
// lights, lux for directional lights) and N photons each carry about 1/N of it.
//
// Light arriving from infinitely far (directional lights, the environment) enters through a
// disc perpendicular to its direction and tangent, on the light's side, to the bounding
// sphere of the scene's bounds (radius R, a little enlarged), of the same radius R: such
// rays cross every point of the scene, and the disc's area pi R^2 turns irradiance into
// power (the idea of pbrt-v4's DistantLight::SampleLe).
//
// Radiometric conventions match next-event estimation exactly: an emissive triangle's
// radiance goes through area_light_radiance (texture and coverage, render/light_sampling.h),
// a spot light's falloff through spot_falloff, and the range window (render/lights.h) is left
// to the photon tracer, which knows the distance of the first hit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "render/environment.h"
#include "render/lights.h"
#include "scene/scene.h"

namespace lancer {

// One photon leaving a light.
struct EmittedPhoton {
  Ray ray;  // dir unit; from an emissive triangle, org is pushed off it (SurfaceOffset), so
            // the photon cannot hit its own light again
  // Le |cos| / (p_pick p_position p_direction) per RGB channel: the mean over samples is the
  // total emitted power, so N photons shot each count power / N.
  glm::vec3 power{0.0f};
  // A punctual light's KHR_lights_punctual range (0: none): the photon tracer multiplies
  // `power` by range_window(distance to the first hit, range) (render/lights.h).
  float range = 0.0f;
  // From an emissive triangle: the density of its start in the throughput measure, p_pick
  // p_position p_direction / |cos| (light tracing's MIS weight, render/light_tracer.h); 0
  // from other lights.
  double start_density = 0.0;
  bool valid = false;  // false: the sample carries nothing (skip it; it still counts as one photon shot)
};

class LightEmission {
 public:
  // Which lights emit: all of them, or the emissive triangles alone (light tracing for the
  // path tracer, render/light_tracer.h, takes only light a path could also hit).
  enum class Emitters { All, TrianglesOnly };

  // Keeps references: scene, area_lights and environment (null: none) must outlive it.
  // A light that emits nothing (zero intensity, a spot cone without solid angle, a
  // directional light or environment in a scene without triangles) is never picked.
  LightEmission(const Scene& scene, const AreaLights& area_lights, const Environment* environment,
                Emitters emitters = Emitters::All);

  bool empty() const { return emitters_.empty(); }
  // Number of emitters that can be picked, in this order: the emissive triangles (all of
  // them one emitter), scene.lights in order, the environment; those that emit nothing are
  // left out.
  std::size_t size() const { return emitters_.size(); }
  // Luminance of the total emitted power (W), what the emitters are picked by. Exact but for
  // textured emitters, whose power AreaLights estimates on a grid (the photons' `power`
  // uses the texture at each point, so the estimate only steers the pick).
  double total_power() const { return total_; }
  // Probability that sample() picks emitter i.
  double pick_probability(std::size_t i) const { return emitters_[i].weight / total_; }

  // The disc distant light enters through: radius R and the centre of the sphere it is
  // tangent to (0 for a scene without triangles).
  float scene_radius() const { return radius_; }
  glm::vec3 scene_center() const { return center_; }

  // u_pick in [0, 1), u_pos and u_dir in [0, 1)^2. Must not be called when empty().
  EmittedPhoton sample(float u_pick, glm::vec2 u_pos, glm::vec2 u_dir) const;

 private:
  enum class Kind : std::uint8_t { Area, Point, Spot, Directional, Environment };
  struct Emitter {
    Kind kind = Kind::Area;
    std::uint32_t light = 0;     // index into scene.lights (punctual kinds)
    double weight = 0.0;         // luminance of the emitted power, > 0
    glm::vec3 axis{0.0f};        // unit: a spot's or directional light's direction
    float one_minus_cos = 0.0f;  // a spot's sampled cone: 1 - cos(outer cone)
  };

  EmittedPhoton sample_area(float u_pick, glm::vec2 u_pos, glm::vec2 u_dir, double p_pick) const;
  EmittedPhoton sample_punctual(const Emitter& e, glm::vec2 u_dir, double p_pick) const;
  EmittedPhoton sample_distant(const glm::vec3& dir, const glm::vec3& radiance_over_pdf, glm::vec2 u_pos,
                               double p_pick) const;

  const Scene& scene_;
  const AreaLights& area_lights_;
  const Environment* environment_;
  std::vector<Emitter> emitters_;
  std::vector<double> cdf_;  // cdf_[i]: total weight of emitters 0..i
  double total_ = 0.0;
  float radius_ = 0.0f;
  glm::vec3 center_{0.0f};
};

// The luminance of the power a spot light emits, over its intensity's luminance: the
// extension's falloff (spot_falloff) integrated over the sphere, 2 pi times the integral
// of the falloff over cos(angle). 0 for a light without a direction.
double spot_solid_angle(const PunctualLight& light);

// The integral over the sphere of the environment's radiance luminance (W / m^2 per unit
// of pi R^2): 4 pi luminance for a constant one, for a map the sum over its pixels of
// luminance times the pixel's solid angle (lookups are nearest-pixel).
double environment_luminance_integral(const Environment& environment);

}  // namespace lancer
