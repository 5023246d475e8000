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
  s.radiance = s.point.radiance;
  const Material& m = scene.materials[scene.material_id[s.point.prim]];
  if (m.emissive_texture.present() || m.alpha_mode != AlphaMode::Opaque) {
    // The texture at the point: shade the light's triangle as a ray from p would see it. A
    // surface that covers only the fraction alpha of the point emits alpha times as much
    // (render/coverage.h).
    Ray toward;
    toward.org = p;
    toward.dir = s.wi;
    const ShadingInputs si = evaluate_shading(scene, toward, Hit{std::sqrt(s.dist2), s.point.prim, s.point.b1, s.point.b2});
    s.radiance = si.emission * si.alpha;
  }
  return s;
}

}  // namespace lancer
