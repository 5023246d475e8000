// Building the kd-tree: options, and the flat result the KdTree class lays out.
//
// SAH trees follow Wald & Havran, "On building fast kd-trees for ray tracing, and on doing
// that in O(N log N)", IEEE RT 2006: events sorted once, a sweep over all three axes per
// node, classification, and splicing of the sorted events into the children without
// re-sorting; straddling triangles are clipped to the child cells ("perfect splits").
// Subtrees are built in parallel with oneTBB; the result does not depend on the number of
// threads (see kd_build.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "accel/kd_build_cost.h"
#include "accel/kd_node.h"
#include "accel/triangle_soa.h"

namespace lancer {

enum class KdSplit {
  Sah,     // surface area heuristic, O(N log N) event sweep
  Middle,  // spatial middle of the cell's longest axis
  Median,  // median of the triangle (clipped) box centres along the longest axis
};

struct KdBuildOptions {
  KdSplit split = KdSplit::Sah;
  float traversal_cost = kKdTraversalCost;
  // C_isect / C_trav; 0: kd_intersection_cost(the ISA's kernels), which KdTree fills in
  // (build_kd_tree itself wants a positive value).
  float intersection_cost = 0.0f;
  float empty_space_factor = kKdEmptySpaceFactor;
  // 0: the automatic bound round(8 + 1.3 log2 N); always capped at kKdMaxDepth.
  int max_depth = 0;
  // Memory bound: the leaves hold at most ceil(reference_factor * N) + 1 triangle
  // references in total (each node gets a share of this budget, see kd_build.cpp).
  // In [1, 16].
  float reference_factor = 4.0f;
  // Middle and Median split until a leaf holds at most this many triangles.
  std::size_t naive_leaf_size = 4;
  // Inputs of fewer triangles are built on the calling thread alone, with the least
  // memory (kd_build.cpp, "Peak memory"); the tree is the same either way.
  std::size_t one_thread_below = std::size_t(1) << 16;
  // Hand the memory the build freed back to the system before the leaves are laid out
  // (release_free_memory). It walks every free block of every arena, milliseconds on a
  // fragmented heap: a caller that builds many trees (one per instanced mesh) turns it
  // off and hands memory back once after them.
  bool hand_back_memory = true;
};

// The tree before the SoA layout: leaves index `prims` (unpadded, ascending triangle
// index within each leaf).
struct KdBuildOutput {
  Bounds3 bounds;                    // the root cell; empty when there is no finite triangle
  std::vector<KdNode> nodes;         // nodes[0] is the root
  std::vector<std::uint32_t> prims;  // leaf ranges, first_slot() indexes this
  int depth_bound = 0;               // the depth bound the build used
  std::size_t reference_budget = 0;  // the bound on prims.size()
};

// Triangles with a NaN or infinite coordinate are left out (the watertight kernel never
// reports a hit on them). Throws std::length_error if the tree would exceed the 30-bit
// offsets of the node layout.
KdBuildOutput build_kd_tree(const TriangleSoA& tris, const KdBuildOptions& options);

// The automatic depth bound for n triangles: round(8 + 1.3 log2 n), capped at kKdMaxDepth.
int kd_depth_bound(std::size_t n, int requested);

}  // namespace lancer
