// Width 4 on SSE4.2: vfloat4, vint4 and vbool4 in lancer::sse4.
//
// Same groups of operations, in the same order, as vfloat1_scalar.h, vfloat8_avx2.h and
// vfloat16_avx512.h: types, factories, loads/stores, unary, binary, fused multiply-add,
// comparisons, mask logic, select, reductions, int ops, gathers, conversions, bitcasts.
//
// Semantics shared by all widths (tests/simd/vector_ops_*_test.cpp check them per lane
// against the scalar types):
//   min/max return the second operand when either is NaN (minps/maxps).
//   Comparisons are ordered (false with NaN) except !=, which is true with NaN.
//   rcp/rsqrt: hardware estimate plus one Newton-Raphson step; rcp(±0) = ±inf,
//     rcp(±inf) = ±0, rsqrt(+0) = +inf, rsqrt(+inf) = 0. Relative error bound for normal
//     inputs whose result is normal: see kRcpMaxRelError below.
//   Masked loads, stores and gathers never touch memory of inactive lanes; inactive lanes
//     read as 0.
//   reduce_* combine lanes pairwise, so reduce_add may differ from a sequential sum in the
//     last bits; reduce_min/max are unspecified with NaN or with both +0 and -0 present.
//   Int arithmetic wraps; shift counts must be in [0, 31].
// SSE4 only: there is no FMA, so fmadd/fmsub/fnmadd are a*b then +c, rounded twice; their
// results can differ in the last bit from the AVX2, AVX-512 and scalar widths, which round once.
#pragma once

#if !(defined(__x86_64__) || defined(_M_X64))
#error "vfloat4_sse4.h is x86-64 only; other machines use the scalar path (vfloat1_scalar.h)."
#endif
#if !defined(__SSE4_2__) || defined(__AVX__)
// Built with AVX flags, these inline functions would collide with the SSE4 copies at link
// time (the ODR trap); built without SSE4.2 they would not compile.
#error "vfloat4_sse4.h needs -msse4.2 and no AVX flags: include it only from SSE4 translation units."
#endif

#include <immintrin.h>

#include <cstdint>

#include "simd/simd_types.h"

namespace lancer::sse4 {

// ---- Types ----------------------------------------------------------------------------
struct vbool4 {
  static constexpr int size = 4;
  __m128 v;  // each lane all ones (true) or all zeros (false)

  vbool4() = default;
  explicit vbool4(__m128 m) : v(m) {}
  vbool4(bool b) : v(_mm_castsi128_ps(_mm_set1_epi32(b ? -1 : 0))) {}
  bool operator[](int i) const { return ((_mm_movemask_ps(v) >> i) & 1) != 0; }
};

struct vint4 {
  static constexpr int size = 4;
  __m128i v;

  vint4() = default;
  explicit vint4(__m128i x) : v(x) {}
  vint4(std::int32_t a) : v(_mm_set1_epi32(a)) {}  // broadcast
  vint4(float) = delete;                            // no silent float -> int truncation
  vint4(double) = delete;
  std::int32_t operator[](int i) const {
    alignas(16) std::int32_t t[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(t), v);
    return t[i];
  }
};

struct vfloat4 {
  static constexpr int size = 4;
  __m128 v;

