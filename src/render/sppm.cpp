#include "render/sppm.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "accel/ray_offset.h"
#include "render/bsdf.h"
#include "render/coverage.h"
#include "render/drawn_triangle.h"
#include "render/path_rules.h"
#include "render/photon_walk.h"
#include "render/shading_inputs.h"
#include "render/shadow_ray.h"
#include "render/surface_bsdf.h"

namespace lancer {

namespace {

// Photon streams are told apart from pixel streams by a y no image has.
constexpr std::uint32_t kPhotonStreamY = 0xFFFFFFFFu;

}  // namespace

using namespace path_rules;

SppmIntegrator::SppmIntegrator(const Scene& scene, const Accelerator& accel, const AreaLights& area_lights,
                               const LightEmission& emission, const Environment* environment, int max_depth,
                               int light_samples)
    : scene_(scene),
      accel_(accel),
      area_lights_(area_lights),
      emission_(emission),
      environment_(environment),
      max_depth_(max_depth),
      light_samples_(std::max(1, light_samples)),
      has_coverage_(scene_has_coverage(scene)) {}

SppmIntegrator::CameraPath SppmIntegrator::camera_path(const Ray& camera_ray, const Hit& camera_hit,
                                                       SobolSampler& sampler, std::uint64_t& rays,
                                                       bool emission_apart) const {
  CameraPath result;
  glm::vec3& L = result.L;
  glm::vec3 beta(1.0f);
  Ray ray = camera_ray;
  Hit hit = camera_hit;
  int bounces = 0, crossings = 0;
  float travelled = 0.0f;  // from the last scattering point, through surfaces passed
  float distance = 0.0f;   // from the camera, for the visible point's footprint
  float prev_pdf = 0.0f;
  bool prev_delta = true;
  bool in_volume = false;
  glm::vec3 sigma_a(0.0f);
  for (;;) {
    const float dir_length = glm::length(ray.dir);
    const glm::vec3 dir = ray.dir / dir_length;
    if (!hit.valid()) {
      if (environment_) {
        const float w = prev_delta ? 1.0f : power_heuristic(prev_pdf, environment_->pdf(dir));
        L += beta * environment_->radiance(dir) * w;
      }
      break;
    }
    const float segment = hit.t * dir_length;
    if (in_volume) beta *= glm::exp(-sigma_a * segment);
    const ShadingInputs si = evaluate_shading(scene_, ray, hit);
    // As path.cpp: only the first surface's emission may be estimated apart.
    const bool first_surface = emission_apart;
    emission_apart = false;
    const std::uint32_t dims = sampler.dimension();
    sampler.skip(bounce_dimensions(light_samples_));

    BounceChance chance(sampler, dims + kRouletteDimension);
    if (si.alpha < 1.0f && crossings < kMaxCrossings && chance.passes(si.alpha)) {  // coverage: as path.cpp
      travelled += segment;
      distance += segment;
      ++crossings;
      ray = continue_past(scene_, ray, hit);
      ++rays;
      hit = accel_.intersect(ray);
      continue;
    }
    distance += segment;

    const bool seen_apart = first_surface && si.alpha >= 1.0f;
    if (emits_toward(*si.material, si.front_face) && !is_black(si.emission) && !seen_apart) {
      float w = 1.0f;
      if (!prev_delta) {
        const float pdf_area = area_lights_.pdf_area(hit.prim, hit.instance);
        const float cos_l = std::abs(glm::dot(si.ng, dir));
        const float d = travelled + segment;
        if (pdf_area > 0.0f && cos_l > 0.0f) w = power_heuristic(prev_pdf, light_samples_ * (pdf_area * d * d / cos_l));
      }
      L += beta * si.emission * w;
    }
    if (si.unlit) {
      L += beta * si.base_color;
      break;
    }
    // Light from further bounces needs one more: none at the last.
    if (bounces >= max_depth_) break;

    const SurfaceScattering sc(si, -dir);
    const bool non_delta = !sc.bsdf.is_delta_only();
    // A visible point on a diffuse surface, or on a glossy one where the path may bounce
    // only once more (the photons bring the rest).
    const bool visible_point = non_delta && (sc.bsdf.has_diffuse() || bounces + 1 >= max_depth_);
    if (non_delta) {
      // Next-event estimation: MIS with the BSDF sample where the path goes on by sampling
      // the non-delta lobes, in full at a visible point (its BSDF is not sampled; the
      // photons bring only light that has bounced).
      const SurfaceOffset leave = leaving_offset(scene_, si);
      next_event_estimation(scene_, area_lights_, environment_, light_samples_, si.p, sampler, dims, beta,
                            !visible_point, [&](const glm::vec3& wi) { return sc.evaluate(wi); },
                            [&](const ShadowAim& aim, const glm::vec3& contribution) {
                              const Ray shadow = shadow_ray(aim, shadow_origin(leave, aim), leave.time());
                              L += contribution * shadow_visibility(scene_, accel_, shadow, has_coverage_, rays);
                            });
    }

    const float u_split = sc.bsdf.reads_split() ? sampler.get1(dims + kSplitDimension) : 0.0f;
    const glm::vec2 u_bsdf = sampler.get2(dims + kBsdfDimensions);
    std::optional<BsdfSample> bs;
    if (visible_point) {
      // The non-delta lobes are the visible point's; a delta lobe of the same BSDF (a smooth
      // coat over a diffuse base) goes on with the probability sample() picks it, the visible
      // point taking the rest. The choice is sample()'s own, so that a delta lobe picked whose
      // direction does not exist (a coat direction below a normal-mapped base) ends the path
      // as it ends the path tracer's.
      const float p_delta = sc.bsdf.delta_probability(sc.out);
      if (!(p_delta > 0.0f && sc.bsdf.picks_delta(sc.out, u_split, u_bsdf))) {
        if (p_delta < 1.0f) {
          result.vp = {ray, hit, beta / (1.0f - p_delta), distance, bounces, true};
          if (!is_finite(result.vp.beta)) result.vp.valid = false;
        }
        break;
      }
      bs = sc.sample(u_split, u_bsdf);
      if (!bs || !bs->delta) break;
    } else {
      bs = sc.sample(u_split, u_bsdf);
      if (!bs) break;
    }
    beta *= bs->weight;
    if (is_black(beta) || !is_finite(beta)) break;
    prev_pdf = bs->pdf;
    prev_delta = bs->delta;
    if (bs->transmitted && !si.thin_walled) in_volume = si.front_face && volume_absorption(si, sigma_a);
    travelled = 0.0f;
    crossings = 0;
    if (!survives_roulette(++bounces, bs->delta, max_component(beta), chance, beta)) break;
    ray = leaving_ray(scene_, si, bs->wi);
    ++rays;
    hit = accel_.intersect(ray);
  }
  if (!is_finite(L)) L = glm::vec3(0.0f);
  return result;
}

void SppmIntegrator::trace_photon(std::uint64_t index, std::uint64_t seed, std::vector<Photon>& out,
                                  std::uint64_t& rays) const {
  if (emission_.empty()) return;  // no light: every photon shot carries nothing
  walk_photon(scene_, accel_, emission_, index, kPhotonStreamY, seed, 1.0f, rays, [&](const PhotonVertex& v) {
    // Light that has bounced at least once: direct light is next-event estimation's.
    if (v.bounces > 0 && v.sc.bsdf.has_diffuse())
      out.push_back({v.si.p, v.wo, v.power, static_cast<std::uint32_t>(v.bounces)});
    // A photon is useful only to a visible point at least one scattering event before it.
    return v.bounces + 1 >= max_depth_ ? PhotonGoes::Stop : PhotonGoes::AnyLobe;
  });
}

SppmIntegrator::Gathered SppmIntegrator::gather(const VisiblePoint& vp, const PhotonGrid& grid, float radius) const {
  Gathered g;
  if (!vp.valid) return g;
  const ShadingInputs si = evaluate_shading(scene_, vp.ray, vp.hit);
  const SurfaceScattering sc(si, -glm::normalize(vp.ray.dir));
  // Photons whose path, with the camera path's, scatters at most max_depth times.
  const auto most_bounces = static_cast<std::uint32_t>(std::max(0, max_depth_ - vp.bounces - 1));
  grid.for_each_within(si.p, radius, [&](const Photon& ph) {
    if (ph.bounces > most_bounces) return;
    ++g.count;
    // Flux per unit of the true surface's area: f |wi.n| (what evaluate gives, n the BSDF's
    // normal) / |wi.ng|.
    const float cos_g = std::abs(glm::dot(ph.wi, si.ng));
    if (!(cos_g > 0.0f)) return;
    const glm::vec3 f = sc.evaluate(ph.wi).f;
    if (!is_black(f)) g.phi += ph.power * f / cos_g;
  });
  return g;
}

}  // namespace lancer
