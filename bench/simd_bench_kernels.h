// The SIMD-primitive micro-benchmark kernels (BM_Simd/<isa>/<op>): the data they read, the
// table each ISA fills, and its declarations. Declarations only: nothing here is compiled
// with ISA flags. The kernels are templates in simd_bench-inl.h, instantiated once per ISA
// (simd_bench_scalar.cpp, _sse4.cpp, _avx2.cpp, _avx512.cpp); the timing loops, the scalar
// reference and the checks are generic code (simd_bench.cpp, simd_bench_reference.cpp).
//
// Two shapes of kernel, so that each measures throughput rather than latency:
//  - chain kernels (add, mul, fma, div, rcp, sqrt) keep kSimdChains independent vector
//    accumulators in registers and apply the operation kSimdSteps times to each; the
//    chains start from x[0 .. kSimdChains * N) and their final values go to out[0 ..).
//  - stream kernels (minmax, cmp_movemask, select, reduce_add, load_store, gather) walk the
//    L1-resident buffers of kSimdLength floats `passes` times, one vector per step, spread
//    over kSimdChains independent accumulators.
#pragma once

#include <cstdint>

#include "simd/isa.h"

namespace lancer::bench {

inline constexpr int kSimdChains = 8;     // independent accumulators: enough to hide latency
inline constexpr int kSimdSteps = 256;    // steps per chain and call (chain kernels)
inline constexpr int kSimdLength = 2048;  // floats per buffer (8 KiB): a kernel's buffers stay in L1

// The kernels' inputs (all buffers 64-byte aligned, kSimdLength entries). The constants
// sit in memory so the compiler cannot fold a kernel into its result.
struct SimdInputs {
  const float* x;              // in [1, 2): chain starts, min/max, compare, select, copy
  const float* y;              // in [1, 2): select's second operand
  const float* ints;           // whole numbers in [0, 1024): exact sums in any order
  const std::int32_t* index;   // in [0, kSimdLength): gather indices into ints
  int passes;                  // stream kernels: passes over the buffers per call
  float add_c;                 // add:  v = v + add_c
  float mul_c;                 // mul:  v = v * mul_c
  float fma_m, fma_c;          // fma:  v = v * fma_m + fma_c, rounded once
  float div_c;                 // div:  v = v / div_c
  float sqrt_c;                // sqrt: v = sqrt(v) * sqrt_c
  float threshold;             // cmp_movemask and select: x < threshold
};

// One call does one benchmark iteration's work. Chain and stream kernels write their
// vector results to `out` (kSimdLength floats, 64-byte aligned; layouts in
// simd_bench-inl.h); cmp_movemask, reduce_add return their scalar result (whole numbers
// below 2^24, exact), the others 0.
using SimdKernel = double (*)(const SimdInputs& in, float* out);

enum class SimdOp { Add, Mul, Fma, Div, Rcp, Sqrt, MinMax, CmpMovemask, Select, ReduceAdd, LoadStore, Gather };
inline constexpr int kSimdOpCount = 12;

struct SimdKernels {
  Isa isa;
  int width;                      // floats per vector: 1, 4, 8 or 16
  float rcp_max_rel_error;        // the ISA's bound for one rcp (kRcpMaxRelError)
  SimdKernel op[kSimdOpCount];    // indexed by SimdOp; nullptr: not measured at this width
};

}  // namespace lancer::bench

// One table per ISA, each defined in its own translation unit.
namespace lancer::scalar {
bench::SimdKernels simd_bench_kernels();
}
#if defined(__x86_64__) || defined(_M_X64)
namespace lancer::sse4 {
bench::SimdKernels simd_bench_kernels();
}
namespace lancer::avx2 {
bench::SimdKernels simd_bench_kernels();
}
namespace lancer::avx512 {
bench::SimdKernels simd_bench_kernels();
}
#endif
