// What the batch solvers written in GCC's vector extensions share (the ray origins,
// accel/ray_offset_batch-inl.h; the hits' geometry, render/surface_batch-inl.h): vectors of
// LANCER_BATCH_LANES doubles, and of as many floats and integers, with their loads, stores,
// conversions and the lane-wise std functions they stand for, exactly as std computes them.
// A per-ISA translation unit defines LANCER_ISA and LANCER_BATCH_LANES, includes its ISA's
// vector header, then the kernel, which includes this one; everything here lives in
// lancer::LANCER_ISA::batch_lanes and is built with that ISA's flags only.
#pragma once

#include "simd/isa_namespace.h"

#include <cstdint>

#ifndef LANCER_BATCH_LANES
#error "Define LANCER_BATCH_LANES (doubles per vector) before including a batch solver."
#endif

namespace lancer::LANCER_ISA::batch_lanes {

constexpr int N = LANCER_BATCH_LANES;
typedef double vd __attribute__((vector_size(8 * N)));
typedef float vf __attribute__((vector_size(4 * N)));
typedef std::int64_t vl __attribute__((vector_size(8 * N)));
typedef std::int32_t vi __attribute__((vector_size(4 * N)));

inline vd load(const double* p) {
  vd v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
inline vf load(const float* p) {
  vf v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
inline vi load(const std::int32_t* p) {
  vi v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
inline void store(float* p, vf v) { __builtin_memcpy(p, &v, sizeof v); }
inline void store(std::int32_t* p, vi v) { __builtin_memcpy(p, &v, sizeof v); }

inline vd to_double(vf v) { return __builtin_convertvector(v, vd); }
inline vf to_float(vd v) { return __builtin_convertvector(v, vf); }

// std::isfinite.
inline vl finite(vd v) { return (v - v) == 0.0; }
inline vi finite(vf v) { return (v - v) == 0.0f; }

// The square root of each lane, correctly rounded (as std::sqrt).
inline vd sqrt(vd v) {
  for (int i = 0; i < N; ++i) v[i] = __builtin_sqrt(v[i]);
  return v;
}
inline vf sqrt(vf v) {
  for (int i = 0; i < N; ++i) v[i] = __builtin_sqrtf(v[i]);
  return v;
}

// A solver's lanes [0, count), a vector at a time: solve_vector(o, valid) solves the vector
// at offset o, whose first `valid` lanes are in use, and returns bit i for its lane i when it
// computed it. Bit l of the result is lane l's.
template <class SolveVector>
inline std::uint64_t solve_lanes(int count, SolveVector solve_vector) {
  std::uint64_t done = 0;
  for (int o = 0; o < count; o += N) {
    const int valid = count - o < N ? count - o : N;
    const std::uint64_t bits = solve_vector(o, valid);
    const std::uint64_t mask = valid == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << valid) - 1;
    done |= (bits & mask) << o;
  }
  return done;
}

}  // namespace lancer::LANCER_ISA::batch_lanes