  vfloat4() = default;
  explicit vfloat4(__m128 x) : v(x) {}
  vfloat4(float a) : v(_mm_set1_ps(a)) {}  // broadcast
  float operator[](int i) const {
    alignas(16) float t[4];
    _mm_store_ps(t, v);
    return t[i];
  }
};

template <>
struct vtypes<4> {
  using Float = vfloat4;
  using Int = vint4;
  using Bool = vbool4;
  static constexpr int size = 4;
};
static_assert(vfloat<4>::size == 4 && vint<4>::size == 4 && vbool<4>::size == 4);
static_assert(sizeof(vfloat4) == 16 && sizeof(vint4) == 16 && sizeof(vbool4) == 16);

// Max relative error of rcp and rsqrt (estimate + one Newton-Raphson step) for normal
// inputs with normal results: the estimate's 1.5*2^-12 squared (about 1.3e-7 for rcp and
// 2.0e-7 for rsqrt) plus the rounding of the refinement; tests measure all mantissas.
inline constexpr float kRcpMaxRelError = 2.5e-7f;
inline constexpr float kRsqrtMaxRelError = 3.5e-7f;

// ---- Factories ------------------------------------------------------------------------
// Lanes [0, count) on; count is clamped to [0, 4].
inline vbool4 first_lanes(Lanes<4>, int count) {
  return vbool4(_mm_castsi128_ps(_mm_cmpgt_epi32(_mm_set1_epi32(count), _mm_setr_epi32(0, 1, 2, 3))));
}
// Lane i is bit i of bits (the inverse of movemask).
inline vbool4 mask_from_bits(Lanes<4>, int bits) {
  const __m128i lane_bit = _mm_setr_epi32(1, 2, 4, 8);
  return vbool4(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(bits), lane_bit), lane_bit)));
}

// ---- Loads and stores (load/store: 16-byte aligned; loadu/storeu: any address) ---------
inline vfloat4 load(Lanes<4>, const float* p) { return vfloat4(_mm_load_ps(p)); }
inline vfloat4 loadu(Lanes<4>, const float* p) { return vfloat4(_mm_loadu_ps(p)); }
inline vint4 load(Lanes<4>, const std::int32_t* p) {
  return vint4(_mm_load_si128(reinterpret_cast<const __m128i*>(p)));
}
inline vint4 loadu(Lanes<4>, const std::int32_t* p) {
  return vint4(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}
inline void store(float* p, vfloat4 a) { _mm_store_ps(p, a.v); }
inline void storeu(float* p, vfloat4 a) { _mm_storeu_ps(p, a.v); }
inline void store(std::int32_t* p, vint4 a) { _mm_store_si128(reinterpret_cast<__m128i*>(p), a.v); }
inline void storeu(std::int32_t* p, vint4 a) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), a.v); }

// Masked (any address). SSE4 has no masked move that is not a non-temporal store, so these
// touch the active lanes one by one; a full mask takes the plain unaligned path.
inline vfloat4 load(vbool4 m, const float* p) {
  const int bits = _mm_movemask_ps(m.v);
  if (bits == 0xF) return loadu(Lanes<4>{}, p);
  alignas(16) float t[4];
  for (int i = 0; i < 4; ++i) t[i] = ((bits >> i) & 1) ? p[i] : 0.0f;
  return vfloat4(_mm_load_ps(t));
}
inline vint4 load(vbool4 m, const std::int32_t* p) {
  const int bits = _mm_movemask_ps(m.v);
  if (bits == 0xF) return loadu(Lanes<4>{}, p);
  alignas(16) std::int32_t t[4];
  for (int i = 0; i < 4; ++i) t[i] = ((bits >> i) & 1) ? p[i] : 0;
  return vint4(_mm_load_si128(reinterpret_cast<const __m128i*>(t)));
}
inline void store(vbool4 m, float* p, vfloat4 a) {
  const int bits = _mm_movemask_ps(m.v);
  alignas(16) float t[4];
  _mm_store_ps(t, a.v);
  for (int i = 0; i < 4; ++i)
    if ((bits >> i) & 1) p[i] = t[i];
}
inline void store(vbool4 m, std::int32_t* p, vint4 a) {
  const int bits = _mm_movemask_ps(m.v);
  alignas(16) std::int32_t t[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(t), a.v);
  for (int i = 0; i < 4; ++i)
    if ((bits >> i) & 1) p[i] = t[i];
}

