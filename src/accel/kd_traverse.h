// Single-ray traversal of the kd-tree: closest hit and any hit.
#pragma once

#include <cstdint>

#include "accel/kd_node.h"
#include "accel/ray.h"
#include "accel/triangle_soa.h"

namespace lancer {

class KdTree;

// What the traversal reads; cheap to copy.
struct KdTreeView {
  const KdNode* nodes;
  const KdTriangleBlock<kKdBlockWidth>* blocks;
  const std::uint32_t* prims;  // per slot, kNoHit for padding
  std::uint32_t slot_count;
  Bounds3 bounds;
};

KdTreeView view(const KdTree& tree);

// Closest hit with ray.tnear <= t < ray.tfar, ties in t to the lowest triangle index:
// the same triangle and the bit-identical t, u, v that BruteForce returns.
Hit kd_intersect(const KdTreeView& tree, const Ray& ray);

// Work done by one or more traversals, for the cost measurements and statistics.
struct KdTraversalCounts {
  std::uint64_t inner_steps = 0;
  std::uint64_t leaves = 0;
  std::uint64_t triangle_tests = 0;
};

// kd_intersect that also adds up the work it does (slower: for measurements only).
Hit kd_intersect_counted(const KdTreeView& tree, const Ray& ray, KdTraversalCounts& counts);

// True when some triangle is hit with ray.tnear <= t < ray.tfar (BruteForce::occluded).
bool kd_occluded(const KdTreeView& tree, const Ray& ray);

}  // namespace lancer
