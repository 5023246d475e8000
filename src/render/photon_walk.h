// One photon's way from a light through the scene: the walk both photon mappers share
// (SPPM, render/sppm.h, and the caustic photon map, render/caustic_map.h). They differ only
// in where a photon is kept and whether it may scatter by a non-delta lobe; that is the
// caller's visit().
//
// The photon leaves a light by power (light_emission.h), passes through coverage as the
// path tracer's rays do (render/coverage.h), is attenuated inside volumes (Beer-Lambert),
// takes a punctual light's range window at its first surface, scatters by the adjoint of
// the kernel the camera side gathers with (Veach 1997, sec. 3.7.5 and 5.3; see walk_photon),
// and meets Russian roulette with the path tracer's rule (path_rules.h), relative to the
// power it left with.
//
// Its random numbers are sample `index` of the sampler stream (index >> 32, stream_y): each
// photon is a pure function of (index, stream, seed), whatever the thread that traces it.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "accel/ray_offset.h"
#include "render/coverage.h"
#include "render/light_emission.h"
#include "render/lights.h"
#include "render/path_rules.h"
#include "render/ray_sets.h"
#include "render/shading_inputs.h"
#include "render/sobol_sampler.h"
#include "render/surface_bsdf.h"
#include "render/tile_scheduler.h"

