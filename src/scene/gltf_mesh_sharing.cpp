#include "scene/gltf_mesh_sharing.h"

#include <limits>
#include <string>

#include <glm/matrix.hpp>
#include <tiny_gltf.h>

#include "scene/scene_error.h"
#include "scene/scene_warning.h"
#include "scene/scene_instancing.h"

namespace lancer::gltf {

MeshSharing::MeshSharing(const ModelRef& m, Scene& scene, PrimitiveEmitter& emitter, InstancingMode mode)
    : m_(m), scene_(scene), emitter_(emitter), mode_(mode), meshes_(m.model.meshes.size()) {}

void MeshSharing::count(int mesh, const glm::dmat4& world, bool posed, bool moves) {
  if (posed || mesh < 0 || std::size_t(mesh) >= meshes_.size()) return;
  if (!make_instance(0, world)) return;
  ++meshes_[std::size_t(mesh)].drawings;
  meshes_[std::size_t(mesh)].moves |= moves;
}

bool MeshSharing::shared(int mesh) const {
  if (mesh < 0 || std::size_t(mesh) >= meshes_.size()) return false;
  if (meshes_[std::size_t(mesh)].moves) return true;
  if (mode_ == InstancingMode::Off) return false;
  const std::size_t drawings = meshes_[std::size_t(mesh)].drawings;
  if (drawings < 2) return false;
  if (mode_ == InstancingMode::On) return true;
  const std::size_t triangles = emitter_.triangle_bound(mesh);
  return triangles > 0 && drawings - 1 >= (kInstancingMinTriangles + triangles - 1) / triangles;
}

std::optional<InstanceMotion> MeshSharing::motion_of(int mesh, const std::vector<glm::dmat4>& worlds, bool posed) {
  if (posed) {
    if (!warned_deforming_)
      print_scene_warnings(m_.file, "mesh " + std::to_string(mesh) + " is skinned or morphed and moves while the shutter "
                                    "is open: deforming meshes are not blurred, it is drawn as at the opening");
    warned_deforming_ = true;
    return std::nullopt;
  }
  // An emitter that moved would need the lights sampled at each path's time.
  for (const tinygltf::Primitive& p : m_.model.meshes[std::size_t(mesh)].primitives)
    if (p.material >= 0 && std::size_t(p.material) < scene_.materials.size() &&
        scene_.materials[std::size_t(p.material)].emissive()) {
      if (!warned_emitting_)
        print_scene_warnings(m_.file, "mesh " + std::to_string(mesh) + " emits light and moves while the shutter is "
                                      "open: moving lights are not blurred, it is drawn as at the opening");
      warned_emitting_ = true;
      return std::nullopt;
    }
  InstanceMotion motion;
  for (const glm::dmat4& w : worlds) {
    const std::optional<MotionKey> key = motion_key(w);
    // Interpolated stretches must stay invertible: every key proper, or every key mirroring.
    if (!key || (!motion.keys.empty() && (glm::determinant(key->stretch) < 0.0f) !=
                                             (glm::determinant(motion.keys[0].stretch) < 0.0f))) {
      if (!warned_unusable_)
        print_scene_warnings(m_.file, "mesh " + std::to_string(mesh) + " moves through a singular or mirroring "
                                      "transform while the shutter is open: drawn as at the opening, not blurred");
      warned_unusable_ = true;
      return std::nullopt;
    }
    motion.keys.push_back(*key);
  }
  return motion;
}

void MeshSharing::draw(int mesh, const glm::dmat4& world, const MeshPose& pose, const std::vector<glm::dmat4>& motion) {
  const bool posed = !pose.morph_weights.empty() || !pose.joints.empty();
  std::optional<InstanceMotion> moving;
  if (!motion.empty()) moving = motion_of(mesh, motion, posed);
  std::optional<Instance> instance;
  if (!posed && shared(mesh)) instance = moving ? instance_from_key(0, moving->keys[0]) : make_instance(0, world);
  if (!instance) {
    // A world-space copy, numbered where a flattened file puts it.
    if (next_id_ >= std::numeric_limits<std::uint32_t>::max())
      throw SceneError(m_.file, "too many triangles: source ids are 32-bit");
    emitter_.set_next_source_id(std::uint32_t(next_id_));
    emitter_.emit_mesh(mesh, world, pose);
    next_id_ = emitter_.next_source_id();
    return;
  }
  if (pending_.size() >= kMaxSceneInstances)
    throw SceneError(m_.file, "more than " + std::to_string(kMaxSceneInstances) + " mesh instances in the scene");
  MeshState& state = meshes_[std::size_t(mesh)];
  if (!state.stored) {
    // The mesh's one copy, in its own space, its ids counted from 0 (Scene::source_id adds
    // each instance's base).
    state.stored = true;
    state.first = std::uint32_t(scene_.triangle_count());
    emitter_.set_next_source_id(0);
    emitter_.emit_mesh(mesh, glm::dmat4(1.0));
    state.count = std::uint32_t(scene_.triangle_count()) - state.first;
    state.ids = emitter_.next_source_id();
    stored_order_.push_back(mesh);
  }
  instance->mesh = std::uint32_t(mesh);  // the glTF mesh until finish()
  if (moving) {
    instance->motion = std::uint32_t(motions_.size());
    motions_.push_back(std::move(*moving));
  }
  pending_.push_back(*instance);
  // Ids past 2^32 drawn triangles have no number: kNoHit, as Scene::source_id documents.
  pending_base_.push_back(next_id_ + state.ids <= std::numeric_limits<std::uint32_t>::max() ? std::uint32_t(next_id_)
                                                                                          : kNoHit);
  next_id_ += state.ids;
}

void MeshSharing::finish() {
  if (pending_.empty()) return;
  const std::size_t n = scene_.triangle_count();
  std::vector<char> in_copy(n, 0);
  for (int mesh : stored_order_) {
    const MeshState& s = meshes_[std::size_t(mesh)];
    for (std::uint32_t i = s.first; i < s.first + s.count; ++i) in_copy[i] = 1;
  }
  std::vector<std::uint32_t> order;
  order.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i)
    if (!in_copy[i]) order.push_back(i);
  const auto world_count = std::uint32_t(order.size());

  InstancedGeometry& g = scene_.instancing;
  g = {};
  scene_.instance_source_base.clear();
  if (world_count > 0) {
    g.meshes.push_back({0, world_count});
    Instance identity;
    g.instances.push_back(identity);
    scene_.instance_source_base.push_back(0);
  }
  for (int mesh : stored_order_) {
    MeshState& s = meshes_[std::size_t(mesh)];
    s.index = std::uint32_t(g.meshes.size());
    g.meshes.push_back({std::uint32_t(order.size()), s.count});
    for (std::uint32_t i = s.first; i < s.first + s.count; ++i) order.push_back(i);
  }
  reorder_triangles(scene_, order);

  // Instances of a mesh whose every triangle was dropped (zero area) draw nothing.
  g.instances.reserve(g.instances.size() + pending_.size());
  scene_.instance_source_base.reserve(g.instances.capacity());
  for (std::size_t k = 0; k < pending_.size(); ++k) {
    const MeshState& s = meshes_[pending_[k].mesh];
    if (s.count == 0) continue;
    Instance inst = pending_[k];
    inst.mesh = s.index;
    g.instances.push_back(inst);
    scene_.instance_source_base.push_back(pending_base_[k]);
  }
  g.motions = std::move(motions_);
  if (g.instances.empty()) g = {};
  pending_.clear();
  pending_.shrink_to_fit();
  pending_base_.clear();
  pending_base_.shrink_to_fit();
}

}  // namespace lancer::gltf