// ---- Unary ----------------------------------------------------------------------------
inline vfloat4 operator-(vfloat4 a) { return vfloat4(_mm_xor_ps(a.v, _mm_set1_ps(-0.0f))); }
inline vfloat4 abs(vfloat4 a) { return vfloat4(_mm_andnot_ps(_mm_set1_ps(-0.0f), a.v)); }
inline vfloat4 sqrt(vfloat4 a) { return vfloat4(_mm_sqrt_ps(a.v)); }

// 1/a: rcpps estimate x, then x' = x + x(1 - a x) (Newton-Raphson, squares the error).
// For a = ±0 or ±inf the step gives NaN (0 * inf); the estimate is exact there, so keep it.
inline vfloat4 rcp(vfloat4 a) {
  const __m128 x = _mm_rcp_ps(a.v);
  const __m128 e = _mm_sub_ps(_mm_set1_ps(1.0f), _mm_mul_ps(a.v, x));
  const __m128 refined = _mm_add_ps(x, _mm_mul_ps(x, e));
  return vfloat4(_mm_blendv_ps(refined, x, _mm_cmpunord_ps(refined, refined)));
}
// 1/sqrt(a): rsqrtps estimate x, then x' = x (1.5 - 0.5 a x^2); special cases as for rcp.
inline vfloat4 rsqrt(vfloat4 a) {
  const __m128 x = _mm_rsqrt_ps(a.v);
  const __m128 half_a_x = _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(0.5f), a.v), x);
  const __m128 refined = _mm_mul_ps(x, _mm_sub_ps(_mm_set1_ps(1.5f), _mm_mul_ps(half_a_x, x)));
  return vfloat4(_mm_blendv_ps(refined, x, _mm_cmpunord_ps(refined, refined)));
}

// ---- Binary ---------------------------------------------------------------------------
inline vfloat4 operator+(vfloat4 a, vfloat4 b) { return vfloat4(_mm_add_ps(a.v, b.v)); }
inline vfloat4 operator-(vfloat4 a, vfloat4 b) { return vfloat4(_mm_sub_ps(a.v, b.v)); }
inline vfloat4 operator*(vfloat4 a, vfloat4 b) { return vfloat4(_mm_mul_ps(a.v, b.v)); }
inline vfloat4 operator/(vfloat4 a, vfloat4 b) { return vfloat4(_mm_div_ps(a.v, b.v)); }
inline vfloat4 min(vfloat4 a, vfloat4 b) { return vfloat4(_mm_min_ps(a.v, b.v)); }
inline vfloat4 max(vfloat4 a, vfloat4 b) { return vfloat4(_mm_max_ps(a.v, b.v)); }

// ---- Fused multiply-add (emulated: two roundings, see the top of this file) ------------
inline vfloat4 fmadd(vfloat4 a, vfloat4 b, vfloat4 c) { return a * b + c; }
inline vfloat4 fmsub(vfloat4 a, vfloat4 b, vfloat4 c) { return a * b - c; }
inline vfloat4 fnmadd(vfloat4 a, vfloat4 b, vfloat4 c) { return c - a * b; }

// ---- Comparisons ----------------------------------------------------------------------
inline vbool4 operator<(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmplt_ps(a.v, b.v)); }
inline vbool4 operator<=(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmple_ps(a.v, b.v)); }
inline vbool4 operator>(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmpgt_ps(a.v, b.v)); }
inline vbool4 operator>=(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmpge_ps(a.v, b.v)); }
inline vbool4 operator==(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmpeq_ps(a.v, b.v)); }
inline vbool4 operator!=(vfloat4 a, vfloat4 b) { return vbool4(_mm_cmpneq_ps(a.v, b.v)); }

// ---- Mask logic -----------------------------------------------------------------------
inline vbool4 operator&(vbool4 a, vbool4 b) { return vbool4(_mm_and_ps(a.v, b.v)); }
inline vbool4 operator|(vbool4 a, vbool4 b) { return vbool4(_mm_or_ps(a.v, b.v)); }
inline vbool4 operator^(vbool4 a, vbool4 b) { return vbool4(_mm_xor_ps(a.v, b.v)); }
inline vbool4 operator!(vbool4 a) { return vbool4(_mm_xor_ps(a.v, _mm_castsi128_ps(_mm_set1_epi32(-1)))); }
inline vbool4 andnot(vbool4 a, vbool4 b) { return vbool4(_mm_andnot_ps(b.v, a.v)); }  // a and not b

