#include "render/caustic_map.h"

#include <algorithm>

#include <glm/common.hpp>

#include "render/photon_walk.h"
#include "render/tile_scheduler.h"

namespace lancer {

namespace {

// Caustic photons are one sampler stream, told apart from pixels (y < 2^14) and from SPPM's
// photons (y = 0xFFFFFFFF) by their y: photon i is sample i of pixel (i >> 32, y).
constexpr std::uint32_t kCausticStreamY = 0xFFFFFFFEu;

}  // namespace

CausticMap::CausticMap(const Scene& scene, const Accelerator& accel, const LightEmission& emission,
                       const Settings& settings, TileRunner& runner)
    : scene_(scene),
      accel_(accel),
      emission_(emission),
      settings_(settings),
      k_(std::max(2, settings.k)),
      max_radius_(settings.max_radius),
      inv_photons_(settings.photons > 0 ? 1.0f / static_cast<float>(settings.photons) : 0.0f) {
  if (emission_.empty() || settings.photons <= 0 || settings.max_depth < 2 || !(max_radius_ > 0.0f)) return;
  const auto count = static_cast<std::size_t>(settings.photons);
  std::vector<std::vector<Stored>> chunk_photons;
  rays_ = trace_photons_in_chunks(runner, count, chunk_photons,
                                  [&](std::size_t i, std::vector<Stored>& out, std::uint64_t& rays) {
                                    trace_photon(i, out, rays);
                                  });
  std::size_t stored = 0;
  for (const std::vector<Stored>& chunk : chunk_photons) stored += chunk.size();
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
  walk_photon(scene_, accel_, emission_, index, kCausticStreamY, settings_.seed, inv_photons_, rays,
              [&](const PhotonVertex& v) {
                const bool delta_only = v.sc.bsdf.is_delta_only();
                // A caustic photon: light that reached a non-delta surface through delta bounces only.
                if (!delta_only && v.bounces > 0)
                  out.push_back({v.si.p, {v.wo, v.power, v.si.ng, static_cast<std::uint32_t>(v.bounces)}});
                // The camera vertex that gathers it is one more scattering event; and a photon
                // scattered by a non-delta lobe is no longer caustic light (the path tracer finds
                // the rest).
                if (v.bounces + 2 > settings_.max_depth) return PhotonGoes::Stop;
                if (!delta_only && v.sc.bsdf.delta_probability(v.sc.out) <= 0.0f) return PhotonGoes::Stop;
                return PhotonGoes::DeltaOnly;
              });
}

}  // namespace lancer
