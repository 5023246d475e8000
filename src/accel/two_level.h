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
// Direct instances: a static instance whose transforms are exactly the identity (the world
// geometry of a scene where only some meshes are instanced or move) stays out of the top
// level: every ray enters it first (still through ray_to_object, so the answers keep
// their definition), and the top level then clips the ray to the best hit so far. Most
// rays of such a scene then never pay for the top level's fat-ray setup.
//
// Traversal holds no lock and allocates nothing (fixed stacks, one entry per level); the
// only virtual calls are one per bottom-level visit.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "accel/accelerator.h"
#include "accel/instances.h"
#include "accel/kd_build.h"
#include "accel/top_level_tree.h"
#include "accel/two_level_motion.h"
#include "simd/isa.h"

namespace lancer {

namespace two_level {
struct TopRay;       // two_level_ray.h
struct PacketSetup;  // two_level_packet.cpp
}  // namespace two_level

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
  // Whether the top level's instances are few enough to be met one by one (see "Few
  // instances" below) rather than through its tree.
  bool meets_few_instances() const { return !few_top_.empty(); }
  // Instances entered before the top level (see "Direct instances" above).
  std::size_t direct_count() const { return direct_list_.size(); }
  // Meshes with a bottom-level tree (those some instance draws).
  std::size_t bottom_count() const;
  const TopLevelTree& top_level() const { return top_; }
  std::string_view bottom_name() const { return bottom_name_; }
  double build_ms() const { return build_ms_; }

  // A top level of at most this many instances is met one by one (see "Few instances").
  static constexpr std::size_t kFewTopInstances = 8;
  static_assert(kFewTopInstances < 32, "few_met keeps one bit per instance in an unsigned, and shifts 1u by the count");

 private:
  // The packet's top-level rays (two_level_packet.cpp).
  void setup_packet(const Ray* rays, const Hit* hits, std::uint64_t skip, int count, two_level::PacketSetup& p) const;
  void intersect_packet64(const Ray* rays, Hit* hits, int count) const;
  std::uint64_t moving_lanes(std::uint32_t i, std::uint64_t lanes, const Ray* rays,
                             const two_level::PacketSetup& p) const;
  int gather_lanes(std::uint32_t i, std::uint64_t lanes, const Ray* rays, const Hit* hits, Ray* local,
                   int* lane_of) const;
  void enter_packet(std::uint32_t i, std::uint64_t lanes, const Ray* rays, Hit* hits) const;
  std::uint64_t block_packet(std::uint32_t i, std::uint64_t lanes, const Ray* rays) const;
  void occluded_packet64(const Ray* rays, bool* occluded, int count) const;
  // Enters instance i with the tie rule above, updating `best`.
  void visit(std::uint32_t i, const Ray& ray, Hit& best) const;
  // The ray instance i's tree is given: moved into its space, tfar
  // narrowed by the tie rule against `best`.
  Ray entered(std::uint32_t i, const Ray& ray, const Hit& best) const {
    const Instance& inst = instances_[i];
    Ray r = inst.motion == kNoHit ? ray_to_object(inst, ray) : ray_to_object(at_time(i, ray.time), ray);
    if (best.valid()) r.tfar = i < best.instance ? std::nextafter(best.t, kInfinity) : best.t;
    return r;
  }
  // Whether instance i blocks the ray.
  bool blocks(std::uint32_t i, const Ray& ray) const;
  // The instances of the top level (all but the direct ones), after `best` from the others.
  void intersect_top(const Ray& ray, Hit& best) const;
  bool occluded_top(const Ray& ray) const;
  // The direct instances for a packet: hits start empty.
  void intersect_direct(const Ray* rays, Hit* hits, int count) const;

  // Few instances (at most kFewTopInstances in the top level): a ray, or a packet's lanes
  // whatever their directions, meets each in ascending order after a test against its
  // box instead of walking the top level's tree; the same answers by the tie rule.
  //
  // The few_top_ entries the ray may meet, bit j for few_top_[j], and the ray set up in
  // `tr` (every bit for a ray the top level scans: TopPlan::Scan). First its segment box
  // (two_level_ray.h) against each instance's box (a moving one's over the piece of the
  // shutter holding the ray's time), which needs no division; then, only for the boxes it
  // meets, the fat ray's clip (fat_ray_meets_box), which rejects far more of a long ray's.
  unsigned few_met(const Ray& clipped, two_level::TopRay& tr) const;
  // few_top_[j]'s box at `time`.
  const Bounds3& few_box(std::size_t j, float time) const {
    const std::uint32_t i = few_top_[j];
    return piece_count_[i] == 0 ? few_top_boxes_[j] : piece_box(i, time);
  }
  // Moving instance i's box over the piece of the shutter holding `time`
  // (ShutterBounds::pieces).
  const Bounds3& piece_box(std::uint32_t i, float time) const {
    return piece_boxes_[piece_first_[i] + two_level::piece_of(piece_count_[i], time)];
  }
  // Whether the fat ray can meet moving instance i at `time`: the box of i over the piece
  // of the shutter holding `time` (a small part of its box over the shutter), tested
  // before the interpolation at_time costs.
  bool meets_moving(std::uint32_t i, const two_level::TopRay& tr, float time) const;
  // Moving instance i as a ray at `time` meets it (PreparedMotions::moving_at, memoised
  // per thread). The reference is good until this thread's next interpolation.
  const Instance& at_time(std::uint32_t i, float time) const { return motions_.moving_at(instances_[i], time); }

  std::vector<Instance> instances_;
  PreparedMotions motions_;  // instance_at's bits, with each span's slerp angle computed once
  std::vector<std::uint32_t> mesh_first_;             // per mesh, its first triangle
  std::vector<std::unique_ptr<Accelerator>> bottoms_;  // per mesh, null when no instance draws it
  std::vector<std::unique_ptr<TriangleSoA>> kept_;     // per mesh, the copy a BruteForce bottom refers to
  std::vector<char> direct_;                // per instance: entered before the top level
  std::vector<std::uint32_t> direct_list_;  // the direct instances, ascending
  std::vector<std::uint32_t> few_top_;  // the top level's instances when at most kFewTopInstances, else empty
  std::vector<Bounds3> few_top_boxes_;  // their widened world boxes (used for those that do not move)
  // Per moving instance, the index of its first piece's box (ShutterBounds::pieces).
  std::vector<std::uint32_t> piece_first_;
  std::vector<std::uint32_t> piece_count_;  // per instance, its piece count (0: static)
  std::vector<Bounds3> piece_boxes_;
  TopLevelTree top_;
  double beta_ = 0.0;    // the fat ray's radius per unit of |org| (two_level_ray.h)
  double extent_ = 0.0;  // the largest mesh extent times its to_world norm (two_level_ray.h)
  double top_norm_ = 0.0;  // two_level::box_norm of the top level's box
  std::string_view bottom_name_;
  double build_ms_ = 0.0;
};

}  // namespace lancer
