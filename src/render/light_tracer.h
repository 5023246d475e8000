// Light tracing for the path tracer's caustics seen directly: the paths camera - x1 -
// (delta bounces) - emissive triangle, with x1 scattering by a non-delta lobe and at least
// one delta bounce (a mirror, smooth glass) between it and the light.
//
// A path tracer finds those paths only when x1's BSDF sample happens to leave along the one
// delta chain that reaches a light: the caustic under a glass sphere, the bright patches a
// mirror throws on a wall. On the mirror/glass Cornell box they were most of the image's
// error. Traced from the light instead (the t = 1 strategy of bidirectional path tracing:
// Veach 1997, sec. 10.2; Pharr, Jakob & Humphreys, PBR 4th ed., "Light tracing"), each light
// path that reaches x1 through delta bounces is joined to the camera by one shadow ray and
// lands in the pixel x1 projects to.
//
// Both estimators take these paths, weighed by multiple importance sampling (Veach 1997,
// ch. 9, the power heuristic) so that each path counts once in all: where the light is small
// beside what the camera sees (the caustic under a glass sphere) the light paths carry
// nearly all of it, where the light is large and the view narrow the camera's paths do.
// Through delta bounces the throughput measure dA |cos| dw is conserved (Veach 1997, sec.
// 5.2; the refractive index's square cancels on a way from air back to air), so the two
// densities compare at the two ends of the chain:
//   camera paths:  p_cam(x1) p_bsdf(x1, w1) / |cos(w1, ng)|, p_cam the density of x1 per
//                  unit area a pixel's samples give (PinholeCamera::importance times the
//                  cosine at x1), w1 the direction x1 sends the path towards the chain;
//   light paths:   N p_light(y) / |cos| at the light point y, N the paths of a pass (a pixel
//                  takes one camera sample per pass).
// Both are functions of the path alone (the choices of lobe along the chain are left out of
// both), so the weights sum to 1 whichever side computes them. The other estimator's
// paths to the light (the path tracer's: PathIntegrator's light_tracer) take weight
// camera^2 / (camera^2 + light^2), the light tracer's its complement. A path of n scattering
// events counts on either side only if n <= max_depth.
//
// Units. Light path i carries flux Phi (render/light_emission.h, photon_walk.h); joined at
// x1 it adds to pixel p
//   Phi f(wo = to the camera, wi = back along the light path) |wi.n| / |wi.ng|
//       * |cos(to the camera, ng)| / (A_p r^2 cos^3 theta)   (PinholeCamera::connect)
// times the shadow ray's transmittance; the pixel's estimate is the sum over the N paths
// traced, over N (RenderState::mean). For a box filter this is the pixel's mean radiance
// over its area, what its camera samples average.
//
// Deterministic: light path i of pass s is sample s * N + i of its own sampler stream; the
// paths are traced in fixed chunks whose splats are added in chunk order, so the sums do
// not depend on the thread count, the tile size or the process.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/ray.h"

#include "accel/accelerator.h"
#include "render/camera.h"
#include "render/light_emission.h"
#include "render/lights.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace lancer {

class TileRunner;

// Light paths per pass: one per this many pixels. Measured on the mirror/glass Cornell box
// (256 x 256, 256 passes, 2 threads, AVX-512; MSE against the Cycles reference times
// seconds, lower is better): one path per pixel 3.21e-3, per 2 pixels 2.93e-3, per 4
// 2.71e-3, per 10 2.78e-3, per 20 2.96e-3; the path tracer alone 3.86e-3. The light paths'
// share of the error is small from one per 4 pixels on; their rays are not.
inline constexpr std::uint64_t kPixelsPerLightPath = 4;

class LightTracer {
 public:
  // Whether light tracing takes these paths in this render: the path integrator, a box
  // pixel filter, a perspective camera (pinhole or thin lens; an orthographic camera has no
  // point to join), nothing moving (the shutter closed), emissive triangles, a material that
  // may scatter by a delta lobe, no single-sided surface that lets light through (coverage,
  // transmission) and no absorbing volume (where light and camera paths would not take the
  // same ways), max_depth >= 2 and settings.light_traced_caustics. Elsewhere the path
  // tracer keeps these paths itself.
  static bool applies(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                      const AreaLights& area_lights);

  // Keeps references to everything given; all must outlive it.
  LightTracer(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
              const AreaLights& area_lights, const RenderSettings& settings);

  // Light paths per pass: one per kPixelsPerLightPath pixels (at least one).
  std::uint64_t paths_per_pass() const { return paths_per_pass_; }

  // The MIS densities (above). Camera side: x1 with geometric normal ng seen from the lens
  // point `lens`, the path leaving it towards w1 (unit) with BSDF density pdf_w1.
  double camera_density(const glm::vec3& lens, const glm::vec3& x1, const glm::vec3& ng, const glm::vec3& w1,
                        float pdf_w1) const;
  // Light side: a pass's paths leaving emissive triangle `prim` (of `instance`) where a path
  // reached it, in the throughput measure; 0 where no light path starts.
  double light_density(std::uint32_t prim, std::uint32_t instance) const;
  // The power heuristic's weight of the side with density `mine` against `other`'s.
  static float weight(double mine, double other) {
    const double a = mine * mine, b = other * other;
    return a + b > 0.0 ? static_cast<float>(a / (a + b)) : 0.0f;
  }

  // Traces pass `pass`'s light paths on `runner` and adds what each brings to a pixel into
  // sum (one per pixel, row-major), in an order no thread schedule changes. Returns the rays
  // traced. Not to be called from two threads at once (it reuses its splat lists).
  std::uint64_t trace_pass(int pass, TileRunner& runner, std::vector<glm::dvec3>& sum) const;

  // One light path's splats (exposed for tests): appended to `out`, rays counted.
  struct Splat {
    std::uint32_t pixel;
    glm::vec3 value;
  };
  void trace_path(std::uint64_t index, std::vector<Splat>& out, std::uint64_t& rays) const;

 private:
  const Scene& scene_;
  const Accelerator& accel_;
  const PinholeCamera& camera_;
  const AreaLights& area_lights_;
  LightEmission emission_;
  int max_depth_;
  std::uint64_t seed_;
  bool has_coverage_;
  std::uint64_t paths_per_pass_;
  std::vector<bool> smooth_;  // per material: may scatter by a delta lobe
  mutable std::vector<std::vector<Splat>> chunks_;
};

}  // namespace lancer
