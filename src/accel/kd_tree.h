// Lancer's kd-tree accelerator: SAH (or naive) build, 8-byte nodes, leaf triangles copied
// in SoA blocks, single-ray front-to-back traversal that gives exactly the oracle's answer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "accel/accelerator.h"
#include "accel/kd_build.h"
#include "accel/kd_node.h"

namespace lancer {

class KdTree final : public Accelerator {
 public:
  using Block = KdTriangleBlock<kKdBlockWidth>;

  // Copies what it needs: `tris` may be destroyed afterwards. Builds with oneTBB in the
  // current task arena; the tree is the same for every thread count.
  explicit KdTree(const TriangleSoA& tris, const KdBuildOptions& options = {});

  Hit intersect(const Ray& ray) const override;
  bool occluded(const Ray& ray) const override;
  std::size_t memory_bytes() const override;
  std::string_view name() const override { return "kdtree"; }

  // Read access for statistics, tests and other traversal kernels.
  const std::vector<KdNode>& nodes() const { return nodes_; }
  // Per slot: the triangle index, kNoHit for padding. Leaf ranges start at multiples of
  // the block width.
  const std::vector<std::uint32_t>& leaf_prims() const { return leaf_prims_; }
  const AlignedVector<Block>& blocks() const { return blocks_; }
  const Bounds3& bounds() const { return bounds_; }
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
  std::vector<KdNode> nodes_;
  std::vector<std::uint32_t> leaf_prims_;
  AlignedVector<Block> blocks_;
  std::size_t triangle_count_ = 0;
  std::size_t references_ = 0;
  std::size_t reference_budget_ = 0;
  int depth_bound_ = 0;
  double build_ms_ = 0.0;
};

}  // namespace lancer
