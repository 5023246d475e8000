// Single-ray traversal of the kd-tree (closest hit and any hit), packet traversal of up to
// 64 rays (kd_packet-inl.h), and their per-ISA dispatch.
//
// One kernel per instruction set (kd_traverse_<isa>.cpp instantiates kd_traverse-inl.h in
// namespace lancer::<isa>); all give exactly the oracle's answers. The kernels are picked
// once through a plain table of function pointers (select_kd_kernels).
#pragma once

#include <cstdint>

#include "accel/kd_node.h"
#include "accel/ray.h"
#include "accel/triangle_soa.h"
#include "simd/isa.h"

namespace lancer {

class KdTree;

// What the traversal reads; cheap to copy.
struct KdTreeView {
  const KdNode* nodes;
  const float* blocks;         // KdTriangleBlock<block_width> layout, 9 * block_width floats each
  const std::uint32_t* prims;  // per slot, kNoHit for padding
  std::uint32_t slot_count;
  std::uint32_t block_width;
  Bounds3 bounds;
  float max_extent_up;  // kd_max_extent_up(bounds), made once per tree: every ray's setup reads it
};

KdTreeView view(const KdTree& tree);

// Work done by one or more traversals, for the cost measurements and statistics.
struct KdTraversalCounts {
  std::uint64_t inner_steps = 0;
  std::uint64_t leaves = 0;
  std::uint64_t triangle_tests = 0;  // triangles tested (a SIMD leaf test counts its live lanes)
};

// Closest hit with ray.tnear <= t < ray.tfar, ties in t to the lowest triangle index:
// the same triangle and the bit-identical t, u, v that BruteForce returns.
using KdIntersectFn = Hit (*)(const KdTreeView& tree, const Ray& ray);
// The same, also adding up the work done (slower: for measurements only).
using KdIntersectCountedFn = Hit (*)(const KdTreeView& tree, const Ray& ray, KdTraversalCounts& counts);
// True when some triangle is hit with ray.tnear <= t < ray.tfar (BruteForce::occluded).
using KdOccludedFn = bool (*)(const KdTreeView& tree, const Ray& ray);
// The same, also adding up the work done.
using KdOccludedCountedFn = bool (*)(const KdTreeView& tree, const Ray& ray, KdTraversalCounts& counts);
// intersect for rays[0..count), count <= 64, traversed together as one packet
// (kd_packet-inl.h): hits[i] is exactly what intersect gives for rays[i].
using KdIntersectPacketFn = void (*)(const KdTreeView& tree, const Ray* rays, Hit* hits, int count);
// occluded for rays[0..count), count <= 64, as one packet whose lanes leave at their first
// hit: occluded[i] is exactly what occluded gives for rays[i].
using KdOccludedPacketFn = void (*)(const KdTreeView& tree, const Ray* rays, bool* occluded, int count);

struct KdKernels {
  Isa isa;
  int block_width;  // the leaf block width these kernels read (a multiple of the vector width)
  KdIntersectFn intersect;
  KdIntersectCountedFn intersect_counted;
  KdOccludedFn occluded;
  KdOccludedCountedFn occluded_counted;
  KdIntersectPacketFn intersect_packet;
  KdOccludedPacketFn occluded_packet;
};

// The kernels of one ISA. Throws std::invalid_argument when this build has none for it
// (the x86 ISAs on other machines). Does not check the CPU: see cpu_supports.
KdKernels select_kd_kernels(Isa isa);

}  // namespace lancer
