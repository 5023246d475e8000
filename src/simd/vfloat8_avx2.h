// Width 8 on AVX2 + FMA: vfloat8, vint8 and vbool8 in lancer::avx2.
//
// Same groups of operations, in the same order, as vfloat1_scalar.h, vfloat4_sse4.h and
// vfloat16_avx512.h; the semantics shared by all widths are listed at the top of
// vfloat4_sse4.h. Here fmadd/fmsub/fnmadd are the FMA instructions (one rounding, bitwise
// equal to the scalar std::fma), masked loads/stores use vmaskmov (inactive lanes never
// fault) and gathers are native.
#pragma once

#if !(defined(__x86_64__) || defined(_M_X64))
#error "vfloat8_avx2.h is x86-64 only; other machines use the scalar path (vfloat1_scalar.h)."
#endif
#if !defined(__AVX2__) || !defined(__FMA__) || defined(__AVX512F__)
// Built with AVX-512 flags, these inline functions would collide with the AVX2 copies at
// link time (the ODR trap); built without AVX2 + FMA they would not compile.
#error "vfloat8_avx2.h needs -mavx2 -mfma and no AVX-512 flags: include it only from AVX2 translation units."
#endif

#include <immintrin.h>

#include <cstdint>

#include "simd/simd_types.h"

namespace lancer::avx2 {

// ---- Types ----------------------------------------------------------------------------
struct vbool8 {
  static constexpr int size = 8;
  __m256 v;  // each lane all ones (true) or all zeros (false)

  vbool8() = default;
  explicit vbool8(__m256 m) : v(m) {}
  vbool8(bool b) : v(_mm256_castsi256_ps(_mm256_set1_epi32(b ? -1 : 0))) {}
  bool operator[](int i) const { return ((_mm256_movemask_ps(v) >> i) & 1) != 0; }
};

struct vint8 {
  static constexpr int size = 8;
  __m256i v;

  vint8() = default;
  explicit vint8(__m256i x) : v(x) {}
  vint8(std::int32_t a) : v(_mm256_set1_epi32(a)) {}  // broadcast
  vint8(float) = delete;                               // no silent float -> int truncation
  vint8(double) = delete;
  std::int32_t operator[](int i) const {
    alignas(32) std::int32_t t[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(t), v);
    return t[i];
  }
};

struct vfloat8 {
  static constexpr int size = 8;
  __m256 v;

  vfloat8() = default;
  explicit vfloat8(__m256 x) : v(x) {}
  vfloat8(float a) : v(_mm256_set1_ps(a)) {}  // broadcast
  float operator[](int i) const {
    alignas(32) float t[8];
    _mm256_store_ps(t, v);
    return t[i];
  }
};

template <>
struct vtypes<8> {
  using Float = vfloat8;
  using Int = vint8;
  using Bool = vbool8;
  static constexpr int size = 8;
};
static_assert(vfloat<8>::size == 8 && vint<8>::size == 8 && vbool<8>::size == 8);
static_assert(sizeof(vfloat8) == 32 && sizeof(vint8) == 32 && sizeof(vbool8) == 32);

// Max relative error of rcp and rsqrt (estimate + one Newton-Raphson step) for normal
// inputs with normal results: as for SSE4 (1.3e-7 and 2.0e-7 from the squared estimate
// error), with one rounding fewer thanks to FMA; tests measure all mantissas.
inline constexpr float kRcpMaxRelError = 2.0e-7f;
inline constexpr float kRsqrtMaxRelError = 3.0e-7f;

// ---- Factories ------------------------------------------------------------------------
// Lanes [0, count) on; count is clamped to [0, 8].
inline vbool8 first_lanes(Lanes<8>, int count) {
  return vbool8(_mm256_castsi256_ps(
      _mm256_cmpgt_epi32(_mm256_set1_epi32(count), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7))));
}
// Lane i is bit i of bits (the inverse of movemask).
inline vbool8 mask_from_bits(Lanes<8>, int bits) {
  const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return vbool8(_mm256_castsi256_ps(
      _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(bits), lane_bit), lane_bit)));
}