namespace lancer {

// A surface a photon met and scatters at (not one it passed through).
struct PhotonVertex {
  const ShadingInputs& si;
  const SurfaceScattering& sc;  // seen from wo
  glm::vec3 wo;                 // unit, back towards where the photon came from
  glm::vec3 power;              // the flux it carries on arrival
  int bounces;                  // scattering events before this surface
  const Hit& hit;               // the photon's hit on this surface
  double start_density;         // EmittedPhoton::start_density of its light
};

// What visit() lets the photon do next.
enum class PhotonGoes { Stop, AnyLobe, DeltaOnly };

namespace photon_walk {
// Where a photon's values lie among its dimensions: where it leaves the light, then per
// surface met the same four uses.
constexpr std::uint32_t kEmitPickDimension = 0;
constexpr std::uint32_t kEmitPositionDimensions = 1;   // and 2
constexpr std::uint32_t kEmitDirectionDimensions = 3;  // and 4
constexpr std::uint32_t kEmitDimensions = 5;
constexpr std::uint32_t kSplitDimension = 0;
constexpr std::uint32_t kBsdfDimensions = 1;  // and 2
constexpr std::uint32_t kRouletteDimension = 3;  // also the coverage choice, rescaled
constexpr std::uint32_t kBounceDimensions = 4;
}  // namespace photon_walk

// How a photon leaves a surface it scatters at: its new direction b, and the factor its
// power takes on the way.
struct PhotonScatter {
  glm::vec3 wi{0.0f};
  glm::vec3 factor{0.0f};
  bool delta = false;
  bool transmitted = false;
};

// Of the photons leaving a surface whose normal bends (SurfaceScattering::bends), the share
// drawn by the cosine around ng instead of by the BSDF (scatter_photon), where the BSDF has a
// diffuse lobe or a roughness of 0.5 or more. A glossy BSDF alone leaves little of its adjoint
// in its wedge, and there the share falls with the roughness (0.1: a fortieth), so that few of
// its photons take the cosine's low weights.
inline constexpr float kPhotonCosineShare = 0.125f;
inline float photon_cosine_share(const ShadingInputs& si, const SurfaceScattering& sc) {
  return sc.bsdf.has_diffuse() ? kPhotonCosineShare : kPhotonCosineShare * std::min(1.0f, 2.0f * si.roughness);
}

// The photon's way on from the surface (si, sc seen from wo, back where it came from), from
// sample values u_split and u; nullopt when it is absorbed, or when `delta_only` and it would
// leave by a non-delta lobe (a caustic photon's end).
//
// Photons carry flux, so they scatter by the adjoint of the kernel the camera side gathers
// with: K(wo, wi) = f |wi.n| as the camera sees the surface from the new direction b, with
// the photon's way back as wi, and the flux through the true surface needs |b.ng| / |a.ng|,
// a = wo here (Veach 1997, sec. 3.7.5 and 5.3). K is evaluated rather than assumed
// symmetric: a bent normal depends on the viewer (shading_inputs.h), and a rough
// refraction's BTDF differs from its transpose by eta^2 (bsdf_base.h, "importance form").
// Where normals bend, the BSDF seen from wo draws no b in its own wedge, while K can be
// positive there (the normal bent for b may still reflect toward wo). So there b is drawn
// from a mixture that reaches every direction on wo's side: by the cosine around ng with
// probability photon_cosine_share (u_split, which a bending BSDF does not read, decides),
// else by the BSDF, and weighed by the mixture's density. Only SPPM's photons go on by
// non-delta lobes, so only they take it. (Drawn by the BSDF alone, they lost 10-14 % of the
// flux at a steeply leaning normal, photon_walk_test.cpp, and the normal-mapped still life's
// SPPM image was about 0.4 % darker, docs/performance.md.)
// Delta lobes are symmetric: their weight with the shading-normal correction (Veach's
// eq. 5.17) is exact, but for the layers' share of a base lobe under a coat or a sheen
// (Bsdf::Outgoing::base_scale), which the camera side takes at its own direction, b here.
inline std::optional<PhotonScatter> scatter_photon(const ShadingInputs& si, const SurfaceScattering& sc,
                                                   const glm::vec3& wo, float u_split, glm::vec2 u,
                                                   bool delta_only = false) {
  const float a_ng = std::abs(glm::dot(wo, si.ng));
  if (!(a_ng > 0.0f)) return std::nullopt;
  PhotonScatter out;
  float pdf = 0.0f;
  if (sc.bends) {
    if (delta_only) return std::nullopt;  // a bending BSDF has no delta lobe
    // K is 0 below wo's side, where a camera would see the surface's back and a bending BSDF
    // (it only reflects) sends nothing; evaluate_seen_from does not say so itself, hence the
    // side's check below.
    const glm::vec3 side = glm::dot(wo, si.ng) > 0.0f ? si.ng : -si.ng;
    const float cosine = photon_cosine_share(si, sc);
    float bsdf_pdf = 0.0f;  // the BSDF's density of out.wi (a sample's own, else evaluated)
    if (u_split < cosine) {
      out.wi = cosine_hemisphere_direction(side, u.x, u.y);
      bsdf_pdf = sc.evaluate(out.wi).pdf;
    } else {
      const std::optional<BsdfSample> bs = sc.sample(0.0f, u);
      if (!bs) return std::nullopt;
      out.wi = bs->wi;
      bsdf_pdf = bs->pdf;
    }
    const float b_side = glm::dot(out.wi, side);
    if (!(b_side > 0.0f)) return std::nullopt;
    pdf = (1.0f - cosine) * bsdf_pdf + cosine * b_side * std::numbers::inv_pi_v<float>;
  } else {
    const std::optional<BsdfSample> bs = sc.sample(u_split, u);
    if (!bs || (delta_only && !bs->delta)) return std::nullopt;
    out.wi = bs->wi;
    out.delta = bs->delta;
    out.transmitted = bs->transmitted;
    if (bs->delta) {
      const glm::vec3& b = bs->wi;
      const float b_ns = std::abs(glm::dot(b, si.ns));
      if (!(b_ns > 0.0f)) return std::nullopt;
      float layers = 1.0f;
      if (sc.bsdf.layered() && !bs->layer)
        layers = sc.out.base_scale > 0.0f ? sc.bsdf.outgoing(b).base_scale / sc.out.base_scale : 0.0f;
      out.factor = bs->weight * (layers * std::abs(glm::dot(wo, si.ns)) * std::abs(glm::dot(b, si.ng)) / (a_ng * b_ns));
      return out;
    }
    pdf = bs->pdf;
  }
  if (!(pdf > 0.0f)) return std::nullopt;
  const glm::vec3 k = sc.evaluate_seen_from(out.wi, wo).f;
  out.factor = k * (std::abs(glm::dot(out.wi, si.ng)) / (a_ng * pdf));
  return out;
}

// Ends no photon early (walk_photon's default `ends`).
struct EndsNoPhoton {
  bool operator()(const Ray&, const Hit&, int) const { return false; }
};

// Walks photon `index` of stream (stream_y, seed), its power multiplied by power_scale.
// visit(const PhotonVertex&) -> PhotonGoes is called at every surface the photon scatters
// at (unlit surfaces absorb it first); `rays` counts the rays traced. `emission` must not
// be empty. ends(ray, hit, bounces) -> bool, asked at every hit before the surface is
// shaded, may end the photon there: for a caller that knows the surface will not matter to it.
template <class Visit, class Ends = EndsNoPhoton>
void walk_photon(const Scene& scene, const Accelerator& accel, const LightEmission& emission, std::uint64_t index,
                 std::uint32_t stream_y, std::uint64_t seed, float power_scale, std::uint64_t& rays, Visit&& visit,
                 Ends ends = {}) {
  using namespace photon_walk;
  using path_rules::is_black, path_rules::is_finite, path_rules::max_component;
  SobolSampler sampler(static_cast<std::uint32_t>(index >> 32), stream_y, static_cast<std::uint32_t>(index), seed);
  const EmittedPhoton emitted = emission.sample(sampler.get1(kEmitPickDimension), sampler.get2(kEmitPositionDimensions),
                                                sampler.get2(kEmitDirectionDimensions));
  sampler.skip(kEmitDimensions);
  if (!emitted.valid) return;
  glm::vec3 beta = emitted.power * power_scale;
  const float start_power = max_component(beta);
  if (!(start_power > 0.0f) || !std::isfinite(start_power)) return;
  Ray ray = emitted.ray;
  int bounces = 0, crossings = 0;
  float from_light = 0.0f;  // distance travelled before the first scattering (the range window)
  bool in_volume = false;
  glm::vec3 sigma_a(0.0f);
  for (;;) {
    ++rays;
    const Hit hit = accel.intersect(ray);
    if (!hit.valid() || ends(ray, hit, bounces)) return;
    const float dir_length = glm::length(ray.dir);
    const glm::vec3 dir = ray.dir / dir_length;
    const float segment = hit.t * dir_length;
    if (in_volume) beta *= glm::exp(-sigma_a * segment);
    const ShadingInputs si = evaluate_shading(scene, ray, hit);
    const std::uint32_t dims = sampler.dimension();
    sampler.skip(kBounceDimensions);
    path_rules::BounceChance chance(sampler, dims + kRouletteDimension);
    if (si.alpha < 1.0f && crossings < kMaxCrossings && chance.passes(si.alpha)) {  // coverage: as the path tracer
      if (bounces == 0) from_light += segment;
      ++crossings;
      ray = continue_past(scene, ray, hit);
      continue;
    }
    if (bounces == 0 && emitted.range > 0.0f) {
      beta *= range_window(from_light + segment, emitted.range);
      if (is_black(beta)) return;
    }
    if (si.unlit) return;  // shows its colour, scatters nothing
    const glm::vec3 wo = -dir;
    const SurfaceScattering sc(si, wo);
    const PhotonGoes goes = visit(PhotonVertex{si, sc, wo, beta, bounces, hit, emitted.start_density});
    if (goes == PhotonGoes::Stop) return;
    // A bending BSDF has no transmission, so the split value is free for scatter_photon's choice.
    const float u_split = sc.bsdf.reads_split() || sc.bends ? sampler.get1(dims + kSplitDimension) : 0.0f;
    const std::optional<PhotonScatter> next =
        scatter_photon(si, sc, wo, u_split, sampler.get2(dims + kBsdfDimensions), goes == PhotonGoes::DeltaOnly);
    if (!next) return;
    beta *= next->factor;
    if (is_black(beta) || !is_finite(beta)) return;
    if (next->transmitted && !si.thin_walled) in_volume = si.front_face && volume_absorption(si, sigma_a);
    crossings = 0;
    if (!path_rules::survives_roulette(++bounces, next->delta, max_component(beta) / start_power, chance, beta)) return;
    ray = leaving_ray(scene, si, next->wi);
  }
}

// Photons traced by one task: each chunk keeps its own list.
inline constexpr std::size_t kPhotonChunk = 4096;

// Photons 0..count-1 in parallel on `runner`, in fixed chunks of kPhotonChunk:
// trace(i, out, rays) appends what photon i leaves to chunk list `out` (cleared first, its
// memory kept for the next call) and counts its rays. The lists, read in chunk order, hold
// the photons in an order no thread schedule changes. Returns the rays traced.
template <class Stored, class Trace>
std::uint64_t trace_photons_in_chunks(TileRunner& runner, std::size_t count, std::vector<std::vector<Stored>>& chunks,
                                      Trace&& trace) {
  chunks.resize((count + kPhotonChunk - 1) / kPhotonChunk);
  std::atomic<std::uint64_t> total{0};
  runner.run_ranges(chunks.size(), 1, [&](std::size_t begin, std::size_t end) {
    std::uint64_t rays = 0;
    for (std::size_t c = begin; c < end; ++c) {
      chunks[c].clear();
      const std::size_t last = std::min(count, (c + 1) * kPhotonChunk);
      for (std::size_t i = c * kPhotonChunk; i < last; ++i) trace(i, chunks[c], rays);
    }
    total.fetch_add(rays, std::memory_order_relaxed);
  });
  return total.load();
}

}  // namespace lancer
