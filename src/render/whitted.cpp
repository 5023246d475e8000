#include "render/whitted.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "accel/ray_offset.h"
#include "render/drawn_triangle.h"
#include "render/bsdf_lobes.h"
#include "render/coverage.h"
#include "render/shading_inputs.h"
#include "render/fresnel.h"
#include "render/light_sampling.h"
#include "render/shadow_ray.h"
#include "render/surface_bsdf.h"

namespace lancer {

namespace {

constexpr float kInvPi = 0.31830988618379067f;

// Below this roughness a metal, or a clearcoat, is a mirror here; above it its glossy
// reflection is left out, as Whitted's model leaves out every glossy lobe.
constexpr float kMirrorRoughness = 0.2f;

bool is_mirror(const ShadingInputs& si) { return si.metallic >= 0.5f && si.roughness < kMirrorRoughness; }
bool has_mirror_coat(const ShadingInputs& si) { return si.clearcoat > 0.0f && si.clearcoat_roughness < kMirrorRoughness; }

// The rays leaving the shading point: origins pushed off its triangle just far enough that
// a ray cannot hit it again, for each ray's exact direction (ray_offset.h).
SurfaceOffset leaving(const Scene& scene, const ShadingInputs& si) {
  return leaving_offset(scene, si);
}


// The coat's normal: its own (normal-mapped) one, else the shading normal.
glm::vec3 coat_normal(const ShadingInputs& si) {
  return glm::dot(si.clearcoat_normal, si.clearcoat_normal) > 0.0f ? si.clearcoat_normal : si.ns;
}

}  // namespace

// What a lit point sends toward the viewer per unit radiance arriving from wi, f * cos(wi):
// the Lambertian base with weight `diffuse` (colour / pi, already scaled) and the sheen
// lobe (KHR_materials_sheen, the path tracer's SheenLobe) around the frame's normal, with the
// wedge handled as shading_inputs.h says: the normal bent and the wedge dropped (`bends`),
// or folded. 0 for a light below either plane.
struct WhittedIntegrator::DirectResponse {
  const ShadingInputs& si;
  glm::vec3 diffuse;
  SheenLobe sheen;
  ShadingFrame frame;  // around ns, or the bent normal
  glm::vec3 wo_local;
  bool bends;

