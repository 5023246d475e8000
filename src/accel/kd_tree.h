// Lancer's kd-tree accelerator: SAH (or naive) build, 8-byte nodes, leaf triangles copied
// in SoA blocks as wide as the chosen ISA's vectors, single-ray front-to-back traversal
// (one kernel per ISA, kd_traverse.h) that gives exactly the oracle's answer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "accel/accelerator.h"
#include "accel/kd_build.h"
#include "accel/kd_node.h"
#include "accel/kd_traverse.h"
#include "simd/isa.h"

namespace lancer {

class KdTree final : public Accelerator {
 public:
  // Copies what it needs: `tris` may be destroyed afterwards. Builds with oneTBB in the
  // current task arena; the tree is the same for every thread count. Traverses with the
  // kernels of `isa` (the best this CPU runs by default); throws std::invalid_argument when
  // the CPU or this build lacks that ISA. The leaf blocks are laid out for it.
  explicit KdTree(const TriangleSoA& tris, const KdBuildOptions& options = {}, Isa isa = best_supported_isa());

  Hit intersect(const Ray& ray) const override { return kernels_.intersect(view(*this), ray); }
  bool occluded(const Ray& ray) const override { return kernels_.occluded(view(*this), ray); }
  // intersect that also adds up the work done (for measurements).
  Hit intersect_counted(const Ray& ray, KdTraversalCounts& counts) const {
    return kernels_.intersect_counted(view(*this), ray, counts);
  }
  bool occluded_counted(const Ray& ray, KdTraversalCounts& counts) const {
    return kernels_.occluded_counted(view(*this), ray, counts);
  }
  // Closest hits of rays[0..count), exactly intersect's, traversed in packets of up to 64
  // rays (coherent rays, e.g. an 8x8 pixel tile, share most of the work). Throws
  // std::invalid_argument for a negative count.
  void intersect_packet(const Ray* rays, Hit* hits, int count) const override;
  // occluded for rays[0..count) in packets of up to 64, each lane leaving at its first hit.
  void occluded_packet(const Ray* rays, bool* occluded, int count) const override;
  std::size_t memory_bytes() const override;
  std::string_view name() const override { return "kdtree"; }

  // Read access for statistics, tests and other traversal kernels.
  const std::vector<KdNode>& nodes() const { return nodes_; }
  // Per slot: the triangle index, kNoHit for padding. Leaf ranges start at multiples of
  // the block width.
  const std::vector<std::uint32_t>& leaf_prims() const { return leaf_prims_; }
  // The leaf triangles: blocks of KdTriangleBlock<block_width()> layout, 9 * block_width()
  // floats each, slot s in block s / block_width() at lane s % block_width().
  const AlignedVector<float>& blocks() const { return blocks_; }
  int block_width() const { return kernels_.block_width; }
  // Vertex k of the triangle in `slot`, as stored (NaN for padding).
  glm::vec3 slot_vertex(std::uint32_t slot, int k) const;
  Isa isa() const { return kernels_.isa; }
  const Bounds3& bounds() const { return bounds_; }
  // The largest extent of bounds(), rounded up to a float (kd_traverse_setup.h).
  float max_extent_up() const { return max_extent_up_; }
  // The options the tree was built with, an automatic intersection cost filled in.
  const KdBuildOptions& options() const { return options_; }
  std::size_t triangle_count() const { return triangle_count_; }
  std::size_t references() const { return references_; }
  std::size_t reference_budget() const { return reference_budget_; }
  int depth_bound() const { return depth_bound_; }
  double build_ms() const { return build_ms_; }

 private:
  void lay_out_leaves(const TriangleSoA& tris, const KdBuildOutput& built);

  KdBuildOptions options_;
  Bounds3 bounds_;
  float max_extent_up_ = 0.0f;
  std::vector<KdNode> nodes_;
  std::vector<std::uint32_t> leaf_prims_;
  KdKernels kernels_;
  AlignedVector<float> blocks_;
  std::size_t triangle_count_ = 0;
  std::size_t references_ = 0;
  std::size_t reference_budget_ = 0;
  int depth_bound_ = 0;
  double build_ms_ = 0.0;
};

}  // namespace lancer
