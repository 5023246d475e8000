// Triangles as they are drawn: a triangle stored in world space as it is, one drawn
// through an instance (Scene::instancing) moved to world space the way a flattened copy
// of the file would have been (gltf_primitives.cpp): corners by the instance's affine
// map, normals by the inverse transpose of its linear part, tangents by the linear part,
// with a mirroring instance (negative determinant) turning the front side over.
#pragma once

#include <cstdint>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include "accel/instances.h"
#include "accel/ray_offset.h"
#include "scene/scene.h"

namespace lancer {

// The transforms triangle hits through `instance` are drawn with at shutter time `time`
// (Ray::time): nothing for world-space triangles, a moving instance where it is then.
class DrawnInstance {
 public:
  DrawnInstance() = default;  // world space
  DrawnInstance(const Scene& scene, std::uint32_t instance, float time) {
    const Instance* inst = scene.instance_transform(instance);
    if (inst == nullptr) return;
    value_ = inst->motion == kNoHit ? *inst : instance_at(scene.instancing, *inst, time);
  }
  const Instance* get() const { return value_ ? &*value_ : nullptr; }

 private:
  std::optional<Instance> value_;  // none in world space (no identity transform written per hit)
};

inline TriangleCorners drawn_corners(const Scene& scene, std::uint32_t prim, const Instance* inst) {
  TriangleCorners c = triangle_corners(scene.triangles, prim);
  if (inst)
    for (glm::vec3& v : c) v = inst->to_world.point(v);
  return c;
}

// A normal of the triangle's space in world space, not normalised (L^-T n).
inline glm::vec3 normal_to_world(const Instance* inst, const glm::vec3& n) {
  return inst ? glm::transpose(inst->to_object.linear) * n : n;
}

// A tangent direction of the triangle's space in world space, not normalised (L t).
inline glm::vec3 vector_to_world(const Instance* inst, const glm::vec3& v) {
  return inst ? inst->to_world.vector(v) : v;
}

// Whether the instance mirrors: its triangles' front side is then the other one.
inline bool mirrors(const Instance* inst) { return inst && glm::determinant(inst->to_world.linear) < 0.0f; }

// cross(b - a, c - a) of the drawn triangle turned to its front side, not normalised.
inline glm::vec3 drawn_front_normal(const TriangleCorners& c, const Instance* inst) {
  const glm::vec3 n = glm::cross(c[1] - c[0], c[2] - c[0]);
  return mirrors(inst) ? -n : n;
}

// Where rays leave at shutter time `time` the point p (world space, geometric normal n) of
// triangle `prim` drawn through `instance`: the offset proven against the triangle as the
// accelerator traces it, and the time the rays made from it carry.
inline SurfaceOffset leaving_offset(const Scene& scene, const glm::vec3& p, const glm::vec3& n, std::uint32_t prim,
                                    std::uint32_t instance, float time) {
  const DrawnInstance drawn(scene, instance, time);
  return SurfaceOffset(p, n, triangle_corners(scene.triangles, prim), drawn.get(), time);
}

}  // namespace lancer
