// Meshes drawn more than once (by several nodes, or EXT_mesh_gpu_instancing): which are
// stored once, in their own space, and drawn through instances (Scene::instancing), and
// which are copied into world space as before.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>

#include "scene/gltf_accessors.h"
#include "scene/gltf_primitives.h"
#include "scene/scene.h"

namespace lancer::gltf {

// The most instances a scene may draw: each holds two transforms and a place in the top
// level of the accelerator (a few hundred bytes in all), so 2^22 of them take about 1 GiB.
inline constexpr std::size_t kMaxSceneInstances = std::size_t(1) << 22;

class MeshSharing {
 public:
  MeshSharing(const ModelRef& m, Scene& scene, PrimitiveEmitter& emitter, InstancingMode mode);

  // First pass, over every drawing: mesh `mesh` drawn by `world`, posed (a skin or morph
  // weights: never shared) or not, moving while the shutter is open or not.
  void count(int mesh, const glm::dmat4& world, bool posed, bool moves = false);
  // Whether the unposed drawings of `mesh` share one stored copy: one of them moves (a
  // motion needs an instance, whatever the mode), or the mode allows it, the mesh is drawn
  // at least twice, and (Auto) the copies would add kInstancingMinTriangles.
  bool shared(int mesh) const;
  // Second pass, in the same order: the drawing through an instance when the mesh is
  // shared and the drawing is unposed with a usable transform (make_instance), else as a
  // world-space copy. `motion`: its world matrices at the shutter's kShutterSteps times
  // (empty: still); a moving drawing gets an InstanceMotion, unless it is posed (a
  // deforming mesh), emits light, or its transform turns singular or mirrors part of the
  // way: then it stays where it is at the opening, with a warning. Throws SceneError past
  // kMaxSceneInstances.
  void draw(int mesh, const glm::dmat4& world, const MeshPose& pose, const std::vector<glm::dmat4>& motion = {});
  // After the last drawing: the world-space triangles first, then each shared mesh's, and
  // scene.instancing with one identity instance for the world-space ones. Nothing changes
  // when no mesh was drawn through an instance.
  void finish();

 private:
  struct MeshState {
    std::size_t drawings = 0;  // unposed ones with a usable transform (first pass)
    bool moves = false;        // one of them moves while the shutter is open
    bool stored = false;       // its copy is in the scene
    std::uint32_t first = 0, count = 0;  // that copy's triangles, as emitted
    std::uint32_t first_id = 0, ids = 0;  // the source ids its emission used
    std::uint32_t index = 0;  // in scene.instancing.meshes
  };

  const ModelRef& m_;
  Scene& scene_;
  PrimitiveEmitter& emitter_;
  InstancingMode mode_;
  std::vector<MeshState> meshes_;
  std::vector<int> stored_order_;  // glTF meshes in the order their copies were emitted
  std::vector<Instance> pending_;  // drawings through instances; mesh is the glTF mesh
  std::vector<std::uint32_t> pending_base_;  // their source id bases
  std::vector<InstanceMotion> motions_;      // of the moving ones (Instance::motion)
  bool warned_deforming_ = false, warned_emitting_ = false, warned_unusable_ = false;
  // The motion of a drawing by `worlds`, or nothing (with a warning) where it cannot move.
  std::optional<InstanceMotion> motion_of(int mesh, const std::vector<glm::dmat4>& worlds, bool posed);
  std::uint64_t next_id_ = 0;      // of the flattened numbering (can pass 2^32 when shared)
};

}  // namespace lancer::gltf
