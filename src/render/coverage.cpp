#include "render/coverage.h"

#include <cmath>
#include <cstddef>
#include <vector>

#include "accel/ray_offset.h"
#include "render/drawn_triangle.h"
#include "render/shading_inputs.h"
#include "render/surface.h"

namespace lancer {

bool scene_has_coverage(const Scene& scene) {
  std::vector<bool> partial(scene.materials.size());
  for (std::size_t i = 0; i < partial.size(); ++i)
    partial[i] = scene.materials[i].alpha_mode != AlphaMode::Opaque || culls_back_faces(scene.materials[i]);
  // Only the materials some triangle uses: a file's unused single-sided material costs nothing.
  for (const std::uint32_t id : scene.material_id)
    if (id < partial.size() && partial[id]) return true;
  return false;
}

Ray continue_past(const Scene& scene, const Ray& ray, const Hit& hit) {
  const SurfacePoint sp = make_surface_point(scene, ray, hit);
  Ray next = ray;
  next.org = leaving_offset(scene, sp.p, sp.ng, hit.prim, hit.instance, ray.time).origin(ray.dir);
  // The new origin lies within a few ulps of the hit point, so the old end point is
  // reached after what remained of the old ray (the shadow rays' end points are shortened
  // by far more than that, kShadowShorten).
  if (std::isfinite(ray.tfar)) next.tfar = ray.tfar - hit.t;
  return next;
}

void skip_uncovered(const Scene& scene, const Accelerator& accel, const Ray& ray, Hit& hit, std::uint64_t& rays) {
  Ray past = ray;
  Hit next = hit;
  float before = 0.0f;  // t along `ray` of past's origin (give or take the few-ulp offset)
  for (int k = 0; k < kMaxCrossings && next.valid() && surface_coverage(scene, past, next) <= 0.0f; ++k) {
    before += next.t;
    past = continue_past(scene, past, next);
    ++rays;
    next = accel.intersect(past);
  }
  if (next.valid()) next.t += before;
  hit = next;
}

float shadow_transmittance(const Scene& scene, const Accelerator& accel, const Ray& shadow, bool occluded,
                           std::uint64_t& rays) {
  if (!occluded) return 1.0f;
  Ray ray = shadow;
  float through = 1.0f;
  for (int k = 0; k < kMaxCrossings; ++k) {
    ++rays;
    const Hit hit = accel.intersect(ray);
    if (!hit.valid()) return through;
    through *= 1.0f - surface_coverage(scene, ray, hit);
    if (!(through > 0.0f)) return 0.0f;
    ray = continue_past(scene, ray, hit);
  }
  return 0.0f;
}

float shadow_visibility(const Scene& scene, const Accelerator& accel, const Ray& shadow, bool has_coverage,
                        std::uint64_t& rays) {
  ++rays;
  const bool occluded = accel.occluded(shadow);
  return has_coverage ? shadow_transmittance(scene, accel, shadow, occluded, rays) : (occluded ? 0.0f : 1.0f);
}

}  // namespace lancer
