// What every path of light shares, camera paths and photons alike: the sample layout of a
// bounce, Veach's power heuristic, Russian roulette, and next-event estimation toward every
// light. The path tracer (path.cpp), SPPM's camera paths (sppm.cpp) and the photon walk
// (photon_walk.h) all read them from here, so that they render the same light transport.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

#include "render/bsdf_base.h"
#include "render/environment.h"
#include "render/light_sampling.h"
#include "render/lights.h"
#include "render/shadow_ray.h"
#include "render/sobol_sampler.h"
#include "scene/scene.h"

namespace lancer::path_rules {

// Where each camera-path bounce's sample values lie among its dimensions: a fixed layout
// whatever is used.
constexpr std::uint32_t kLightPickDimension = 0;     // which emissive triangle
constexpr std::uint32_t kLightPointDimensions = 1;   // and 2: the point on it
constexpr std::uint32_t kEnvironmentDimensions = 3;  // and 4: a direction toward the environment
constexpr std::uint32_t kSplitDimension = 5;         // reflection or refraction
constexpr std::uint32_t kBsdfDimensions = 6;         // and 7: the direction within the lobe
constexpr std::uint32_t kRouletteDimension = 8;      // also the coverage choice, rescaled
constexpr std::uint32_t kBounceDimensions = 9;       // with one light sample
constexpr std::uint32_t kLightDimensions = 3;        // each further light sample: pick and point

// The dimensions one bounce takes with `light_samples` samples of the emissive triangles.
constexpr std::uint32_t bounce_dimensions(int light_samples) {
  return kBounceDimensions + kLightDimensions * static_cast<std::uint32_t>(light_samples - 1);
}

// Russian roulette from the fourth bounce on (scattering event kRouletteDepth + 1), with
// survival min(1, sqrt(max throughput component / its start)), at least kMinSurvival.
// sqrt: paths end later than with the throughput itself (as Cycles does it); measured in
// path.cpp's history, docs/performance.md.
constexpr int kRouletteDepth = 3;
constexpr float kMinSurvival = 0.05f;

// Whether the roulette is played after scattering event `bounces` (counted from 1), the
// path's throughput (relative to its start) being `throughput`: from kRouletteDepth on, but
// after a delta event (a mirror, a smooth refraction) only once the throughput has fallen
// below kDeltaRouletteBelow. Such an event keeps most of the throughput and adds no choice
// of its own, and the light it passes on is the rare, bright caustic: killing it there
// added variance where the image has most (measured: the mirror/glass Cornell box's MSE
// -16 % for 5 % more time, four seeds, docs/performance.md). A path caught between two
// imperfect mirrors still ends soon, not at the bounce limit.
constexpr float kDeltaRouletteBelow = 1.0f / 16.0f;
inline bool roulette_after(int bounces, bool delta, float throughput) {
  return bounces >= kRouletteDepth && (!delta || throughput < kDeltaRouletteBelow);
}

inline float max_component(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
inline bool is_black(const glm::vec3& v) { return v.x <= 0.0f && v.y <= 0.0f && v.z <= 0.0f; }
inline bool is_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The survival probability of a path whose throughput is `throughput` (its largest
// component, relative to where it started).
inline float survival(float throughput) { return std::max(kMinSurvival, std::min(1.0f, std::sqrt(throughput))); }

// A bounce's coverage choice and its Russian roulette share one sample value (the bounce's
// roulette dimension: kRouletteDimension after its first, or the photon walk's own): a
// BLEND surface's choice reads it, and the roulette then reads it rescaled to [0, 1) within
// the part that kept the surface, so each use stays uniform and stratified. One per bounce.
class BounceChance {
 public:
  BounceChance(const SobolSampler& sampler, std::uint32_t dimension) : sampler_(sampler), dim_(dimension) {}
  // Whether the ray goes on past a surface of coverage `alpha` (< 1; render/coverage.h):
  // always where alpha is 0, else with probability 1 - alpha.
  bool passes(float alpha) {
    if (!(alpha > 0.0f)) return true;
    const float u = sampler_.get1(dim_);
    u_roulette_ = std::min(u / alpha, 0x1.fffffep-1f);  // the quotient may round up to 1
    return u >= alpha;
  }
  // The roulette's value: the coverage choice's, rescaled, when it drew one.
  float roulette() const { return u_roulette_ >= 0.0f ? u_roulette_ : sampler_.get1(dim_); }

 private:
  const SobolSampler& sampler_;
  std::uint32_t dim_;
  float u_roulette_ = -1.0f;  // not drawn yet
};

// The Russian roulette after scattering event `bounces` (roulette_after), played with
// `chance`, `throughput` being max_component(beta) relative to where the path started:
// false when the path ends here; else true, with beta divided by its survival probability
// where the roulette was played. The one roulette step of every integrator.
inline bool survives_roulette(int bounces, bool delta, float throughput, const BounceChance& chance,
                              glm::vec3& beta) {
  if (!roulette_after(bounces, delta, throughput)) return true;
  const float survive = survival(throughput);
  if (chance.roulette() >= survive) return false;
  beta /= survive;
  return true;
}

// Veach's power heuristic with beta = 2, the weight of the strategy with density `a`.
inline float power_heuristic(float a, float b) {
  if (!(a > 0.0f)) return 0.0f;
  if (std::isinf(a)) return 1.0f;
  const float a2 = a * a, b2 = b * b;
  return std::isfinite(b2) ? a2 / (a2 + b2) : 0.0f;
}

// Next-event estimation at shading point p, the bounce's dimensions starting at `dims`:
// light_samples points on the emissive triangles, one direction toward the environment (when
// not null) and every punctual light. For each sample that the BSDF and the light both carry,
// emit(aim, contribution) with contribution = beta f L / pdf times the MIS weight against the
// BSDF sample when `mis`, else in full (where the BSDF is not sampled for light); the caller
// traces the shadow ray now (SPPM) or queues it (the path tracer's wavefront).
// evaluate(wi) -> BsdfEval: the BSDF at p, the wedge handled as shading_inputs.h says.
template <class Evaluate, class Emit>
void next_event_estimation(const Scene& scene, const AreaLights& area_lights, const Environment* environment,
                           int light_samples, const glm::vec3& p, const SobolSampler& sampler, std::uint32_t dims,
                           const glm::vec3& beta, bool mis, Evaluate&& evaluate, Emit&& emit) {
  // Emissive triangles: the first sample in the bounce's base layout, the others after it,
  // combined with the BSDF sample by MIS as one strategy of light_samples samples.
  for (int k = 0; k < light_samples && !area_lights.empty(); ++k) {
    const std::uint32_t at = k == 0 ? dims : dims + kBounceDimensions + kLightDimensions * (k - 1);
    const LightSample ls = sample_area_light(scene, area_lights, p, sampler.get1(at + kLightPickDimension),
                                             sampler.get2(at + kLightPointDimensions));
    if (!ls.valid) continue;
    const BsdfEval e = evaluate(ls.wi);
    if (is_black(e.f)) continue;
    const float light_pdf = light_samples * ls.pdf_solid_angle();
    const float w = mis ? power_heuristic(light_pdf, e.pdf) : 1.0f;
    emit(aim_at_area_light(ls.point.point, ls.point.normal), beta * e.f * ls.radiance * (w / light_pdf));
  }
  if (environment) {
    const EnvSample es = environment->sample(sampler.get2(dims + kEnvironmentDimensions));
    const BsdfEval e = es.pdf > 0.0f ? evaluate(es.dir) : BsdfEval{};
    if (!is_black(e.f) && !is_black(es.radiance)) {
      const float w = mis ? power_heuristic(es.pdf, e.pdf) : 1.0f;
      emit(aim_along(es.dir), beta * e.f * es.radiance * (w / es.pdf));
    }
  }
  // Punctual lights: delta lights, one shadow ray each, no MIS.
  for (const PunctualLight& light : scene.lights) {
    const PunctualIncidence in = illuminate(light, p);
    if (is_black(in.irradiance)) continue;
    const glm::vec3 f = evaluate(in.wi).f;
    if (is_black(f)) continue;
    emit(aim_at_punctual(light, in.wi), beta * f * in.irradiance);
  }
}

}  // namespace lancer::path_rules
