#include "render/light_sampling.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "render/shading_inputs.h"

namespace lancer {

namespace {
// Closer than this (squared distance), a light sample's 1/r^2 is not evaluated.
constexpr float kMinLightDistance2 = 1e-20f;
}  // namespace

LightSample sample_area_light(const Scene& scene, const AreaLights& lights, const glm::vec3& p, float u_pick,
                              glm::vec2 u) {
  LightSample s;
  s.point = lights.sample(u_pick, u.x, u.y);
  const glm::vec3 d = s.point.point - p;
  s.dist2 = glm::dot(d, d);
  if (!(s.dist2 > kMinLightDistance2 && s.point.pdf_area > 0.0f)) return s;
  s.wi = d / std::sqrt(s.dist2);
  s.cos_l = -glm::dot(s.point.normal, s.wi);
  if (s.point.two_sided && s.cos_l < 0.0f) {  // p sees the back side, which emits too
    s.point.normal = -s.point.normal;
    s.cos_l = -s.cos_l;
  }
  if (!(s.cos_l > 0.0f)) return s;
  s.valid = true;
  s.radiance = area_light_radiance(scene, s.point, -s.wi);
  return s;
}

glm::vec3 area_light_radiance(const Scene& scene, const AreaLightSample& s, const glm::vec3& w) {
  const Material& m = scene.materials[scene.material_id[s.prim]];
  if (!m.emissive_texture.present() && m.alpha_mode == AlphaMode::Opaque) return s.radiance;
  // The texture at the point: shade the light's triangle as a ray arriving along -w would see
  // it (only the ray's direction and the hit's barycentrics matter). A surface that covers
  // only the fraction alpha of the point emits alpha times as much (render/coverage.h).
  Ray toward;
  toward.org = s.point + w;
  toward.dir = -w;
  const ShadingInputs si = evaluate_shading(scene, toward, Hit{1.0f, s.prim, s.b1, s.b2, s.instance});
  return si.emission * si.alpha;
}

}  // namespace lancer
