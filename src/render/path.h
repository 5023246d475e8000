// Unidirectional path tracing with next-event estimation at every bounce (Kajiya 1986;
// Veach 1997, ch. 9), glTF materials (bsdf.h) and the glTF lights:
//  - emissive triangles, sampled by power (lights.h), and the environment (environment.h)
//    are reached both by light sampling and by BSDF sampling, the two combined by
//    multiple importance sampling with the power heuristic (beta = 2);
//  - KHR_lights_punctual lights are delta lights: light sampling only, one shadow ray each;
//  - KHR_materials_volume: inside a transmissive volume, Beer-Lambert attenuation
//    exp(-sigma_a t) with sigma_a = -ln(attenuationColor) / attenuationDistance;
//  - Russian roulette from the fourth bounce on, with survival probability
//    min(1, max throughput component) (at least 5 %).
// Emission counts on the front side of a triangle only (the side lights.h samples).
// alphaMode is ignored (every triangle is opaque). The background is black unless an
// environment is given.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "render/environment.h"
#include "render/lights.h"
#include "render/sobol_sampler.h"
#include "scene/scene.h"

namespace lancer {

class PathIntegrator {
 public:
  // Keeps references: all must outlive the integrator. `environment` may be null (black).
  // max_depth: the longest path, in bounces after the camera ray (0: emission seen directly).
  // light_samples: points sampled on the emissive triangles at each bounce (at least 1),
  // each with its shadow ray, combined with the BSDF sample by MIS (Veach 1997, 9.2.4,
  // with n_light = light_samples and n_bsdf = 1).
  PathIntegrator(const Scene& scene, const Accelerator& accel, const AreaLights& area_lights,
                 const Environment* environment, int max_depth, int light_samples = 1);

  // Radiance arriving along -ray.dir at ray.org, given the camera ray's closest hit.
  // `rays` is increased by every ray traced here (not the camera ray itself).
  glm::vec3 radiance_from_hit(const Ray& ray, const Hit& hit, SobolSampler& sampler, std::uint64_t& rays) const;

 private:
  const Scene& scene_;
  const Accelerator& accel_;
  const AreaLights& area_lights_;
  const Environment* environment_;
  int max_depth_;
  int light_samples_;
};

}  // namespace lancer