// ---- Loads and stores (load/store: 32-byte aligned; loadu/storeu: any address) ---------
inline vfloat8 load(Lanes<8>, const float* p) { return vfloat8(_mm256_load_ps(p)); }
inline vfloat8 loadu(Lanes<8>, const float* p) { return vfloat8(_mm256_loadu_ps(p)); }
inline vint8 load(Lanes<8>, const std::int32_t* p) {
  return vint8(_mm256_load_si256(reinterpret_cast<const __m256i*>(p)));
}
inline vint8 loadu(Lanes<8>, const std::int32_t* p) {
  return vint8(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)));
}
inline void store(float* p, vfloat8 a) { _mm256_store_ps(p, a.v); }
inline void storeu(float* p, vfloat8 a) { _mm256_storeu_ps(p, a.v); }
inline void store(std::int32_t* p, vint8 a) { _mm256_store_si256(reinterpret_cast<__m256i*>(p), a.v); }
inline void storeu(std::int32_t* p, vint8 a) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), a.v); }

// Masked (any address): vmaskmov suppresses faults on inactive lanes.
inline vfloat8 load(vbool8 m, const float* p) { return vfloat8(_mm256_maskload_ps(p, _mm256_castps_si256(m.v))); }
inline vint8 load(vbool8 m, const std::int32_t* p) {
  return vint8(_mm256_maskload_epi32(p, _mm256_castps_si256(m.v)));
}
inline void store(vbool8 m, float* p, vfloat8 a) { _mm256_maskstore_ps(p, _mm256_castps_si256(m.v), a.v); }
inline void store(vbool8 m, std::int32_t* p, vint8 a) {
  _mm256_maskstore_epi32(p, _mm256_castps_si256(m.v), a.v);
}

// ---- Unary ----------------------------------------------------------------------------
inline vfloat8 operator-(vfloat8 a) { return vfloat8(_mm256_xor_ps(a.v, _mm256_set1_ps(-0.0f))); }
inline vfloat8 abs(vfloat8 a) { return vfloat8(_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)); }
inline vfloat8 sqrt(vfloat8 a) { return vfloat8(_mm256_sqrt_ps(a.v)); }

// 1/a: rcpps estimate x, then x' = x + x(1 - a x) (Newton-Raphson, squares the error).
// For a = ±0 or ±inf the step gives NaN (0 * inf); the estimate is exact there, so keep it.
inline vfloat8 rcp(vfloat8 a) {
  const __m256 x = _mm256_rcp_ps(a.v);
  const __m256 e = _mm256_fnmadd_ps(a.v, x, _mm256_set1_ps(1.0f));
  const __m256 refined = _mm256_fmadd_ps(x, e, x);
  return vfloat8(_mm256_blendv_ps(refined, x, _mm256_cmp_ps(refined, refined, _CMP_UNORD_Q)));
}
// 1/sqrt(a): rsqrtps estimate x, then x' = x (1.5 - 0.5 a x^2); special cases as for rcp.
inline vfloat8 rsqrt(vfloat8 a) {
  const __m256 x = _mm256_rsqrt_ps(a.v);
  const __m256 half_a_x = _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(0.5f), a.v), x);
  const __m256 refined = _mm256_mul_ps(x, _mm256_fnmadd_ps(half_a_x, x, _mm256_set1_ps(1.5f)));
  return vfloat8(_mm256_blendv_ps(refined, x, _mm256_cmp_ps(refined, refined, _CMP_UNORD_Q)));
}

// ---- Binary ---------------------------------------------------------------------------
inline vfloat8 operator+(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_add_ps(a.v, b.v)); }
inline vfloat8 operator-(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_sub_ps(a.v, b.v)); }
inline vfloat8 operator*(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_mul_ps(a.v, b.v)); }
inline vfloat8 operator/(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_div_ps(a.v, b.v)); }
inline vfloat8 min(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_min_ps(a.v, b.v)); }
inline vfloat8 max(vfloat8 a, vfloat8 b) { return vfloat8(_mm256_max_ps(a.v, b.v)); }

// ---- Fused multiply-add (one rounding) ------------------------------------------------
inline vfloat8 fmadd(vfloat8 a, vfloat8 b, vfloat8 c) { return vfloat8(_mm256_fmadd_ps(a.v, b.v, c.v)); }
inline vfloat8 fmsub(vfloat8 a, vfloat8 b, vfloat8 c) { return vfloat8(_mm256_fmsub_ps(a.v, b.v, c.v)); }
inline vfloat8 fnmadd(vfloat8 a, vfloat8 b, vfloat8 c) { return vfloat8(_mm256_fnmadd_ps(a.v, b.v, c.v)); }

