// Width 16 on AVX-512 (F, VL, BW, DQ): vfloat16, vint16 and vbool16 in lancer::avx512.
//
// Same groups of operations, in the same order, as vfloat1_scalar.h, vfloat4_sse4.h and
// vfloat8_avx2.h; the semantics shared by all widths are listed at the top of
// vfloat4_sse4.h. The mask is an opmask register (__mmask16, lane i = bit i), so movemask
// is free and masked loads, stores and gathers are native (inactive lanes never fault).
// rcp/rsqrt start from the 14-bit estimates (vrcp14ps, vrsqrt14ps), so they are more
// accurate than the SSE4 and AVX2 widths after the same Newton-Raphson step.
#pragma once

#if !(defined(__x86_64__) || defined(_M_X64))
#error "vfloat16_avx512.h is x86-64 only; other machines use the scalar path (vfloat1_scalar.h)."
#endif
#if !defined(__AVX512F__) || !defined(__AVX512VL__) || !defined(__AVX512BW__) || !defined(__AVX512DQ__) || \
    !defined(__FMA__)
#error "vfloat16_avx512.h needs -mavx512f -mavx512vl -mavx512bw -mavx512dq -mfma: include it only from AVX-512 translation units."
#endif

#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
// GCC 12's AVX-512 intrinsics initialise their "undefined" vectors from themselves (GCC bug
// 105593), which -Wmaybe-uninitialized and -Wuninitialized report wherever they are inlined.
// Silence them for the intrinsics header only (this header must be the first to include it
// in the TU).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#else
#include <immintrin.h>
#endif

#include <cstdint>

#include "simd/simd_types.h"

namespace lancer::avx512 {

// ---- Types ----------------------------------------------------------------------------
struct vbool16 {
  static constexpr int size = 16;
  __mmask16 v;  // lane i = bit i

  vbool16() = default;
  explicit vbool16(__mmask16 m) : v(m) {}
  vbool16(bool b) : v(static_cast<__mmask16>(b ? 0xFFFF : 0)) {}
  bool operator[](int i) const { return ((v >> i) & 1) != 0; }
};

struct vint16 {
  static constexpr int size = 16;
  __m512i v;

  vint16() = default;
  explicit vint16(__m512i x) : v(x) {}
  vint16(std::int32_t a) : v(_mm512_set1_epi32(a)) {}  // broadcast
  vint16(float) = delete;                               // no silent float -> int truncation
  vint16(double) = delete;
  std::int32_t operator[](int i) const {
    alignas(64) std::int32_t t[16];
    _mm512_store_si512(t, v);
    return t[i];
  }
};

struct vfloat16 {
  static constexpr int size = 16;
  __m512 v;

