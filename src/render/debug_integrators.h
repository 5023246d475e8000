// Debug views of the primary hit; black (zero) where the camera ray hits nothing.
//  normals: the stored shading normal (as in the file, not flipped towards the camera)
//           mapped to colour as n * 0.5 + 0.5;
//  depth:   t of the hit along the unit-length camera ray, i.e. the distance from the
//           camera in scene units, written linearly to all three channels;
//  primid:  a colour hashed from the triangle's position in the source file
//           (scene.source_triangle_id), so the same triangle keeps its colour whatever
//           the reader drops or the accelerator reorders.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "render/render_settings.h"
#include "render/sobol_sampler.h"
#include "scene/scene.h"

namespace lancer {

// A colour with channels in [0.15, 1] from a hash of `id`.
glm::vec3 primid_color(std::uint32_t id);

// albedo:  the base colour at the hit (factor times texture, linear);
// ao:      ambient occlusion, the fraction of kAoRays cosine-distributed rays from the hit
//          (about the geometric normal, on the ray's side) that travel kAoRadius times the
//          scene's bounding-box diagonal without hitting anything, as grey.
inline constexpr int kAoRays = 16;
inline constexpr float kAoRadius = 0.1f;

// `kind` must be Normals, Albedo, Depth or PrimId. `ray.dir` must be unit length. Counts one ray.
glm::vec3 debug_radiance(IntegratorKind kind, const Scene& scene, const Accelerator& accel, const Ray& ray,
                         std::uint64_t& rays);
// debug_radiance() for a ray the caller has already traced: `hit` must be
// accel.intersect(ray). Traces nothing, so there is no ray count to add to.
glm::vec3 debug_radiance_from_hit(IntegratorKind kind, const Scene& scene, const Ray& ray, const Hit& hit);

// The ao view at a camera ray's hit; `rays` counts the occlusion rays traced. With
// `has_coverage` (scene_has_coverage, render/coverage.h) the probes see through surfaces
// as far as their coverage lets them.
glm::vec3 ambient_occlusion(const Scene& scene, const Accelerator& accel, const Ray& ray, const Hit& hit,
                            bool has_coverage, SobolSampler& sampler, std::uint64_t& rays);

}  // namespace lancer
