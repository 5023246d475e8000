// Turns glTF mesh primitives into world-space triangles for a SceneBuilder.
#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "scene/gltf_accessors.h"
#include "scene/gltf_draco.h"
#include "scene/scene_builder.h"

namespace lancer::gltf {

// How a node poses its mesh (glTF 2.0, "Morph Targets" and "Skins"): morph weights, one
// per target of each primitive (node.weights, else mesh.weights), and for a skinned mesh
// its joint matrices, world(joint j) * inverseBindMatrix j, which replace the node's own
// transform ("the transform of the skinned mesh node MUST be ignored").
struct MeshPose {
  std::vector<double> morph_weights;  // empty: no target applied
  std::vector<glm::dmat4> joints;     // empty: not skinned
};

class PrimitiveEmitter {
 public:
  // scene.materials must already hold the file's materials (glTF material i = i).
  PrimitiveEmitter(const ModelRef& m, Scene& scene, SceneBuilder& builder) : m_(m), scene_(scene), builder_(builder) {}

  // Emits every primitive of mesh `mesh` placed by `world`. Triangles (mode 4), strips
  // (5) and fans (6) become triangles; points and lines are counted in
  // scene.stats.non_triangle_primitives_skipped with one warning on stderr per file.
  //
  // Source ids: each triangle's id is its position among the triangles of the file in
  // emission order, i.e. node traversal order (see scene_nodes), then primitive order
  // within the mesh, then triangle order within the primitive. A mesh used by two
  // nodes gets ids for each instance; dropped zero-area triangles still use an id.
  void emit_mesh(int mesh, const glm::dmat4& world, const MeshPose& pose = {});

  // At least the number of triangles emit_mesh(mesh) makes (the index or vertex counts of
  // its primitives, the decoded faces of Draco ones), without reading other data; 0 for a
  // mesh index out of range.
  std::size_t triangle_bound(int mesh);

  // The source id the next emitted triangle gets. A reader drawing a mesh through an
  // instance moves it past the ids a flattened copy would have used.
  std::uint32_t next_source_id() const { return next_source_id_; }
  void set_next_source_id(std::uint32_t id) { next_source_id_ = id; }

 private:
  void emit_primitive(int mesh, int primitive, const glm::dmat4& world, const MeshPose& pose);
  std::uint32_t material_id(int material, const std::string& what);
  // The primitive's Draco data, decoded once however many nodes and instances draw it;
  // null when it is not compressed.
  const DracoPrimitive* draco(int mesh, int primitive, const std::string& what);

  const ModelRef& m_;
  Scene& scene_;
  SceneBuilder& builder_;
  std::uint32_t next_source_id_ = 0;
  std::optional<std::uint32_t> default_material_;
  std::map<std::pair<int, int>, std::optional<DracoPrimitive>> draco_;
  bool warned_non_triangles_ = false;
  bool warned_missing_texcoords1_ = false;
};

}  // namespace lancer::gltf