// ---- Comparisons (ordered, except != which is true with NaN) ---------------------------
inline vbool8 operator<(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)); }
inline vbool8 operator<=(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)); }
inline vbool8 operator>(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)); }
inline vbool8 operator>=(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)); }
inline vbool8 operator==(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)); }
inline vbool8 operator!=(vfloat8 a, vfloat8 b) { return vbool8(_mm256_cmp_ps(a.v, b.v, _CMP_NEQ_UQ)); }

// ---- Mask logic -----------------------------------------------------------------------
inline vbool8 operator&(vbool8 a, vbool8 b) { return vbool8(_mm256_and_ps(a.v, b.v)); }
inline vbool8 operator|(vbool8 a, vbool8 b) { return vbool8(_mm256_or_ps(a.v, b.v)); }
inline vbool8 operator^(vbool8 a, vbool8 b) { return vbool8(_mm256_xor_ps(a.v, b.v)); }
inline vbool8 operator!(vbool8 a) {
  return vbool8(_mm256_xor_ps(a.v, _mm256_castsi256_ps(_mm256_set1_epi32(-1))));
}
inline vbool8 andnot(vbool8 a, vbool8 b) { return vbool8(_mm256_andnot_ps(b.v, a.v)); }  // a and not b

// ---- Select: m ? a : b per lane -------------------------------------------------------
inline vfloat8 select(vbool8 m, vfloat8 a, vfloat8 b) { return vfloat8(_mm256_blendv_ps(b.v, a.v, m.v)); }
inline vint8 select(vbool8 m, vint8 a, vint8 b) {
  return vint8(_mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(b.v), _mm256_castsi256_ps(a.v), m.v)));
}

// ---- Reductions -----------------------------------------------------------------------
inline int movemask(vbool8 m) { return _mm256_movemask_ps(m.v); }  // lane i -> bit i
inline bool any(vbool8 m) { return movemask(m) != 0; }
inline bool all(vbool8 m) { return movemask(m) == 0xFF; }
inline bool none(vbool8 m) { return movemask(m) == 0; }
inline int popcount(vbool8 m) { return __builtin_popcount(static_cast<unsigned>(movemask(m))); }

