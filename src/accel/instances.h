// Meshes stored once and drawn many times: the input of the two-level accelerator.
// A mesh is a range of the scene's TriangleSoA, in its own (object) space; an instance
// draws one mesh through an affine transform. Hits name the instance (Hit::instance) and
// the triangle's index in the whole TriangleSoA (Hit::prim), so shading reads per-corner
// attributes exactly as for a one-level scene.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "accel/ray.h"

namespace lancer {

// Triangles [first, first + count) of the TriangleSoA.
struct MeshRange {
  std::uint32_t first = 0;
  std::uint32_t count = 0;
};

// x -> linear * x + offset, in float. The two-level accelerator moves rays into an
// instance's space with exactly these operations (the build keeps -ffp-contract=off, so
// every translation unit rounds them alike); the renderer's ray offsets repeat them to
// prove a ray cannot hit the triangle it leaves.
struct Affine {
  glm::mat3 linear{1.0f};
  glm::vec3 offset{0.0f};

  glm::vec3 point(const glm::vec3& p) const { return vector(p) + offset; }
  glm::vec3 vector(const glm::vec3& v) const {
    return {linear[0][0] * v.x + linear[1][0] * v.y + linear[2][0] * v.z,
            linear[0][1] * v.x + linear[1][1] * v.y + linear[2][1] * v.z,
            linear[0][2] * v.x + linear[1][2] * v.y + linear[2][2] * v.z};
  }
};

// One drawing of mesh `mesh`. to_object is the inverse of to_world (computed in double,
// then rounded), and to_world's linear part is invertible.
struct Instance {
  std::uint32_t mesh = 0;
  Affine to_world;
  Affine to_object;
};

// The ray as the accelerator traces it inside `inst`: origin and direction in object space,
// the same tnear and tfar (the direction is not renormalised, so t keeps its meaning).
inline Ray ray_to_object(const Instance& inst, const Ray& ray) {
  return Ray{inst.to_object.point(ray.org), ray.tnear, inst.to_object.vector(ray.dir), ray.tfar};
}

// A scene whose triangles are drawn through instances. Empty: the triangles are in world
// space and drawn once (the one-level case). Otherwise every triangle belongs to exactly
// one mesh, and a mesh drawn in world space has an instance with identity transforms.
struct InstancedGeometry {
  std::vector<MeshRange> meshes;
  std::vector<Instance> instances;

  bool empty() const { return instances.empty(); }
};

}  // namespace lancer
