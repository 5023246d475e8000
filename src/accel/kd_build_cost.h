// Cost constants of the surface area heuristic for Lancer's kd-tree kernels.
#pragma once

namespace lancer {

// Measured on the development machine (AMD EPYC VM, 2 cores shared with other jobs, g++ 12,
// Release) with
//   build/<dir>/bench/lancer_bench_micro --benchmark_filter=BM_KdCost --benchmark_repetitions=3
// BM_KdCost builds SAH trees of the 100k-triangle "spheres" scene with C_isect / C_trav
// from 0.25 to 8, traces the same diffuse-bounce rays through each (thread CPU time), counts
// inner-node steps and triangle tests per ray, and fits time = c + C_trav * steps +
// C_isect * tests by least squares. Result: about 45 ns per step and 22 ns per test, ratio
// 0.38 to 0.54 over repetitions (in place, so cache misses on nodes count as traversal
// cost); the trees built with ratios 0.25 and 0.5 also traced fastest. Only the ratio
// matters to the SAH, so the step is 1 and the test 0.5.
inline constexpr float kKdTraversalCost = 1.0f;
inline constexpr float kKdIntersectionCost = 0.5f;

// Wald & Havran's empty-space bonus: a split with one empty side costs 0.8 of the formula.
inline constexpr float kKdEmptySpaceFactor = 0.8f;

}  // namespace lancer