namespace detail {
// Pairwise tree: the two 128-bit halves first, then op(op(t0, t2), op(t1, t3)).
template <typename Op>
inline __m128 reduce8(__m256 a, Op op) {
  const __m128 halves = op(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
  const __m128 pairs = op(halves, _mm_movehl_ps(halves, halves));
  return op(pairs, _mm_shuffle_ps(pairs, pairs, _MM_SHUFFLE(1, 1, 1, 1)));
}
}  // namespace detail

inline float reduce_add(vfloat8 a) {
  return _mm_cvtss_f32(detail::reduce8(a.v, [](__m128 x, __m128 y) { return _mm_add_ps(x, y); }));
}
inline float reduce_min(vfloat8 a) {
  return _mm_cvtss_f32(detail::reduce8(a.v, [](__m128 x, __m128 y) { return _mm_min_ps(x, y); }));
}
inline float reduce_max(vfloat8 a) {
  return _mm_cvtss_f32(detail::reduce8(a.v, [](__m128 x, __m128 y) { return _mm_max_ps(x, y); }));
}

// ---- Int ops --------------------------------------------------------------------------
inline vint8 operator-(vint8 a) { return vint8(_mm256_sub_epi32(_mm256_setzero_si256(), a.v)); }
inline vint8 operator+(vint8 a, vint8 b) { return vint8(_mm256_add_epi32(a.v, b.v)); }
inline vint8 operator-(vint8 a, vint8 b) { return vint8(_mm256_sub_epi32(a.v, b.v)); }
inline vint8 operator*(vint8 a, vint8 b) { return vint8(_mm256_mullo_epi32(a.v, b.v)); }  // low 32 bits
inline vint8 operator&(vint8 a, vint8 b) { return vint8(_mm256_and_si256(a.v, b.v)); }
inline vint8 operator|(vint8 a, vint8 b) { return vint8(_mm256_or_si256(a.v, b.v)); }
inline vint8 operator^(vint8 a, vint8 b) { return vint8(_mm256_xor_si256(a.v, b.v)); }
inline vint8 andnot(vint8 a, vint8 b) { return vint8(_mm256_andnot_si256(b.v, a.v)); }  // a and not b
inline vint8 operator<<(vint8 a, int count) { return vint8(_mm256_sll_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint8 operator>>(vint8 a, int count) { return vint8(_mm256_sra_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint8 srl(vint8 a, int count) { return vint8(_mm256_srl_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint8 min(vint8 a, vint8 b) { return vint8(_mm256_min_epi32(a.v, b.v)); }
inline vint8 max(vint8 a, vint8 b) { return vint8(_mm256_max_epi32(a.v, b.v)); }

inline vbool8 operator<(vint8 a, vint8 b) { return vbool8(_mm256_castsi256_ps(_mm256_cmpgt_epi32(b.v, a.v))); }
inline vbool8 operator>(vint8 a, vint8 b) { return vbool8(_mm256_castsi256_ps(_mm256_cmpgt_epi32(a.v, b.v))); }
inline vbool8 operator==(vint8 a, vint8 b) { return vbool8(_mm256_castsi256_ps(_mm256_cmpeq_epi32(a.v, b.v))); }
inline vbool8 operator<=(vint8 a, vint8 b) { return !(a > b); }
inline vbool8 operator>=(vint8 a, vint8 b) { return !(a < b); }
inline vbool8 operator!=(vint8 a, vint8 b) { return !(a == b); }

namespace detail {
template <typename Op>
inline __m128i reduce8i(__m256i a, Op op) {
  const __m128i halves = op(_mm256_castsi256_si128(a), _mm256_extracti128_si256(a, 1));
  const __m128i pairs = op(halves, _mm_shuffle_epi32(halves, _MM_SHUFFLE(1, 0, 3, 2)));
  return op(pairs, _mm_shuffle_epi32(pairs, _MM_SHUFFLE(2, 3, 0, 1)));
}
}  // namespace detail

inline std::int32_t reduce_add(vint8 a) {
  return _mm_cvtsi128_si32(detail::reduce8i(a.v, [](__m128i x, __m128i y) { return _mm_add_epi32(x, y); }));
}
inline std::int32_t reduce_min(vint8 a) {
  return _mm_cvtsi128_si32(detail::reduce8i(a.v, [](__m128i x, __m128i y) { return _mm_min_epi32(x, y); }));
}
inline std::int32_t reduce_max(vint8 a) {
  return _mm_cvtsi128_si32(detail::reduce8i(a.v, [](__m128i x, __m128i y) { return _mm_max_epi32(x, y); }));
}

// ---- Gathers: lane i reads base[index[i]]; masked-off lanes read 0, never dereferenced ---
inline vfloat8 gather(const float* base, vint8 index) { return vfloat8(_mm256_i32gather_ps(base, index.v, 4)); }
inline vfloat8 gather(vbool8 m, const float* base, vint8 index) {
  return vfloat8(_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, index.v, m.v, 4));
}
inline vint8 gather(const std::int32_t* base, vint8 index) {
  return vint8(_mm256_i32gather_epi32(base, index.v, 4));
}
inline vint8 gather(vbool8 m, const std::int32_t* base, vint8 index) {
  return vint8(_mm256_mask_i32gather_epi32(_mm256_setzero_si256(), base, index.v, _mm256_castps_si256(m.v), 4));
}

// ---- Conversions (NaN and out-of-range floats give INT32_MIN) and bitcasts --------------
inline vfloat8 to_float(vint8 a) { return vfloat8(_mm256_cvtepi32_ps(a.v)); }
inline vint8 truncate_to_int(vfloat8 a) { return vint8(_mm256_cvttps_epi32(a.v)); }
inline vint8 round_to_int(vfloat8 a) { return vint8(_mm256_cvtps_epi32(a.v)); }  // nearest even (MXCSR default)
inline vint8 as_int(vfloat8 a) { return vint8(_mm256_castps_si256(a.v)); }
inline vfloat8 as_float(vint8 a) { return vfloat8(_mm256_castsi256_ps(a.v)); }

}  // namespace lancer::avx2
