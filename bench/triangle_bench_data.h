// The generic side of the triangle-test benchmarks: a fixed, seeded set of triangles and
// rays (part of the pairs hit), its SoA blocks at each width, the scalar watertight
// kernel's answer for every pair, and the check of a kernel table against it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "accel/ray.h"
#include "accel/triangle_soa.h"
#include "simd/aligned_vector.h"
#include "triangle_bench_kernels.h"

namespace lancer::bench {

inline constexpr int kBenchTriangles = 256;  // 9 KiB of vertices: the blocks stay in L1
inline constexpr int kBenchRays = 64;

struct TriangleBenchData {
  TriangleSoA triangles;
  std::vector<Ray> rays;
  // intersect_watertight (watertight.h) for ray r and triangle i, at [r * kBenchTriangles + i].
  std::vector<std::uint8_t> hit;
  std::vector<float> t;  // where hit
  std::int64_t hits = 0;
};

// Built once, from a fixed seed (the same on every machine).
const TriangleBenchData& triangle_bench_data();

// The triangles in the kd-tree's leaf layout: blocks of block_width slots, 9 rows each (x
// of vertices 0-2, then y, then z); kBenchTriangles is a multiple of every block width.
AlignedVector<float> triangle_blocks(const TriangleSoA& triangles, int block_width);

// The table of an ISA this build has kernels for (nullopt: none here). Does not check
// the CPU: call it only for cpu_supports(isa).
std::optional<TriangleKernels> triangle_kernels_for(Isa isa);

// Records the kernel's answer for every pair of `data` (prepared rays in leaf_rays, the
// triangles in `blocks`) and compares it with the scalar kernel's: the same hits and
// bit-identical t. Lanes the leaf test hands to the scalar kernel (an edge function exactly
// 0) are left out and counted in edge_zero_lanes. Then checks that count_hits gives the
// recorded number of hits. Returns an empty string when all agree, else what differs.
std::string check_triangle_kernels(const TriangleKernels& kernels, const TriangleBenchData& data, const float* blocks,
                                   const void* leaf_rays, std::int64_t& edge_zero_lanes);

}  // namespace lancer::bench
