#include "render/debug_integrators.h"

#include "render/sampler.h"
#include "render/surface.h"

namespace lancer {

glm::vec3 primid_color(std::uint32_t id) {
  const std::uint64_t h = mix64(static_cast<std::uint64_t>(id) + 0x5851F42D4C957F2Dull);
  auto channel = [h](int shift) { return 0.15f + 0.85f * static_cast<float>((h >> shift) & 0xFFu) / 255.0f; };
  return {channel(0), channel(8), channel(16)};
}

glm::vec3 debug_radiance(IntegratorKind kind, const Scene& scene, const Accelerator& accel, const Ray& ray,
                         std::uint64_t& rays) {
  ++rays;
  return debug_radiance_from_hit(kind, scene, ray, accel.intersect(ray));
}

glm::vec3 debug_radiance_from_hit(IntegratorKind kind, const Scene& scene, const Ray& ray, const Hit& hit) {
  if (!hit.valid()) return glm::vec3(0.0f);
  switch (kind) {
    case IntegratorKind::Normals:
      return make_surface_point(scene, ray, hit).stored_shading_normal() * 0.5f + glm::vec3(0.5f);
    case IntegratorKind::Depth:
      return glm::vec3(hit.t);
    case IntegratorKind::PrimId:
      return primid_color(hit.prim < scene.source_triangle_id.size() ? scene.source_triangle_id[hit.prim] : hit.prim);
    case IntegratorKind::Whitted:
      break;
  }
  return glm::vec3(0.0f);
}

}  // namespace lancer
