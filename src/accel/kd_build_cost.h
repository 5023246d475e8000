// Cost constants of the surface area heuristic for Lancer's kd-tree kernels.
#pragma once

#include "simd/isa.h"

namespace lancer {

// Only the ratio C_isect / C_trav matters to the SAH; C_trav is 1.
inline constexpr float kKdTraversalCost = 1.0f;

// C_isect per ISA: a triangle test costs what that ISA's leaf kernel makes it cost (an
// inner step, a chain of dependent loads and arithmetic with its cache miss, costs 20-30 ns
// everywhere), so each ISA's tree is built for its own kernels. Measured with
//   build/release/bench/lancer_bench_micro --benchmark_filter=BM_KdCost
// which builds SAH trees of the 100k-triangle "spheres" scene with several ratios and traces
// the same diffuse-bounce rays through each, side by side in one run (thread CPU time,
// ns per ray, medians of 3; AMD EPYC VM with AVX-512, g++ 12, Release; closest-hit steps as
// selects since commit d3dbd9e, which made every tree 5-12 % faster without moving the
// optimum: avx2 1/32 and 1/16 are within 2 %, avx512 1/64 and 1/32 within 1 %):
//   ratio    1/64   1/32   1/16   1/8    1/4
//   scalar   2027   1253   1006    884    874
//   sse4      774    606    567    611    676
//   avx2      549    491    498    570    649
//   avx512    464    462    479    578    676
// Packets of primary rays agree (lancer bench --sets primary,diffuse --threads 1, 22 scenes
// at 512 x 512, packet / Embree rtcIntersect16 side by side): avx512 median 1.10x at 1/16,
// 1.16x at 1/32, 1.15x at 1/64; avx2 1.41x at 1/16 and 1.39x at 1/32. The scalar kernel
// stays at 1/16: its faster 1/8 tree takes 104 bytes per triangle on rings-5, over the
// memory bound of kd_memory_test.
constexpr float kd_intersection_cost(Isa isa) {
  switch (isa) {
    case Isa::Scalar:
    case Isa::Sse4:
    case Isa::Avx2:
      return 0.0625f;
    case Isa::Avx512:
      return 0.03125f;
  }
  return 0.0625f;
}

// Wald & Havran's empty-space bonus: a split with one empty side costs 0.8 of the formula.
inline constexpr float kKdEmptySpaceFactor = 0.8f;

}  // namespace lancer
