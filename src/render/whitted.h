// Whitted-style recursive ray tracing (Whitted, "An Improved Illumination Model for
// Shaded Display", CACM 23(6), 1980), as taught in the course, with unbiased soft shadows
// from emissive triangles. It shades the surface the path tracer shades (evaluate_shading:
// textures, normal maps, emissive textures) with the Fresnel terms of fresnel.h.
//
// At each hit: emission (front side only) + one of
//  - mirror (metallic >= 0.5 and roughness < 0.2): Fresnel-Schlick with F0 = base colour
//    times the radiance of the reflected ray;
//  - smooth dielectric (weight = transmission): exact unpolarised Fresnel, Snell's law and
//    total internal reflection; both the reflected and the refracted ray are traced, the
//    refracted one tinted by the base colour (glTF KHR_materials_transmission). Radiance is
//    not scaled by eta^2 across the interface: the factors cancel for closed objects in air.
//    Only a volume boundary (KHR_materials_volume thicknessFactor > 0) refracts; a thin wall
//    (thicknessFactor 0, the default) reflects F(ior) from either side and passes the rest
//    straight on;
//  - Lambert (the remaining weight, BRDF = base colour / pi) lit directly by the punctual
//    lights (one shadow ray each) and by `light_samples` samples of the emissive triangles.
// KHR_materials_unlit surfaces show their base colour and stop there. A smooth clearcoat
// (KHR_materials_clearcoat, roughness below 0.2) is a mirror over all of this, reflecting its
// Fresnel share; a rough one is left out like every glossy lobe. A sheen (KHR_materials_sheen)
// adds its lobe to the direct lighting and dims what lies below it, as the path tracer's does.
// A surface covers the fraction alpha of its point (glTF alphaMode, render/coverage.h): the
// rest of the radiance comes from behind it along the same ray, and shadow rays let
// through 1 - alpha. Secondary rays stop after `max_depth` specular bounces (passing a
// surface is none); the background is black.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "accel/ray_offset.h"
#include "render/lights.h"
#include "render/sobol_sampler.h"
#include "render/shading_inputs.h"
#include "scene/scene.h"

namespace lancer {

class WhittedIntegrator {
 public:
  // Keeps references: all arguments must outlive the integrator.
  WhittedIntegrator(const Scene& scene, const Accelerator& accel, const AreaLights& area_lights, int max_depth,
                    int light_samples);

  // Radiance arriving at ray.org from direction -ray.dir (ray.dir unit length).
  // `rays` is increased by every ray traced (this one, shadow and secondary rays).
  glm::vec3 radiance(const Ray& ray, SobolSampler& sampler, std::uint64_t& rays) const {
    return trace(ray, 0, sampler, rays);
  }
  // radiance() for a ray the caller has already traced: `hit` must be accel.intersect(ray)
  // (e.g. from a packet of camera rays). Gives exactly radiance()'s value; `rays` is
  // increased by the shadow and secondary rays only, not by `ray` itself.
  glm::vec3 radiance_from_hit(const Ray& ray, const Hit& hit, SobolSampler& sampler, std::uint64_t& rays) const {
    return shade(ray, hit, 0, sampler, rays);
  }

 private:
  // Counts and intersects `ray`, then shades its hit.
  glm::vec3 trace(const Ray& ray, int depth, SobolSampler& sampler, std::uint64_t& rays) const;
  // Radiance along `ray` given its closest hit, `depth` specular bounces from the camera:
  // the surface's own for the fraction alpha it covers (render/coverage.h), what lies
  // behind it for the rest.
  glm::vec3 shade(const Ray& ray, const Hit& hit, int depth, SobolSampler& sampler, std::uint64_t& rays) const;
  // The covered surface's radiance: emission, the clearcoat's mirror, then shade_base.
  glm::vec3 shade_surface(const ShadingInputs& si, const Ray& ray, int depth, SobolSampler& sampler,
                          std::uint64_t& rays) const;
  // Below the coat: mirror, dielectric or Lambert, and the sheen.
  glm::vec3 shade_base(const ShadingInputs& si, const Ray& ray, int depth, SobolSampler& sampler,
                       std::uint64_t& rays) const;
  glm::vec3 mirror(const ShadingInputs& si, const Ray& ray, int depth, SobolSampler& sampler,
                   std::uint64_t& rays) const;
  glm::vec3 dielectric(const ShadingInputs& si, const Ray& ray, int depth, SobolSampler& sampler,
                       std::uint64_t& rays) const;
  // Reflected radiance from all lights through `response` (no emission of its own).
  struct DirectResponse;
  glm::vec3 direct_lighting(const ShadingInputs& si, const DirectResponse& response, SobolSampler& sampler,
                            std::uint64_t& rays) const;
  glm::vec3 punctual_lighting(const DirectResponse& response, const SurfaceOffset& leave, std::uint64_t& rays) const;
  glm::vec3 area_lighting(const DirectResponse& response, const SurfaceOffset& leave, SobolSampler& sampler,
                          std::uint64_t& rays) const;

  const Scene& scene_;
  const Accelerator& accel_;
  const AreaLights& area_lights_;
  int max_depth_;
  int light_samples_;
  bool has_coverage_;  // some material is MASK or BLEND
};

}  // namespace lancer
