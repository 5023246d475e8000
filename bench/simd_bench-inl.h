// The SIMD-primitive benchmark kernels, as templates over the width N, compiled once per
// ISA inside namespace lancer::LANCER_ISA by simd_bench_<isa>.cpp (see
// simd_bench_kernels.h for the data and the two kernel shapes). They use only the SIMD
// layer's wrappers of their own namespace and the built-in operators, never an inline
// function of namespace lancer or std (the ODR trap, see simd_types.h).
//
// What one "item" (one float of items/s) is, per kernel:
//   add, mul, div      one lane of one add, mul or div instruction
//   fma                one lane of one fused multiply-add (AVX2 and AVX-512 only: SSE4 and
//                      the scalar build have no FMA instruction; their fmadd is two
//                      operations or a libm call, which would measure something else)
//   rcp                one lane of rcp(): the estimate plus one Newton-Raphson step, as
//                      the kernels use it (the scalar build's rcp is a division)
//   sqrt               one lane of sqrt, plus the multiply that keeps the chain moving
//   minmax             one float folded into a running min and a running max (bounds)
//   cmp_movemask       one float compared, its vector's mask moved to a general register
//                      and added to a counter
//   select             one float chosen between two loaded vectors by a compare, stored
//   reduce_add         one float summed by a horizontal reduction of its vector
//   load_store         one float copied with an aligned load and an aligned store
//   gather             one float gathered by index and added to an accumulator
// Chain kernels are bound by the operation's throughput, not its latency: kSimdChains
// independent chains are enough to cover latencies up to eight times the reciprocal
// throughput (all of these on current x86 cores).
#pragma once

#include "simd/isa_namespace.h"

#include <cstdint>

#include "simd_bench_kernels.h"