  vfloat16() = default;
  explicit vfloat16(__m512 x) : v(x) {}
  vfloat16(float a) : v(_mm512_set1_ps(a)) {}  // broadcast
  float operator[](int i) const {
    alignas(64) float t[16];
    _mm512_store_ps(t, v);
    return t[i];
  }
};

template <>
struct vtypes<16> {
  using Float = vfloat16;
  using Int = vint16;
  using Bool = vbool16;
  static constexpr int size = 16;
};
static_assert(vfloat<16>::size == 16 && vint<16>::size == 16 && vbool<16>::size == 16);
static_assert(sizeof(vfloat16) == 64 && sizeof(vint16) == 64 && sizeof(vbool16) == 2);

// Max relative error of rcp and rsqrt (14-bit estimate + one Newton-Raphson step with FMA)
// for normal inputs with normal results: dominated by the final rounding; tests measure
// all mantissas.
inline constexpr float kRcpMaxRelError = 1.2e-7f;
inline constexpr float kRsqrtMaxRelError = 1.8e-7f;

// ---- Factories ------------------------------------------------------------------------
// Lanes [0, count) on; count is clamped to [0, 16].
inline vbool16 first_lanes(Lanes<16>, int count) {
  if (count <= 0) return vbool16(false);
  if (count >= 16) return vbool16(true);
  return vbool16(static_cast<__mmask16>((1u << count) - 1u));
}
// Lane i is bit i of bits (the inverse of movemask).
inline vbool16 mask_from_bits(Lanes<16>, int bits) { return vbool16(static_cast<__mmask16>(bits & 0xFFFF)); }

// ---- Loads and stores (load/store: 64-byte aligned; loadu/storeu: any address) ---------
inline vfloat16 load(Lanes<16>, const float* p) { return vfloat16(_mm512_load_ps(p)); }
inline vfloat16 loadu(Lanes<16>, const float* p) { return vfloat16(_mm512_loadu_ps(p)); }
inline vint16 load(Lanes<16>, const std::int32_t* p) { return vint16(_mm512_load_si512(p)); }
inline vint16 loadu(Lanes<16>, const std::int32_t* p) { return vint16(_mm512_loadu_si512(p)); }
inline void store(float* p, vfloat16 a) { _mm512_store_ps(p, a.v); }
inline void storeu(float* p, vfloat16 a) { _mm512_storeu_ps(p, a.v); }
inline void store(std::int32_t* p, vint16 a) { _mm512_store_si512(p, a.v); }
inline void storeu(std::int32_t* p, vint16 a) { _mm512_storeu_si512(p, a.v); }

// Masked (any address): inactive lanes are suppressed, so they never fault.
inline vfloat16 load(vbool16 m, const float* p) { return vfloat16(_mm512_maskz_loadu_ps(m.v, p)); }
inline vint16 load(vbool16 m, const std::int32_t* p) { return vint16(_mm512_maskz_loadu_epi32(m.v, p)); }
inline void store(vbool16 m, float* p, vfloat16 a) { _mm512_mask_storeu_ps(p, m.v, a.v); }
inline void store(vbool16 m, std::int32_t* p, vint16 a) { _mm512_mask_storeu_epi32(p, m.v, a.v); }

// ---- Unary ----------------------------------------------------------------------------
inline vfloat16 operator-(vfloat16 a) { return vfloat16(_mm512_xor_ps(a.v, _mm512_set1_ps(-0.0f))); }
inline vfloat16 abs(vfloat16 a) { return vfloat16(_mm512_abs_ps(a.v)); }
inline vfloat16 sqrt(vfloat16 a) { return vfloat16(_mm512_sqrt_ps(a.v)); }

// 1/a: vrcp14ps estimate x, then x' = x + x(1 - a x) (Newton-Raphson, squares the error).
// For a = ±0 or ±inf the step gives NaN (0 * inf); the estimate is exact there, so keep it.
inline vfloat16 rcp(vfloat16 a) {
  const __m512 x = _mm512_rcp14_ps(a.v);
  const __m512 e = _mm512_fnmadd_ps(a.v, x, _mm512_set1_ps(1.0f));
  const __m512 refined = _mm512_fmadd_ps(x, e, x);
  return vfloat16(_mm512_mask_blend_ps(_mm512_cmp_ps_mask(refined, refined, _CMP_UNORD_Q), refined, x));
}
// 1/sqrt(a): vrsqrt14ps estimate x, then x' = x (1.5 - 0.5 a x^2); special cases as for rcp.
inline vfloat16 rsqrt(vfloat16 a) {
  const __m512 x = _mm512_rsqrt14_ps(a.v);
  const __m512 half_a_x = _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(0.5f), a.v), x);
  const __m512 refined = _mm512_mul_ps(x, _mm512_fnmadd_ps(half_a_x, x, _mm512_set1_ps(1.5f)));
  return vfloat16(_mm512_mask_blend_ps(_mm512_cmp_ps_mask(refined, refined, _CMP_UNORD_Q), refined, x));
}

// ---- Binary ---------------------------------------------------------------------------
inline vfloat16 operator+(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_add_ps(a.v, b.v)); }
inline vfloat16 operator-(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_sub_ps(a.v, b.v)); }
inline vfloat16 operator*(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_mul_ps(a.v, b.v)); }
inline vfloat16 operator/(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_div_ps(a.v, b.v)); }
inline vfloat16 min(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_min_ps(a.v, b.v)); }
inline vfloat16 max(vfloat16 a, vfloat16 b) { return vfloat16(_mm512_max_ps(a.v, b.v)); }

