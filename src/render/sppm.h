// Stochastic progressive photon mapping (Hachisuka & Jensen 2009, "Stochastic Progressive
// Photon Mapping", SIGGRAPH Asia): caustics and other light that reaches a diffuse surface
// through delta or glossy bounces, which next-event estimation cannot see.
//
// Each iteration:
//  1. Camera pass: one jittered camera path per pixel (the path tracer's camera rays and
//     samplers), through delta and glossy-only surfaces, to a visible point on the first
//     surface with a diffuse (Lambertian or sheen) lobe. On the way it collects what needs no
//     photons: emission seen (weighted by MIS where a glossy bounce found it) and direct light
//     by next-event estimation at every non-delta vertex (the path tracer's light sampling;
//     with MIS at the glossy vertices the path passes, in full at the visible point, whose
//     non-delta lobes are not sampled). Where the visible point's BSDF also has a delta lobe
//     (a smooth coat, a smooth specular layer) the path goes on through it with that lobe's
//     probability, and otherwise stops with its throughput divided by the rest.
//  2. Photon pass: photons leave the lights by power and scatter through the same BSDFs, by
//     their adjoint (render/photon_walk.h, shared with the caustic photon map); from their
//     second surface on they are left on every surface with a diffuse lobe.
//  3. Gather: each visible point sums power * f(wo, wi) |wi.n| / |wi.ng| over the photons
//     within its radius (photon_grid.h), then updates its statistics (Hachisuka & Jensen
//     2009, eq. 7-8 with alpha = 2/3): N' = N + alpha M, r' = r sqrt(N' / (N + M)),
//     tau' = (tau + beta Phi) r'^2 / r^2.
// A pixel's value after n iterations of Np photons: Ld / n + tau / (n Np pi r^2).
//
// Every random number is a pure function of (pixel or photon, iteration, seed), photons are
// stored per fixed chunk and gathered in a fixed order: the image does not depend on the
// thread count. Photon paths and camera paths are each limited to max_depth bounces.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "render/environment.h"
#include "render/light_emission.h"
#include "render/lights.h"
#include "render/photon_grid.h"
#include "render/sobol_sampler.h"
#include "scene/scene.h"

namespace lancer {

class SppmIntegrator {
 public:
  // Keeps references: all must outlive the integrator. `environment` may be null (black).
  SppmIntegrator(const Scene& scene, const Accelerator& accel, const AreaLights& area_lights,
                 const LightEmission& emission, const Environment* environment, int max_depth, int light_samples);

  // Where a camera path stopped on a diffuse surface: the ray that found it and its hit
  // (the shading point is evaluated again at the gather: smaller than keeping it), the path's
  // throughput there, and the length of the path from the camera (for the initial radius).
  struct VisiblePoint {
    Ray ray;
    Hit hit;
    glm::vec3 beta{0.0f};
    float distance = 0.0f;
    int bounces = 0;  // scattering events before it: photons may bring max_depth - bounces - 1 more
    bool valid = false;
  };
  struct CameraPath {
    glm::vec3 L{0.0f};  // what the path found without photons
    VisiblePoint vp;
  };
  // The camera path of `ray`, whose closest hit is `hit`, drawing from `sampler` only.
  // `rays` is increased by every ray traced here. emission_apart: the emission met at an
  // opaque first surface is estimated elsewhere (render/camera_emission.h) and left out.
  CameraPath camera_path(const Ray& ray, const Hit& hit, SobolSampler& sampler, std::uint64_t& rays,
                         bool emission_apart = false) const;

  // Photon number `index` of the render (counting over all iterations), from its own sampler
  // stream: appends the photons it leaves to `out`.
  void trace_photon(std::uint64_t index, std::uint64_t seed, std::vector<Photon>& out, std::uint64_t& rays) const;

  // The flux `vp` gathers from `grid` within `radius`: Phi (before the point's throughput) and
  // the photon count M.
  struct Gathered {
    glm::vec3 phi{0.0f};
    std::uint32_t count = 0;
  };
  Gathered gather(const VisiblePoint& vp, const PhotonGrid& grid, float radius) const;

 private:
  const Scene& scene_;
  const Accelerator& accel_;
  const AreaLights& area_lights_;
  const LightEmission& emission_;
  const Environment* environment_;
  int max_depth_;
  int light_samples_;
  bool has_coverage_;
};

}  // namespace lancer
