// The top level of the two-level accelerator: a kd-tree over boxes (the instances' world
// bounds), built with the surface area heuristic; leaves list box indices.
//
// Build: events (box starts, ends, flat boxes) are sorted once per axis; each node sweeps
// its three sorted lists for the cheapest plane among the box edges strictly inside its
// cell, then splits every list into its children's in order (a box straddling the plane
// goes to both sides, its edge beyond the plane moved onto it), so no list is sorted again:
// O(N log N) after the first sort. The same idea as Wald & Havran 2006 (kd_build.h) on
// boxes instead of clipped triangles; written from scratch. Serial and free of hashing or
// pointer order, so the tree is the same on every run and for every thread count.
//
// Invariants: nodes[0] is the root; the layout is KdNode's (children side by side, a leaf's
// first_slot() indexes items()); each leaf lists its boxes in ascending index; at every
// split a box goes to each side it reaches past the plane (both when it straddles it), and
// a box lying flat in the plane goes left, so every point of a box lies in the closed cell
// of some leaf listing it. Empty boxes and boxes with a coordinate that is not finite are
// left out. The depth is at most kTopLevelMaxDepth.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "accel/kd_node.h"
#include "accel/triangle_soa.h"

namespace lancer {

// The top level never needs more than this depth; a traversal stack of
// kTopLevelStackSize entries holds one entry per level.
inline constexpr int kTopLevelMaxDepth = 40;
inline constexpr int kTopLevelStackSize = 48;
static_assert(kTopLevelMaxDepth < kTopLevelStackSize);

struct TopLevelBuildOptions {
  float traversal_cost = 1.0f;
  // Visiting one box's content (moving the ray into an instance and entering its tree) in
  // units of one top-level step.
  float visit_cost = 4.0f;
  float empty_space_factor = 0.8f;  // cost factor of a split with one empty side
  int max_depth = 0;                // 0: round(8 + 1.3 log2 N), capped at kTopLevelMaxDepth
};

class TopLevelTree {
 public:
  TopLevelTree() = default;
  // Throws std::length_error when the leaves would exceed KdNode's 30-bit offsets.
  explicit TopLevelTree(const std::vector<Bounds3>& boxes, const TopLevelBuildOptions& options = {});

  const std::vector<KdNode>& nodes() const { return nodes_; }
  const std::vector<std::uint32_t>& items() const { return items_; }
  // The union of the boxes kept (empty when there are none).
  const Bounds3& bounds() const { return bounds_; }
  int depth_bound() const { return depth_bound_; }
  std::size_t memory_bytes() const {
    return nodes_.capacity() * sizeof(KdNode) + items_.capacity() * sizeof(std::uint32_t);
  }

 private:
  std::vector<KdNode> nodes_;
  std::vector<std::uint32_t> items_;
  Bounds3 bounds_;
  int depth_bound_ = 0;
};

}  // namespace lancer