  glm::vec3 lobes(const glm::vec3& wi) const {
    glm::vec3 f = diffuse * std::max(0.0f, glm::dot(frame.n, wi));
    if (sheen.exists()) f += sheen.eval(wo_local, frame.to_local(wi)).f;
    return f;
  }
  glm::vec3 operator()(const glm::vec3& wi) const {
    return evaluate_across_wedge<glm::vec3>(si, bends, frame.n, wi, [&](const glm::vec3& w) { return lobes(w); });
  }
};

WhittedIntegrator::WhittedIntegrator(const Scene& scene, const Accelerator& accel, const AreaLights& area_lights,
                                     int max_depth, int light_samples)
    : scene_(scene),
      accel_(accel),
      area_lights_(area_lights),
      max_depth_(max_depth),
      light_samples_(light_samples),
      has_coverage_(scene_has_coverage(scene)) {}

glm::vec3 WhittedIntegrator::trace(const Ray& ray, int depth, SobolSampler& sampler, std::uint64_t& rays) const {
  ++rays;
  return shade(ray, accel_.intersect(ray), depth, sampler, rays);
}

glm::vec3 WhittedIntegrator::shade(const Ray& ray, const Hit& hit, int depth, SobolSampler& sampler,
                                   std::uint64_t& rays) const {
  // Along the ray through partly covering surfaces, a loop (not a recursion: a stack of
  // cut-outs must not grow the call stack), each surface adding its share.
  glm::vec3 L(0.0f);
  float behind = 1.0f;  // the fraction of the ray not yet covered
  Ray r = ray;
  Hit h = hit;
  for (int crossed = 0; h.valid(); ++crossed) {  // no environment yet: a miss adds nothing
    const ShadingInputs si = evaluate_shading(scene_, r, h);
    if (!(si.alpha < 1.0f) || crossed + 1 >= kMaxCrossings)
      return L + behind * shade_surface(si, r, depth, sampler, rays);
    if (si.alpha > 0.0f) L += (behind * si.alpha) * shade_surface(si, r, depth, sampler, rays);
    behind *= 1.0f - si.alpha;
    r = continue_past(scene_, r, h);
    ++rays;
    h = accel_.intersect(r);
  }
  return L;
}

glm::vec3 WhittedIntegrator::shade_surface(const ShadingInputs& si, const Ray& ray, int depth, SobolSampler& sampler,
                                           std::uint64_t& rays) const {
  glm::vec3 L(0.0f);
  if (emits_toward(*si.material, si.front_face)) L += si.emission;
  if (si.unlit) return L + si.base_color;  // KHR_materials_unlit: shows its colour, scatters nothing
  // KHR_materials_clearcoat: a smooth coat is a mirror over the rest, reflecting its share
  // clearcoat * Fc(|n_c.V|) (the extension's fresnel_coat, ClearcoatLobe::layer_weight) and
  // passing the remainder down.
  float under_coat = 1.0f;
  if (has_mirror_coat(si)) {
    const glm::vec3 nc = coat_normal(si);
    const float coat =
        ClearcoatLobe(si.clearcoat, si.clearcoat_roughness).layer_weight(glm::vec3(0.0f, 0.0f, std::abs(glm::dot(nc, -ray.dir))));
    glm::vec3 dir = glm::normalize(glm::reflect(ray.dir, nc));
    if (depth < max_depth_ && fold_direction(si, dir))
      L += coat * trace(leaving_ray(scene_, si, dir), depth + 1, sampler, rays);
    under_coat = 1.0f - coat;
  }
  return under_coat > 0.0f ? L + under_coat * shade_base(si, ray, depth, sampler, rays) : L;
}

glm::vec3 WhittedIntegrator::shade_base(const ShadingInputs& si, const Ray& ray, int depth, SobolSampler& sampler,
                                        std::uint64_t& rays) const {
  // KHR_materials_sheen: the sheen lobe over the base, which it dims by 1 - max(sheenColor) E.
  // Mirrors are this model's delta lobes: without them the normal bends as the path tracer's
  // does without delta lobes (Whitted's mirrors start at roughness 0.2, the path tracer's
  // delta lobes below 0.032: between the two, Whitted folds where the path tracer bends).
  const bool bends = bends_normal(si, is_mirror(si) || has_mirror_coat(si));
  const ShadingFrame frame = ShadingFrame::from_normal(bends ? bent_shading_normal(si.ng, si.ns, -ray.dir) : si.ns);
  const DirectResponse response_template{
      si, glm::vec3(0.0f), SheenLobe(si.sheen_color, si.sheen_roughness), frame, frame.to_local(-ray.dir), bends};
  const float scale = response_template.sheen.base_scale(response_template.wo_local);
  glm::vec3 L(0.0f);
  float diffuse = 0.0f;
  if (is_mirror(si)) {
    if (depth < max_depth_) L += scale * mirror(si, ray, depth, sampler, rays);
  } else {
    const float transmission = std::clamp(si.transmission, 0.0f, 1.0f);
    if (transmission > 0.0f && depth < max_depth_) L += (scale * transmission) * dielectric(si, ray, depth, sampler, rays);
    diffuse = scale * (1.0f - transmission);
  }
  if (diffuse > 0.0f || response_template.sheen.exists()) {
    DirectResponse response = response_template;
    response.diffuse = si.base_color * (diffuse * kInvPi);
    L += direct_lighting(si, response, sampler, rays);
  }
  return L;
}

glm::vec3 WhittedIntegrator::mirror(const ShadingInputs& si, const Ray& ray, int depth, SobolSampler& sampler,
                                    std::uint64_t& rays) const {
  const glm::vec3 wo = -ray.dir;
  const float cos_i = glm::dot(wo, si.ns);  // > 0: evaluate_shading keeps ns facing the viewer
  glm::vec3 dir = glm::normalize(glm::reflect(ray.dir, si.ns));
  if (!fold_direction(si, dir)) return glm::vec3(0.0f);
  return schlick_fresnel(si.base_color, cos_i) * trace(leaving_ray(scene_, si, dir), depth + 1, sampler, rays);
}

glm::vec3 WhittedIntegrator::dielectric(const ShadingInputs& si, const Ray& ray, int depth, SobolSampler& sampler,
                                        std::uint64_t& rays) const {
  // A non-physical ior from a file (<= 0, NaN) is treated as 1: the surface only refracts.
  const float ior = std::isfinite(si.ior) && si.ior > 0.0f ? si.ior : 1.0f;
  // A thin wall (KHR_materials_volume thicknessFactor 0) has air on both sides: light meets
  // the index ior from either side and goes on unbent (KHR_materials_transmission,
  // "Refraction"). A volume boundary is entered through its front side.
  const bool thin = si.thin_walled;
  const float eta = thin || si.front_face ? ior : 1.0f / ior;  // n_t / n_i
  const glm::vec3 wo = -ray.dir;
  const glm::vec3& n = si.ns;
  const float cos_i = std::clamp(glm::dot(wo, n), 0.0f, 1.0f);
  const float F = exact_dielectric_fresnel(cos_i, eta);

  glm::vec3 L(0.0f);
  // Each direction folded where the two normals disagree on its side (shading_inputs.h).
  auto follow = [&](glm::vec3 dir) {
    return fold_direction(si, dir) ? trace(leaving_ray(scene_, si, dir), depth + 1, sampler, rays) : glm::vec3(0.0f);
  };
  L += F * follow(glm::normalize(glm::reflect(ray.dir, n)));
  if (F < 1.0f && thin) {
    L += (1.0f - F) * si.base_color * follow(glm::normalize(ray.dir));
  } else if (F < 1.0f) {
    const float inv_eta = 1.0f / eta;
    const float sin2_t = inv_eta * inv_eta * (1.0f - cos_i * cos_i);
    const float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin2_t));
    L += (1.0f - F) * si.base_color * follow(glm::normalize(inv_eta * ray.dir + (inv_eta * cos_i - cos_t) * n));
  }
  return L;
}

