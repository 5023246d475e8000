// The two-level accelerator (issue 19): each mesh drawn by an instance is stored once with
// its own object-space tree (a KdTree, or the brute-force oracle for tests); a kd-tree
// over the instances' world boxes (top_level_tree.h) leads a ray to the instances it may
// hit, and each is entered with exactly ray_to_object (instances.h).
//
// Answers. intersect gives the lexicographic minimum of (t, instance, triangle) over every
// instance's bottom-level answer, whatever order the instances are visited in: a visit to
// instance i with best (t_b, i_b) so far narrows tfar to t_b, or to the next float above t_b
// when i < i_b, so any hit it returns wins. Single rays and packets therefore agree bit for
// bit. Hit::prim is the triangle's index in the whole TriangleSoA (mesh.first + its index
// in the mesh), Hit::instance the instance's. Why the top level never skips an instance
// holding the answer: two_level_ray.h.
//
// Moving instances (Instance::motion, issue 19): one is entered with exactly
// ray_to_object(instance_at(geometry, inst, ray.time), ray), each lane of a packet at its
// own time, so the answers above hold at every time; its top-level box holds the mesh over
// the whole shutter (two_level_motion.h). Static instances pay one branch for this.
//
// Traversal holds no lock and allocates nothing (fixed stacks, one entry per level); the
// only virtual calls are one per bottom-level visit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "accel/accelerator.h"
#include "accel/instances.h"
#include "accel/kd_build.h"
#include "accel/top_level_tree.h"
#include "simd/isa.h"

namespace lancer {

class TwoLevelAccelerator final : public Accelerator {
 public:
  // `bottom`: "kdtree" (with `kd` and `isa`) or "brute". Copies what it needs: `tris` and
  // `geometry` may be destroyed afterwards. Throws std::invalid_argument for an unknown
  // bottom, an ISA this CPU lacks, a mesh range outside `tris`, an instance of a mesh that
  // does not exist, a transform that is not finite, singular, or scales by more than 2^40
  // either way, a motion that validate_motions (two_level_motion.h) refuses, or a world box
  // that overflows float.
  TwoLevelAccelerator(const TriangleSoA& tris, const InstancedGeometry& geometry, std::string_view bottom,
                      const KdBuildOptions& kd = {}, Isa isa = best_supported_isa());
  ~TwoLevelAccelerator() override;

  Hit intersect(const Ray& ray) const override;
  bool occluded(const Ray& ray) const override;
  // Packets of up to 64 rays share the top-level traversal and enter each instance's tree
  // as a packet; each answer is bit for bit intersect's (occluded's). Throws
  // std::invalid_argument for a negative count.
  void intersect_packet(const Ray* rays, Hit* hits, int count) const override;
  void occluded_packet(const Ray* rays, bool* occluded, int count) const override;
  std::size_t memory_bytes() const override;
  std::string_view name() const override { return "twolevel"; }

  std::size_t instance_count() const { return instances_.size(); }
  std::size_t mesh_count() const { return mesh_first_.size(); }
  // Meshes with a bottom-level tree (those some instance draws).
  std::size_t bottom_count() const;
  const TopLevelTree& top_level() const { return top_; }
  std::string_view bottom_name() const { return bottom_name_; }
  double build_ms() const { return build_ms_; }

 private:
  void intersect_packet64(const Ray* rays, Hit* hits, int count) const;
  void occluded_packet64(const Ray* rays, bool* occluded, int count) const;
  // Enters instance i with the tie rule above, updating `best`.
  void visit(std::uint32_t i, const Ray& ray, Hit& best) const;

  // The instance as ray `time` meets it: itself when it does not move.
  Instance at_time(const Instance& inst, float time) const { return instance_at(motions_, inst, time); }

  std::vector<Instance> instances_;
  InstancedGeometry motions_;  // only its motions: what instance_at reads
  std::vector<std::uint32_t> mesh_first_;             // per mesh, its first triangle
  std::vector<std::unique_ptr<Accelerator>> bottoms_;  // per mesh, null when no instance draws it
  std::vector<std::unique_ptr<TriangleSoA>> kept_;     // per mesh, the copy a BruteForce bottom refers to
  std::vector<Bounds3> moving_boxes_;  // per instance: its world box over the shutter if it moves
  TopLevelTree top_;
  double beta_ = 0.0;    // the fat ray's radius per unit of |org| (two_level_ray.h)
  double extent_ = 0.0;  // the largest mesh extent times its to_world norm (two_level_ray.h)
  std::string_view bottom_name_;
  double build_ms_ = 0.0;
};

}  // namespace lancer
