// Cost constants of the surface area heuristic for Lancer's kd-tree kernels.
#pragma once

namespace lancer {

// Measured on the development machine (AMD EPYC VM, 2 cores, g++ 12, Release) with
//   build/release/bench/lancer_bench_micro --benchmark_filter=BM_KdCost
// BM_KdCost builds SAH trees of the 100k-triangle "spheres" scene with C_isect / C_trav
// from 1/16 to 2, traces the same diffuse-bounce rays through each (thread CPU time, side
// by side in one run) and reports the time per ray for each tree, with the inner-node
// steps and triangle tests per ray. With the SIMD leaf kernels a triangle test costs a few
// ns while an inner step, with its cache miss and hard-to-predict branch, costs about
// 20 ns, so the least-squares fit of time = c + C_trav * steps + C_isect * tests is poorly
// conditioned; the direct comparison is not. Per diffuse ray (avx2; sse4 alike):
//   ratio   1/16  1/8   1/4   1/2   1     2
//   ns      663   708   828   995   1170  1179
//   steps   25.8  30.1  34.6  39.2  43.3  45.1
//   tests   73.5  40.8  22.9  14.1  9.8   8.6
// so the tree built with ratio 1/16 traces fastest. Only the ratio matters to the SAH.
inline constexpr float kKdTraversalCost = 1.0f;
inline constexpr float kKdIntersectionCost = 0.0625f;

// Wald & Havran's empty-space bonus: a split with one empty side costs 0.8 of the formula.
inline constexpr float kKdEmptySpaceFactor = 0.8f;

}  // namespace lancer
