#include "render/whitted.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "accel/ray_offset.h"
#include "render/shading_inputs.h"
#include "render/shadow_ray.h"

namespace lancer {

namespace {

constexpr float kInvPi = 0.31830988618379067f;
// Closer than this (squared distance), a light sample's 1/r^2 is not evaluated.
constexpr float kMinLightDistance2 = 1e-20f;

bool is_mirror(const Material& m) { return m.metallic >= 0.5f && m.roughness < 0.2f; }

// The rays leaving surface point sp: origins pushed off its triangle just far enough that
// a ray cannot hit it again, for each ray's exact direction (ray_offset.h).
SurfaceOffset leaving(const Scene& scene, const SurfacePoint& sp) {
  return SurfaceOffset(sp.p, sp.ng, triangle_corners(scene.triangles, sp.prim));
}

// A secondary ray from `sp` along unit `dir`.
Ray spawn_ray(const Scene& scene, const SurfacePoint& sp, const glm::vec3& dir) {
  Ray r;
  r.org = leaving(scene, sp).origin(dir);
  r.dir = dir;
  return r;
}

// The normal used for specular directions: the shading normal unless interpolation made
// it face away from the incoming ray, then the geometric one.
glm::vec3 specular_normal(const SurfacePoint& sp, const glm::vec3& wo) {
  return glm::dot(wo, sp.ns) > 0.0f ? sp.ns : sp.ng;
}

}  // namespace

float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  if (cos_i == 0.0f) return 1.0f;
  // Snell: sin_t = sin_i / eta.
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

glm::vec3 fresnel_schlick(const glm::vec3& f0, float cos_i) {
  const float m = 1.0f - std::clamp(cos_i, 0.0f, 1.0f);
  const float m5 = (m * m) * (m * m) * m;
  return f0 + (glm::vec3(1.0f) - f0) * m5;
}

WhittedIntegrator::WhittedIntegrator(const Scene& scene, const Accelerator& accel, const AreaLights& area_lights,
                                     int max_depth, int light_samples)
    : scene_(scene), accel_(accel), area_lights_(area_lights), max_depth_(max_depth), light_samples_(light_samples) {}

glm::vec3 WhittedIntegrator::trace(const Ray& ray, int depth, SobolSampler& sampler, std::uint64_t& rays) const {
  ++rays;
  return shade(ray, accel_.intersect(ray), depth, sampler, rays);
}

glm::vec3 WhittedIntegrator::shade(const Ray& ray, const Hit& hit, int depth, SobolSampler& sampler,
                                   std::uint64_t& rays) const {
  if (!hit.valid()) return glm::vec3(0.0f);  // no environment yet
  const SurfacePoint sp = make_surface_point(scene_, ray, hit);
  const Material& m = *sp.material;

  glm::vec3 L(0.0f);
  if (sp.front_face) L += m.emission();
  if (is_mirror(m)) {
    if (depth < max_depth_) L += mirror(sp, ray, depth, sampler, rays);
    return L;
  }
  const float transmission = std::clamp(m.transmission, 0.0f, 1.0f);
  if (transmission > 0.0f && depth < max_depth_) L += transmission * dielectric(sp, ray, depth, sampler, rays);
  if (transmission < 1.0f) L += (1.0f - transmission) * direct_lighting(sp, sampler, rays);
  return L;
}

glm::vec3 WhittedIntegrator::mirror(const SurfacePoint& sp, const Ray& ray, int depth, SobolSampler& sampler,
                                    std::uint64_t& rays) const {
  const glm::vec3 wo = -ray.dir;
  const glm::vec3 n = specular_normal(sp, wo);
  const float cos_i = glm::dot(wo, n);
  const glm::vec3 dir = glm::normalize(glm::reflect(ray.dir, n));
  return fresnel_schlick(sp.base_color, cos_i) * trace(spawn_ray(scene_, sp, dir), depth + 1, sampler, rays);
}

glm::vec3 WhittedIntegrator::dielectric(const SurfacePoint& sp, const Ray& ray, int depth, SobolSampler& sampler,
                                        std::uint64_t& rays) const {
  // A non-physical ior from a file (<= 0, NaN) is treated as 1: the surface only refracts.
  const float ior = std::isfinite(sp.material->ior) && sp.material->ior > 0.0f ? sp.material->ior : 1.0f;
  // A thin wall (KHR_materials_volume thicknessFactor 0) has air on both sides: light meets
  // the index ior from either side and goes on unbent (KHR_materials_transmission,
  // "Refraction"). A volume boundary is entered through its front side.
  const bool thin = is_thin_walled(*sp.material);
  const float eta = thin || sp.front_face ? ior : 1.0f / ior;  // n_t / n_i
  const glm::vec3 wo = -ray.dir;
  const glm::vec3 n = specular_normal(sp, wo);
  const float cos_i = std::clamp(glm::dot(wo, n), 0.0f, 1.0f);
  const float F = fresnel_dielectric(cos_i, eta);

  glm::vec3 L(0.0f);
  const glm::vec3 refl = glm::normalize(glm::reflect(ray.dir, n));
  L += F * trace(spawn_ray(scene_, sp, refl), depth + 1, sampler, rays);
  if (F < 1.0f && thin) {
    const glm::vec3 straight = glm::normalize(ray.dir);
    L += (1.0f - F) * sp.base_color * trace(spawn_ray(scene_, sp, straight), depth + 1, sampler, rays);
  } else if (F < 1.0f) {
    const float inv_eta = 1.0f / eta;
    const float sin2_t = inv_eta * inv_eta * (1.0f - cos_i * cos_i);
    const float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin2_t));
    const glm::vec3 refr = glm::normalize(inv_eta * ray.dir + (inv_eta * cos_i - cos_t) * n);
    L += (1.0f - F) * sp.base_color * trace(spawn_ray(scene_, sp, refr), depth + 1, sampler, rays);
  }
  return L;
}

