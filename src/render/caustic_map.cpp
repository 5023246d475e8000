#include "render/caustic_map.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/common.hpp>
#include <glm/exponential.hpp>

#include "accel/ray_offset.h"
#include "render/bsdf.h"
#include "render/coverage.h"
#include "render/lights.h"
#include "render/shading_inputs.h"
#include "render/sobol_sampler.h"
#include "render/surface_bsdf.h"
#include "render/tile_scheduler.h"

namespace lancer {

namespace {

// As SppmIntegrator::trace_photon: roulette from the fourth bounce on, survival
// min(1, sqrt(throughput / power at the light)), at least 5 %.
constexpr int kRouletteDepth = 3;
constexpr float kMinSurvival = 0.05f;

// A photon's dimensions: where it leaves the light, then per surface met the same three uses.
constexpr std::uint32_t kEmitPickDimension = 0;
constexpr std::uint32_t kEmitPositionDimensions = 1;   // and 2
constexpr std::uint32_t kEmitDirectionDimensions = 3;  // and 4
constexpr std::uint32_t kEmitDimensions = 5;
constexpr std::uint32_t kSplitDimension = 0;
constexpr std::uint32_t kBsdfDimensions = 1;  // and 2
constexpr std::uint32_t kRouletteDimension = 3;
constexpr std::uint32_t kBounceDimensions = 4;
// Caustic photons are one sampler stream, told apart from pixels (y < 2^14) and from SPPM's
// photons (y = 0xFFFFFFFF) by their y: photon i is sample i of pixel (i >> 32, y).
constexpr std::uint32_t kCausticStreamY = 0xFFFFFFFEu;
// Photons traced by one task: each chunk keeps its own list, joined in chunk order.
constexpr std::size_t kPhotonChunk = 4096;

float max_component(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
bool is_black(const glm::vec3& v) { return v.x <= 0.0f && v.y <= 0.0f && v.z <= 0.0f; }
bool is_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// As path.cpp: Beer-Lambert inside a KHR_materials_volume boundary, never in a thin wall.
bool volume_absorption(const ShadingInputs& si, glm::vec3& sigma_a) {
  if (si.thin_walled || !(si.attenuation_distance > 0.0f) || !std::isfinite(si.attenuation_distance))
    return false;
  const glm::vec3 c = glm::max(si.attenuation_color, glm::vec3(1e-6f));
  sigma_a = -glm::log(c) / si.attenuation_distance;
  return true;
}

}  // namespace

CausticMap::CausticMap(const Scene& scene, const Accelerator& accel, const LightEmission& emission,
                       const Settings& settings, TileRunner& runner)
    : scene_(scene),
      accel_(accel),
      emission_(emission),
      settings_(settings),
      has_coverage_(scene_has_coverage(scene)),
      k_(std::max(2, settings.k)),
      max_radius_(settings.max_radius),
      inv_photons_(settings.photons > 0 ? 1.0f / static_cast<float>(settings.photons) : 0.0f) {
  if (emission_.empty() || settings.photons <= 0 || settings.max_depth < 2 || !(max_radius_ > 0.0f)) return;
  const auto count = static_cast<std::size_t>(settings.photons);
  const std::size_t chunks = (count + kPhotonChunk - 1) / kPhotonChunk;
  std::vector<std::vector<Stored>> chunk_photons(chunks);
  std::vector<std::uint64_t> chunk_rays(chunks, 0);
  runner.run_ranges(chunks, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const std::size_t last = std::min(count, (c + 1) * kPhotonChunk);
      for (std::size_t i = c * kPhotonChunk; i < last; ++i) trace_photon(i, chunk_photons[c], chunk_rays[c]);
    }
  });
  std::size_t stored = 0;
  for (std::size_t c = 0; c < chunks; ++c) stored += chunk_photons[c].size(), rays_ += chunk_rays[c];
  std::vector<glm::vec3> points;
  std::vector<CausticPhoton> in_order;
  points.reserve(stored);
  in_order.reserve(stored);
  for (std::vector<Stored>& chunk : chunk_photons) {
    for (const Stored& s : chunk) points.push_back(s.p), in_order.push_back(s.photon);
    std::vector<Stored>().swap(chunk);
  }
  if (points.empty()) return;
  tree_.build(points);
  std::vector<glm::vec3>().swap(points);  // the tree holds its own copy
  photons_.resize(tree_.size());
  for (std::uint32_t slot = 0; slot < tree_.size(); ++slot) photons_[slot] = in_order[tree_.slot_index(slot)];
  lower_ = upper_ = tree_.slot_point(0);
  for (std::uint32_t slot = 1; slot < tree_.size(); ++slot)
    lower_ = glm::min(lower_, tree_.slot_point(slot)), upper_ = glm::max(upper_, tree_.slot_point(slot));
  lower_ -= glm::vec3(max_radius_);
  upper_ += glm::vec3(max_radius_);
}

