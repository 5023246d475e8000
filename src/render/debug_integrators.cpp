#include "render/debug_integrators.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "accel/ray_offset.h"
#include "render/bsdf.h"
#include "render/coverage.h"
#include "render/sobol_sampler.h"
#include "render/shading_inputs.h"
#include "render/surface.h"
#include "render/turn.h"
#include "simd/splitmix64.h"

namespace lancer {

glm::vec3 primid_color(std::uint32_t id) {
  const std::uint64_t h = splitmix64_mix(static_cast<std::uint64_t>(id) + 0x5851F42D4C957F2Dull);
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
    case IntegratorKind::Albedo:
      return evaluate_shading(scene, ray, hit).base_color;
    case IntegratorKind::Depth:
      return glm::vec3(hit.t);
    case IntegratorKind::PrimId:
      return primid_color(scene.source_id(hit.prim, hit.instance));
    case IntegratorKind::Path:
    case IntegratorKind::Whitted:
    case IntegratorKind::Sppm:
    case IntegratorKind::Photon:
    case IntegratorKind::Ao:
      break;
  }
  return glm::vec3(0.0f);
}

glm::vec3 ambient_occlusion(const Scene& scene, const Accelerator& accel, const Ray& ray, const Hit& hit,
                            bool has_coverage, SobolSampler& sampler, std::uint64_t& rays) {
  if (!hit.valid()) return glm::vec3(0.0f);
  const ShadingInputs si = evaluate_shading(scene, ray, hit);
  const glm::vec3 e = scene.bounds().extent();
  const float reach = kAoRadius * std::sqrt(glm::dot(e, e));
  const ShadingFrame frame = ShadingFrame::from_normal(si.ng);
  const glm::vec3 origin = offset_ray_origin(si.p, si.ng);
  float open = 0.0f;
  for (int k = 0; k < kAoRays; ++k) {
    // Cosine-weighted (Malley's method: uniform on the disk, lifted to the hemisphere).
    const glm::vec2 u = sampler.next2();
    const float r = std::sqrt(u.x);
    const glm::vec2 cs = turn_cos_sin(u.y);
    const glm::vec3 local(r * cs.x, r * cs.y, std::sqrt(std::max(0.0f, 1.0f - r * r)));
    Ray probe;
    probe.org = origin;
    probe.dir = frame.to_world(local);
    probe.tfar = reach;
    probe.time = si.time;
    open += shadow_visibility(scene, accel, probe, has_coverage, rays);
  }
  return glm::vec3(open / kAoRays);
}

}  // namespace lancer