glm::vec3 WhittedIntegrator::direct_lighting(const ShadingInputs& si, const DirectResponse& response,
                                             SobolSampler& sampler, std::uint64_t& rays) const {
  const SurfaceOffset leave = leaving(scene_, si);
  return punctual_lighting(response, leave, rays) + area_lighting(response, leave, sampler, rays);
}

// Sum over punctual lights of irradiance * response, one shadow ray each.
glm::vec3 WhittedIntegrator::punctual_lighting(const DirectResponse& response, const SurfaceOffset& leave,
                                               std::uint64_t& rays) const {
  glm::vec3 L(0.0f);
  for (const PunctualLight& light : scene_.lights) {
    const PunctualIncidence in = illuminate(light, response.si.p);
    if (in.irradiance == glm::vec3(0.0f)) continue;
    const glm::vec3 f = response(in.wi);
    if (f == glm::vec3(0.0f)) continue;  // light below the surface
    const Ray shadow = shadow_ray_to_punctual(leave, light, in.wi);
    L += in.irradiance * f * shadow_visibility(scene_, accel_, shadow, has_coverage_, rays);
  }
  return L;
}

// Estimate of the light from the emissive triangles, sampled in area:
// L = 1/N sum L_e response(wi) cos_l / r^2 / pdf_area  (cos_l on the emitting side), L_e with
// the emissive texture (sample_area_light, the path tracer's light sample).
glm::vec3 WhittedIntegrator::area_lighting(const DirectResponse& response, const SurfaceOffset& leave,
                                           SobolSampler& sampler, std::uint64_t& rays) const {
  if (area_lights_.empty() || light_samples_ <= 0) return glm::vec3(0.0f);
  glm::vec3 sum(0.0f);
  for (int k = 0; k < light_samples_; ++k) {
    const float u_pick = sampler.next1();
    const LightSample ls = sample_area_light(scene_, area_lights_, response.si.p, u_pick, sampler.next2());
    if (!ls.valid) continue;
    const glm::vec3 f = response(ls.wi);
    if (f == glm::vec3(0.0f)) continue;
    const Ray shadow = shadow_ray_to_area_light(leave, ls.point.point, ls.point.normal);
    const float visible = shadow_visibility(scene_, accel_, shadow, has_coverage_, rays);
    if (visible > 0.0f) sum += ls.radiance * f * (visible / ls.pdf_solid_angle());
  }
  return sum / static_cast<float>(light_samples_);
}

}  // namespace lancer