// ---- Fused multiply-add (one rounding) ------------------------------------------------
inline vfloat16 fmadd(vfloat16 a, vfloat16 b, vfloat16 c) { return vfloat16(_mm512_fmadd_ps(a.v, b.v, c.v)); }
inline vfloat16 fmsub(vfloat16 a, vfloat16 b, vfloat16 c) { return vfloat16(_mm512_fmsub_ps(a.v, b.v, c.v)); }
inline vfloat16 fnmadd(vfloat16 a, vfloat16 b, vfloat16 c) { return vfloat16(_mm512_fnmadd_ps(a.v, b.v, c.v)); }

// ---- Comparisons (ordered, except != which is true with NaN) ---------------------------
inline vbool16 operator<(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)); }
inline vbool16 operator<=(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)); }
inline vbool16 operator>(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)); }
inline vbool16 operator>=(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ)); }
inline vbool16 operator==(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ)); }
inline vbool16 operator!=(vfloat16 a, vfloat16 b) { return vbool16(_mm512_cmp_ps_mask(a.v, b.v, _CMP_NEQ_UQ)); }

// ---- Mask logic -----------------------------------------------------------------------
inline vbool16 operator&(vbool16 a, vbool16 b) { return vbool16(static_cast<__mmask16>(a.v & b.v)); }
inline vbool16 operator|(vbool16 a, vbool16 b) { return vbool16(static_cast<__mmask16>(a.v | b.v)); }
inline vbool16 operator^(vbool16 a, vbool16 b) { return vbool16(static_cast<__mmask16>(a.v ^ b.v)); }
inline vbool16 operator!(vbool16 a) { return vbool16(static_cast<__mmask16>(~a.v)); }
inline vbool16 andnot(vbool16 a, vbool16 b) { return vbool16(static_cast<__mmask16>(a.v & ~b.v)); }  // a and not b

// ---- Select: m ? a : b per lane -------------------------------------------------------
inline vfloat16 select(vbool16 m, vfloat16 a, vfloat16 b) { return vfloat16(_mm512_mask_blend_ps(m.v, b.v, a.v)); }
inline vint16 select(vbool16 m, vint16 a, vint16 b) { return vint16(_mm512_mask_blend_epi32(m.v, b.v, a.v)); }

// ---- Reductions -----------------------------------------------------------------------
inline int movemask(vbool16 m) { return m.v; }  // lane i -> bit i
inline bool any(vbool16 m) { return m.v != 0; }
inline bool all(vbool16 m) { return m.v == 0xFFFF; }
inline bool none(vbool16 m) { return m.v == 0; }
inline int popcount(vbool16 m) { return __builtin_popcount(m.v); }
// Pairwise trees (the compiler's _mm512_reduce_* sequences).
inline float reduce_add(vfloat16 a) { return _mm512_reduce_add_ps(a.v); }
inline float reduce_min(vfloat16 a) { return _mm512_reduce_min_ps(a.v); }
inline float reduce_max(vfloat16 a) { return _mm512_reduce_max_ps(a.v); }