namespace lancer::LANCER_ISA {
namespace simd_bench {

using bench::kSimdChains;
using bench::kSimdLength;
using bench::kSimdSteps;
using bench::SimdInputs;

// Runs kSimdChains independent chains v = step(v), kSimdSteps times each; chain k starts
// from in.x[k N .. k N + N) and ends in out[k N .. k N + N).
template <int N, typename Step>
inline void run_chains(const SimdInputs& in, float* out, Step step) {
  const Lanes<N> w;
  vfloat<N> v[kSimdChains];
#pragma GCC unroll 8
  for (int k = 0; k < kSimdChains; ++k) v[k] = load(w, in.x + k * N);
  for (int s = 0; s < kSimdSteps; ++s) {
#pragma GCC unroll 8
    for (int k = 0; k < kSimdChains; ++k) v[k] = step(v[k]);
  }
#pragma GCC unroll 8
  for (int k = 0; k < kSimdChains; ++k) store(out + k * N, v[k]);
}

template <int N>
double add_kernel(const SimdInputs& in, float* out) {
  const vfloat<N> c(in.add_c);
  run_chains<N>(in, out, [c](vfloat<N> v) { return v + c; });
  return 0.0;
}

template <int N>
double mul_kernel(const SimdInputs& in, float* out) {
  const vfloat<N> c(in.mul_c);
  run_chains<N>(in, out, [c](vfloat<N> v) { return v * c; });
  return 0.0;
}

template <int N>
double fma_kernel(const SimdInputs& in, float* out) {
  const vfloat<N> m(in.fma_m), c(in.fma_c);
  run_chains<N>(in, out, [m, c](vfloat<N> v) { return fmadd(v, m, c); });
  return 0.0;
}

template <int N>
double div_kernel(const SimdInputs& in, float* out) {
  const vfloat<N> c(in.div_c);
  run_chains<N>(in, out, [c](vfloat<N> v) { return v / c; });
  return 0.0;
}

template <int N>
double rcp_kernel(const SimdInputs& in, float* out) {
  run_chains<N>(in, out, [](vfloat<N> v) { return rcp(v); });  // rcp(rcp(x)) ~ x: stays in range
  return 0.0;
}

template <int N>
double sqrt_kernel(const SimdInputs& in, float* out) {
  const vfloat<N> c(in.sqrt_c);
  run_chains<N>(in, out, [c](vfloat<N> v) { return sqrt(v) * c; });  // tends to c^2
  return 0.0;
}

// Running bounds of x: kSimdChains / 2 (min, max) pairs, vector i of x folded into pair
// i % (kSimdChains / 2). out[p N ..] holds pair p's min, out[(kSimdChains / 2 + p) N ..]
// its max.
template <int N>
double minmax_kernel(const SimdInputs& in, float* out) {
  constexpr int kPairs = kSimdChains / 2;
  const Lanes<N> w;
  vfloat<N> lo[kPairs], hi[kPairs];
#pragma GCC unroll 8
  for (int k = 0; k < kPairs; ++k) lo[k] = hi[k] = load(w, in.x + k * N);
  for (int p = 0; p < in.passes; ++p)
    for (int j = 0; j < kSimdLength; j += kPairs * N) {
#pragma GCC unroll 8
      for (int k = 0; k < kPairs; ++k) {
        const vfloat<N> v = load(w, in.x + j + k * N);
        lo[k] = min(lo[k], v);
        hi[k] = max(hi[k], v);
      }
    }
#pragma GCC unroll 8
  for (int k = 0; k < kPairs; ++k) {
    store(out + k * N, lo[k]);
    store(out + (kPairs + k) * N, hi[k]);
  }
  return 0.0;
}

// Sum over passes and vectors of movemask(x < threshold) (lane i is bit i).
template <int N>
double cmp_movemask_kernel(const SimdInputs& in, float*) {
  const Lanes<N> w;
  const vfloat<N> t(in.threshold);
  std::int32_t count[kSimdChains] = {};
  for (int p = 0; p < in.passes; ++p)
    for (int j = 0; j < kSimdLength; j += kSimdChains * N) {
#pragma GCC unroll 8
      for (int k = 0; k < kSimdChains; ++k) count[k] += movemask(load(w, in.x + j + k * N) < t);
    }
  std::int32_t total = 0;
  for (int k = 0; k < kSimdChains; ++k) total += count[k];
  return double(total);
}

// out[i] = x[i] < threshold ? x[i] : y[i].
template <int N>
double select_kernel(const SimdInputs& in, float* out) {
  const Lanes<N> w;
  const vfloat<N> t(in.threshold);
  for (int p = 0; p < in.passes; ++p) {
#pragma GCC unroll 8
    for (int j = 0; j < kSimdLength; j += N) {
      const vfloat<N> a = load(w, in.x + j), b = load(w, in.y + j);
      store(out + j, select(a < t, a, b));
    }
  }
  return 0.0;
}

// passes * (sum of ints), one horizontal reduction per vector.
template <int N>
double reduce_add_kernel(const SimdInputs& in, float*) {
  const Lanes<N> w;
  float sum[kSimdChains] = {};
  for (int p = 0; p < in.passes; ++p)
    for (int j = 0; j < kSimdLength; j += kSimdChains * N) {
#pragma GCC unroll 8
      for (int k = 0; k < kSimdChains; ++k) sum[k] += reduce_add(load(w, in.ints + j + k * N));
    }
  float total = 0.0f;
  for (int k = 0; k < kSimdChains; ++k) total += sum[k];
  return double(total);
}

// out = x, with aligned loads and stores.
template <int N>
double load_store_kernel(const SimdInputs& in, float* out) {
  const Lanes<N> w;
  for (int p = 0; p < in.passes; ++p) {
#pragma GCC unroll 8
    for (int j = 0; j < kSimdLength; j += N) store(out + j, load(w, in.x + j));
  }
  return 0.0;
}

// Accumulator k (out[k N ..]) sums ints[index[i]] over the vectors i of index with
// i % kSimdChains == k, once per pass.
template <int N>
double gather_kernel(const SimdInputs& in, float* out) {
  const Lanes<N> w;
  vfloat<N> acc[kSimdChains];
#pragma GCC unroll 8
  for (int k = 0; k < kSimdChains; ++k) acc[k] = vfloat<N>(0.0f);
  for (int p = 0; p < in.passes; ++p)
    for (int j = 0; j < kSimdLength; j += kSimdChains * N) {
#pragma GCC unroll 8
      for (int k = 0; k < kSimdChains; ++k) acc[k] = acc[k] + gather(in.ints, load(w, in.index + j + k * N));
    }
#pragma GCC unroll 8
  for (int k = 0; k < kSimdChains; ++k) store(out + k * N, acc[k]);
  return 0.0;
}

// The table for width N; with_fma: the width has a fused multiply-add instruction.
template <int N, bool with_fma>
bench::SimdKernels make_kernels(Isa isa, float rcp_max_rel_error) {
  static_assert(kSimdLength % (kSimdChains * N) == 0, "whole rounds of vectors");
  bench::SimdKernels t{isa, N, rcp_max_rel_error, {}};
  using bench::SimdOp;
  auto set = [&t](SimdOp op, bench::SimdKernel k) { t.op[static_cast<int>(op)] = k; };
  set(SimdOp::Add, &add_kernel<N>);
  set(SimdOp::Mul, &mul_kernel<N>);
  if constexpr (with_fma) set(SimdOp::Fma, &fma_kernel<N>);
  set(SimdOp::Div, &div_kernel<N>);
  set(SimdOp::Rcp, &rcp_kernel<N>);
  set(SimdOp::Sqrt, &sqrt_kernel<N>);
  set(SimdOp::MinMax, &minmax_kernel<N>);
  set(SimdOp::CmpMovemask, &cmp_movemask_kernel<N>);
  set(SimdOp::Select, &select_kernel<N>);
  set(SimdOp::ReduceAdd, &reduce_add_kernel<N>);
  set(SimdOp::LoadStore, &load_store_kernel<N>);
  set(SimdOp::Gather, &gather_kernel<N>);
  return t;
}

}  // namespace simd_bench
}  // namespace lancer::LANCER_ISA