void CausticMap::trace_photon(std::uint64_t index, std::vector<Stored>& out, std::uint64_t& rays) const {
  if (emission_.empty()) return;
  SobolSampler sampler(static_cast<std::uint32_t>(index >> 32), kCausticStreamY, static_cast<std::uint32_t>(index),
                       settings_.seed);
  const EmittedPhoton emitted =
      emission_.sample(sampler.get1(kEmitPickDimension), sampler.get2(kEmitPositionDimensions),
                       sampler.get2(kEmitDirectionDimensions));
  sampler.skip(kEmitDimensions);
  if (!emitted.valid) return;
  const float start_power = max_component(emitted.power);
  if (!(start_power > 0.0f) || !std::isfinite(start_power)) return;
  glm::vec3 beta = emitted.power * inv_photons_;
  const float start_beta = max_component(beta);
  Ray ray = emitted.ray;
  int bounces = 0, crossings = 0;
  float from_light = 0.0f;  // distance travelled before the first scattering (the range window)
  bool in_volume = false;
  glm::vec3 sigma_a(0.0f);
  for (;;) {
    ++rays;
    const Hit hit = accel_.intersect(ray);
    if (!hit.valid()) return;
    const float dir_length = glm::length(ray.dir);
    const glm::vec3 dir = ray.dir / dir_length;
    const float segment = hit.t * dir_length;
    if (in_volume) beta *= glm::exp(-sigma_a * segment);
    const ShadingInputs si = evaluate_shading(scene_, ray, hit);
    const std::uint32_t dims = sampler.dimension();
    sampler.skip(kBounceDimensions);
    float u_roulette = -1.0f;
    if (si.alpha < 1.0f && crossings < kMaxCrossings) {  // coverage: as the path tracer
      bool through = !(si.alpha > 0.0f);
      if (!through) {
        const float u = sampler.get1(dims + kRouletteDimension);
        through = u >= si.alpha;
        u_roulette = std::min(u / si.alpha, 0x1.fffffep-1f);
      }
      if (through) {
        if (bounces == 0) from_light += segment;
        ++crossings;
        ray = continue_past(scene_, ray, hit);
        continue;
      }
    }
    if (bounces == 0 && emitted.range > 0.0f) {
      beta *= range_window(from_light + segment, emitted.range);
      if (is_black(beta)) return;
    }
    if (si.unlit) return;  // shows its colour, scatters nothing
    const glm::vec3 wo = -dir;  // back towards the light
    const SurfaceScattering sc(si, wo);
    const bool delta_only = sc.bsdf.is_delta_only();
    // A caustic photon: light that reached a non-delta surface through delta bounces only.
    if (!delta_only && bounces > 0) out.push_back({si.p, {wo, beta, si.ng, static_cast<std::uint32_t>(bounces)}});
    // The camera vertex that gathers it is one more scattering event.
    if (bounces + 2 > settings_.max_depth) return;
    if (!delta_only && sc.bsdf.delta_probability(sc.out) <= 0.0f) return;
    const float u_split = sc.bsdf.reads_split() ? sampler.get1(dims + kSplitDimension) : 0.0f;
    const std::optional<BsdfSample> bs = sc.sample(u_split, sampler.get2(dims + kBsdfDimensions));
    // Only delta bounces: a photon scattered by a non-delta lobe is no longer caustic light
    // (the path tracer finds the rest).
    if (!bs || !bs->delta) return;
    // Veach's adjoint with shading normals (1997, eq. 5.17), as SppmIntegrator::trace_photon.
    const float wo_ng = std::abs(glm::dot(wo, si.ng)), wi_ns = std::abs(glm::dot(bs->wi, si.ns));
    if (!(wo_ng > 0.0f) || !(wi_ns > 0.0f)) return;
    const float correction = std::abs(glm::dot(wo, si.ns)) * std::abs(glm::dot(bs->wi, si.ng)) / (wo_ng * wi_ns);
    beta *= bs->weight * correction;
    if (is_black(beta) || !is_finite(beta)) return;
    if (bs->transmitted && !si.thin_walled) in_volume = si.front_face && volume_absorption(si, sigma_a);
    crossings = 0;
    if (++bounces >= kRouletteDepth) {
      const float survive = std::max(kMinSurvival, std::min(1.0f, std::sqrt(max_component(beta) / start_beta)));
      if ((u_roulette >= 0.0f ? u_roulette : sampler.get1(dims + kRouletteDimension)) >= survive) return;
      beta /= survive;
    }
    Ray next;
    next.org = SurfaceOffset(si.p, si.ng, triangle_corners(scene_.triangles, si.prim)).origin(bs->wi);
    next.dir = bs->wi;
    ray = next;
  }
}

}  // namespace lancer
