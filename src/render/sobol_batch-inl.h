// The batch draw of sobol_batch.h, for one ISA: SobolSampler::get1 and get2 (sobol_sampler.cpp)
// for LANCER_SOBOL_LANES samplers per vector, in GCC's vector extensions. Integer arithmetic
// and one exact conversion: the values are the scalar ones bit for bit.
//
// ODR: everything here lives in lancer::LANCER_ISA and calls no inline function of
// namespace lancer or std (only builtins); the constants are sobol_sampler's, restated.
#pragma once

#include "simd/isa_namespace.h"

#include <cstdint>

#include "render/sobol_batch.h"

#ifndef LANCER_SOBOL_LANES
#error "Define LANCER_SOBOL_LANES (64-bit integers per vector) before including sobol_batch-inl.h."
#endif

namespace lancer::LANCER_ISA {
namespace sobol_lanes {

constexpr int N = LANCER_SOBOL_LANES;
typedef std::uint64_t vu64 __attribute__((vector_size(8 * N)));
typedef std::uint32_t vu32 __attribute__((vector_size(4 * N)));
typedef std::int32_t vi32 __attribute__((vector_size(4 * N)));
typedef float vf __attribute__((vector_size(4 * N)));

constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;

template <class V, class T>
inline V load(const T* p) {
  V v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
inline void store(float* p, vf v) { __builtin_memcpy(p, &v, sizeof v); }

// splitmix64_mix (simd/splitmix64.h).
inline vu64 mix(vu64 z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
// SobolSampler::set_hash.
inline vu64 set_hash(vu32 dim, vu64 key) {
  return mix(key + (__builtin_convertvector(dim, vu64) + 1) * kGolden);
}
inline vu32 low(vu64 v) { return __builtin_convertvector(v, vu32); }
inline vu32 high(vu64 v) { return __builtin_convertvector(v >> 32, vu32); }
// sobol::laine_karras_permutation.
inline vu32 permute(vu32 x, vu32 seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}
// sobol::reverse_bits (the byte swap as two more swap steps).
inline vu32 reverse(vu32 v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
  v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
  return (v >> 16) | (v << 16);
}
// sobol::reversed_sobol_dimension1: four byte tables, looked up lane by lane.
inline vu32 second_dimension(vu32 r, const std::uint32_t* const table[4]) {
  vu32 out;
  for (int i = 0; i < N; ++i)
    out[i] = table[0][r[i] & 0xFFu] ^ table[1][(r[i] >> 8) & 0xFFu] ^ table[2][(r[i] >> 16) & 0xFFu] ^
             table[3][r[i] >> 24];
  return out;
}
// sobol::to_unit_float: the top 24 bits, exactly.
inline vf unit_float(vu32 bits) {
  return __builtin_convertvector((vi32)(bits >> 8), vf) * (1.0f / 16777216.0f);
}

inline void draw_vector(const sobol_batch::Lanes& L, int o, sobol_batch::Out& out) {
  const vu64 shuffle_key = load<vu64>(L.shuffle_key + o), scramble_key = load<vu64>(L.scramble_key + o);
  const vu32 index = load<vu32>(L.reversed_index + o);
  for (int k = 0; k < 2; ++k) {
    {  // get1
      const vu32 dim = load<vu32>(L.dim1[k] + o);
      const vu32 y = permute(index, low(set_hash(dim, shuffle_key)));
      store(out.v1[k] + o, unit_float(reverse(permute(reverse(y), low(set_hash(dim, scramble_key))))));
    }
    {  // get2
      const vu32 dim = load<vu32>(L.dim2[k] + o);
      const vu32 y = permute(index, low(set_hash(dim, shuffle_key)));
      const vu64 scramble = set_hash(dim, scramble_key);
      const vu32 a = permute(reverse(y), low(scramble));
      const vu32 b = permute(second_dimension(y, L.table), high(scramble));
      store(out.v2x[k] + o, unit_float(reverse(a)));
      store(out.v2y[k] + o, unit_float(reverse(b)));
    }
  }
}

}  // namespace sobol_lanes

inline void draw_sobol_lanes_impl(const sobol_batch::Lanes& lanes, int count, sobol_batch::Out& out) {
  for (int o = 0; o < count; o += sobol_lanes::N) sobol_lanes::draw_vector(lanes, o, out);
}

}  // namespace lancer::LANCER_ISA