// ---- Select: m ? a : b per lane -------------------------------------------------------
inline vfloat4 select(vbool4 m, vfloat4 a, vfloat4 b) { return vfloat4(_mm_blendv_ps(b.v, a.v, m.v)); }
inline vint4 select(vbool4 m, vint4 a, vint4 b) {
  return vint4(_mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(b.v), _mm_castsi128_ps(a.v), m.v)));
}

// ---- Reductions -----------------------------------------------------------------------
inline int movemask(vbool4 m) { return _mm_movemask_ps(m.v); }  // lane i -> bit i
inline bool any(vbool4 m) { return movemask(m) != 0; }
inline bool all(vbool4 m) { return movemask(m) == 0xF; }
inline bool none(vbool4 m) { return movemask(m) == 0; }
inline int popcount(vbool4 m) { return __builtin_popcount(static_cast<unsigned>(movemask(m))); }

namespace detail {
// Pairwise tree over the four lanes: op(op(a0, a2), op(a1, a3)).
template <typename Op>
inline __m128 reduce4(__m128 a, Op op) {
  const __m128 pairs = op(a, _mm_movehl_ps(a, a));
  return op(pairs, _mm_shuffle_ps(pairs, pairs, _MM_SHUFFLE(1, 1, 1, 1)));
}
}  // namespace detail

inline float reduce_add(vfloat4 a) {
  return _mm_cvtss_f32(detail::reduce4(a.v, [](__m128 x, __m128 y) { return _mm_add_ps(x, y); }));
}
inline float reduce_min(vfloat4 a) {
  return _mm_cvtss_f32(detail::reduce4(a.v, [](__m128 x, __m128 y) { return _mm_min_ps(x, y); }));
}
inline float reduce_max(vfloat4 a) {
  return _mm_cvtss_f32(detail::reduce4(a.v, [](__m128 x, __m128 y) { return _mm_max_ps(x, y); }));
}

