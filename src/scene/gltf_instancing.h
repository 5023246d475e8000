// EXT_mesh_gpu_instancing: a node drawing its mesh many times, each instance with its own
// translation, rotation and scale, given per instance by accessors.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>

#include "scene/gltf_accessors.h"

namespace lancer::gltf {

// The most triangles the copies of one instanced mesh may make: instances are copied into
// the scene (there is no two-level acceleration structure yet), and a few bytes of
// accessors could otherwise ask for any number of them. 2^25 triangles take about 7 GiB
// with the kd-tree.
inline constexpr std::size_t kMaxInstancedTriangles = std::size_t(1) << 25;
// The most instances of one node, whatever its mesh: each costs a matrix before any
// triangle is copied (2^22 of them take 512 MiB).
inline constexpr std::size_t kMaxInstances = std::size_t(1) << 22;

// The per-instance transforms of node `node` (EXT_mesh_gpu_instancing, "Extension
// Schema"): T * R * S from its TRANSLATION (VEC3 FLOAT), ROTATION (VEC4 quaternion of
// FLOAT or normalized BYTE/SHORT) and SCALE (VEC3 FLOAT) accessors, a missing one being
// the identity, all of the same count. They apply in the node's space, before its world
// transform: world * instance. Nothing when the node does not use the extension (its mesh
// is drawn once), and an empty list when it has no instances (the mesh is not drawn).
// TRANSLATION and SCALE may be integers when the file uses KHR_mesh_quantization. Throws
// SceneError for a malformed extension, accessors of different counts, a non-finite
// value, a zero quaternion, more than kMaxInstances instances, or more than
// kMaxInstancedTriangles allows copies of a mesh of `mesh_triangles` triangles.
std::optional<std::vector<glm::dmat4>> instance_transforms(const ModelRef& m, int node, std::size_t mesh_triangles);

}  // namespace lancer::gltf