// ---- Int ops --------------------------------------------------------------------------
inline vint16 operator-(vint16 a) { return vint16(_mm512_sub_epi32(_mm512_setzero_si512(), a.v)); }
inline vint16 operator+(vint16 a, vint16 b) { return vint16(_mm512_add_epi32(a.v, b.v)); }
inline vint16 operator-(vint16 a, vint16 b) { return vint16(_mm512_sub_epi32(a.v, b.v)); }
inline vint16 operator*(vint16 a, vint16 b) { return vint16(_mm512_mullo_epi32(a.v, b.v)); }  // low 32 bits
inline vint16 operator&(vint16 a, vint16 b) { return vint16(_mm512_and_si512(a.v, b.v)); }
inline vint16 operator|(vint16 a, vint16 b) { return vint16(_mm512_or_si512(a.v, b.v)); }
inline vint16 operator^(vint16 a, vint16 b) { return vint16(_mm512_xor_si512(a.v, b.v)); }
inline vint16 andnot(vint16 a, vint16 b) { return vint16(_mm512_andnot_si512(b.v, a.v)); }  // a and not b
inline vint16 operator<<(vint16 a, int count) { return vint16(_mm512_sll_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint16 operator>>(vint16 a, int count) { return vint16(_mm512_sra_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint16 srl(vint16 a, int count) { return vint16(_mm512_srl_epi32(a.v, _mm_cvtsi32_si128(count))); }
inline vint16 min(vint16 a, vint16 b) { return vint16(_mm512_min_epi32(a.v, b.v)); }
inline vint16 max(vint16 a, vint16 b) { return vint16(_mm512_max_epi32(a.v, b.v)); }

inline vbool16 operator<(vint16 a, vint16 b) { return vbool16(_mm512_cmp_epi32_mask(a.v, b.v, _MM_CMPINT_LT)); }
inline vbool16 operator<=(vint16 a, vint16 b) { return vbool16(_mm512_cmp_epi32_mask(a.v, b.v, _MM_CMPINT_LE)); }
inline vbool16 operator>(vint16 a, vint16 b) { return vbool16(_mm512_cmp_epi32_mask(a.v, b.v, _MM_CMPINT_NLE)); }
inline vbool16 operator>=(vint16 a, vint16 b) { return vbool16(_mm512_cmp_epi32_mask(a.v, b.v, _MM_CMPINT_NLT)); }
inline vbool16 operator==(vint16 a, vint16 b) { return vbool16(_mm512_cmp_epi32_mask(a.v, b.v, _MM_CMPINT_EQ)); }
inline vbool16 operator!=(vint16 a, vint16 b) { return vbool16(_mm512_cmp_epi32_mask(a.v, b.v, _MM_CMPINT_NE)); }

// Not _mm512_reduce_add_epi32: GCC implements it with plain int additions, undefined on
// overflow, while the lanes here wrap like every other vint operation.
inline std::int32_t reduce_add(vint16 a) {
  const __m256i s8 = _mm256_add_epi32(_mm512_castsi512_si256(a.v), _mm512_extracti64x4_epi64(a.v, 1));
  __m128i s4 = _mm_add_epi32(_mm256_castsi256_si128(s8), _mm256_extracti128_si256(s8, 1));
  s4 = _mm_add_epi32(s4, _mm_shuffle_epi32(s4, 0x4E));
  s4 = _mm_add_epi32(s4, _mm_shuffle_epi32(s4, 0xB1));
  return _mm_cvtsi128_si32(s4);
}
inline std::int32_t reduce_min(vint16 a) { return _mm512_reduce_min_epi32(a.v); }
inline std::int32_t reduce_max(vint16 a) { return _mm512_reduce_max_epi32(a.v); }

// ---- Gathers: lane i reads base[index[i]]; masked-off lanes read 0, never dereferenced ---
inline vfloat16 gather(const float* base, vint16 index) { return vfloat16(_mm512_i32gather_ps(index.v, base, 4)); }
inline vfloat16 gather(vbool16 m, const float* base, vint16 index) {
  return vfloat16(_mm512_mask_i32gather_ps(_mm512_setzero_ps(), m.v, index.v, base, 4));
}
inline vint16 gather(const std::int32_t* base, vint16 index) {
  return vint16(_mm512_i32gather_epi32(index.v, base, 4));
}
inline vint16 gather(vbool16 m, const std::int32_t* base, vint16 index) {
  return vint16(_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), m.v, index.v, base, 4));
}

// ---- Conversions (NaN and out-of-range floats give INT32_MIN) and bitcasts --------------
inline vfloat16 to_float(vint16 a) { return vfloat16(_mm512_cvtepi32_ps(a.v)); }
inline vint16 truncate_to_int(vfloat16 a) { return vint16(_mm512_cvttps_epi32(a.v)); }
inline vint16 round_to_int(vfloat16 a) { return vint16(_mm512_cvtps_epi32(a.v)); }  // nearest even (MXCSR default)
inline vint16 as_int(vfloat16 a) { return vint16(_mm512_castps_si512(a.v)); }
inline vfloat16 as_float(vint16 a) { return vfloat16(_mm512_castsi512_ps(a.v)); }

}  // namespace lancer::avx512