// ---- Int ops --------------------------------------------------------------------------
inline vint4 operator-(vint4 a) { return vint4(_mm_sub_epi32(_mm_setzero_si128(), a.v)); }
inline vint4 operator+(vint4 a, vint4 b) { return vint4(_mm_add_epi32(a.v, b.v)); }
inline vint4 operator-(vint4 a, vint4 b) { return vint4(_mm_sub_epi32(a.v, b.v)); }
inline vint4 operator*(vint4 a, vint4 b) { return vint4(_mm_mullo_epi32(a.v, b.v)); }  // low 32 bits
inline vint4 operator&(vint4 a, vint4 b) { return vint4(_mm_and_si128(a.v, b.v)); }
inline vint4 operator|(vint4 a, vint4 b) { return vint4(_mm_or_si128(a.v, b.v)); }
inline vint4 operator^(vint4 a, vint4 b) { return vint4(_mm_xor_si128(a.v, b.v)); }
inline vint4 andnot(vint4 a, vint4 b) { return vint4(_mm_andnot_si128(b.v, a.v)); }  // a and not b
inline vint4 operator<<(vint4 a, int count) { return vint4(_mm_sll_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint4 operator>>(vint4 a, int count) { return vint4(_mm_sra_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint4 srl(vint4 a, int count) { return vint4(_mm_srl_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint4 min(vint4 a, vint4 b) { return vint4(_mm_min_epi32(a.v, b.v)); }
inline vint4 max(vint4 a, vint4 b) { return vint4(_mm_max_epi32(a.v, b.v)); }

inline vbool4 operator<(vint4 a, vint4 b) { return vbool4(_mm_castsi128_ps(_mm_cmplt_epi32(a.v, b.v))); }
inline vbool4 operator>(vint4 a, vint4 b) { return vbool4(_mm_castsi128_ps(_mm_cmpgt_epi32(a.v, b.v))); }
inline vbool4 operator==(vint4 a, vint4 b) { return vbool4(_mm_castsi128_ps(_mm_cmpeq_epi32(a.v, b.v))); }
inline vbool4 operator<=(vint4 a, vint4 b) { return !(a > b); }
inline vbool4 operator>=(vint4 a, vint4 b) { return !(a < b); }
inline vbool4 operator!=(vint4 a, vint4 b) { return !(a == b); }

namespace detail {
template <typename Op>
inline __m128i reduce4i(__m128i a, Op op) {
  const __m128i pairs = op(a, _mm_shuffle_epi32(a, _MM_SHUFFLE(1, 0, 3, 2)));
  return op(pairs, _mm_shuffle_epi32(pairs, _MM_SHUFFLE(2, 3, 0, 1)));
}
}  // namespace detail

inline std::int32_t reduce_add(vint4 a) {
  return _mm_cvtsi128_si32(detail::reduce4i(a.v, [](__m128i x, __m128i y) { return _mm_add_epi32(x, y); }));
}
inline std::int32_t reduce_min(vint4 a) {
  return _mm_cvtsi128_si32(detail::reduce4i(a.v, [](__m128i x, __m128i y) { return _mm_min_epi32(x, y); }));
}
inline std::int32_t reduce_max(vint4 a) {
  return _mm_cvtsi128_si32(detail::reduce4i(a.v, [](__m128i x, __m128i y) { return _mm_max_epi32(x, y); }));
}

// ---- Gathers: lane i reads base[index[i]] (emulated, SSE4 has no gather) ----------------
inline vfloat4 gather(const float* base, vint4 index) {
  alignas(16) std::int32_t i[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(i), index.v);
  return vfloat4(_mm_setr_ps(base[i[0]], base[i[1]], base[i[2]], base[i[3]]));
}
inline vfloat4 gather(vbool4 m, const float* base, vint4 index) {
  alignas(16) std::int32_t i[4];
  alignas(16) float t[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(i), index.v);
  const int bits = _mm_movemask_ps(m.v);
  for (int k = 0; k < 4; ++k) t[k] = ((bits >> k) & 1) ? base[i[k]] : 0.0f;
  return vfloat4(_mm_load_ps(t));
}
inline vint4 gather(const std::int32_t* base, vint4 index) {
  alignas(16) std::int32_t i[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(i), index.v);
  return vint4(_mm_setr_epi32(base[i[0]], base[i[1]], base[i[2]], base[i[3]]));
}
inline vint4 gather(vbool4 m, const std::int32_t* base, vint4 index) {
  alignas(16) std::int32_t i[4];
  alignas(16) std::int32_t t[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(i), index.v);
  const int bits = _mm_movemask_ps(m.v);
  for (int k = 0; k < 4; ++k) t[k] = ((bits >> k) & 1) ? base[i[k]] : 0;
  return vint4(_mm_load_si128(reinterpret_cast<const __m128i*>(t)));
}

// ---- Conversions (NaN and out-of-range floats give INT32_MIN) and bitcasts --------------
inline vfloat4 to_float(vint4 a) { return vfloat4(_mm_cvtepi32_ps(a.v)); }
inline vint4 truncate_to_int(vfloat4 a) { return vint4(_mm_cvttps_epi32(a.v)); }
inline vint4 round_to_int(vfloat4 a) { return vint4(_mm_cvtps_epi32(a.v)); }  // nearest even (MXCSR default)
inline vint4 as_int(vfloat4 a) { return vint4(_mm_castps_si128(a.v)); }
inline vfloat4 as_float(vint4 a) { return vfloat4(_mm_castsi128_ps(a.v)); }

}  // namespace lancer::sse4