glm::vec3 WhittedIntegrator::direct_lighting(const SurfacePoint& sp, SobolSampler& sampler,
                                             std::uint64_t& rays) const {
  const SurfaceOffset leave = leaving(scene_, sp);
  const glm::vec3 E = punctual_lighting(sp, leave, rays) + area_lighting(sp, leave, sampler, rays);
  return sp.base_color * kInvPi * E;
}

// Sum over punctual lights of irradiance * cos(theta), one shadow ray each.
glm::vec3 WhittedIntegrator::punctual_lighting(const SurfacePoint& sp, const SurfaceOffset& leave,
                                               std::uint64_t& rays) const {
  glm::vec3 E(0.0f);
  for (const PunctualLight& light : scene_.lights) {
    const PunctualIncidence in = illuminate(light, sp.p);
    if (in.irradiance == glm::vec3(0.0f)) continue;
    const float cos_g = glm::dot(sp.ng, in.wi);
    const float cos_s = glm::dot(sp.ns, in.wi);
    if (cos_g <= 0.0f || cos_s <= 0.0f) continue;  // light below the surface
    const Ray shadow = shadow_ray_to_punctual(leave, light, in.wi);
    ++rays;
    if (!accel_.occluded(shadow)) E += in.irradiance * cos_s;
  }
  return E;
}

// Estimate of the irradiance from the emissive triangles, sampled in area:
// E = 1/N sum L_e cos_s cos_l / r^2 / pdf_area  (one-sided emitters).
glm::vec3 WhittedIntegrator::area_lighting(const SurfacePoint& sp, const SurfaceOffset& leave, SobolSampler& sampler,
                                           std::uint64_t& rays) const {
  if (area_lights_.empty() || light_samples_ <= 0) return glm::vec3(0.0f);
  glm::vec3 sum(0.0f);
  for (int k = 0; k < light_samples_; ++k) {
    const float u_pick = sampler.next1();
    const glm::vec2 u = sampler.next2();
    const AreaLightSample ls = area_lights_.sample(u_pick, u.x, u.y);
    const glm::vec3 d = ls.point - sp.p;
    const float dist2 = glm::dot(d, d);
    if (!(dist2 > kMinLightDistance2) || !(ls.pdf_area > 0.0f)) continue;
    const glm::vec3 wi = d / std::sqrt(dist2);
    const float cos_g = glm::dot(sp.ng, wi);
    const float cos_s = glm::dot(sp.ns, wi);
    const float cos_l = -glm::dot(ls.normal, wi);
    if (cos_g <= 0.0f || cos_s <= 0.0f || cos_l <= 0.0f) continue;
    const Ray shadow = shadow_ray_to_area_light(leave, ls.point, ls.normal);
    ++rays;
    if (accel_.occluded(shadow)) continue;
    sum += ls.radiance * (cos_s * cos_l / (dist2 * ls.pdf_area));
  }
  return sum / static_cast<float>(light_samples_);
}

}  // namespace lancer
