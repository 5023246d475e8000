// Width 1 in any ISA's namespace: the "vector" types float, int32_t and bool, and the
// named operations every vector header has, in the same order (factories, loads/stores,
// unary, binary, fused multiply-add, mask logic, select, reductions, int ops, gathers,
// conversions and bitcasts). Arithmetic, comparisons and mask logic are the built-ins.
//
// Why in every ISA: a width-generic kernel template (the ray setup, kd_ray_setup-inl.h) is
// instantiated at width 1 for one ray inside each ISA's namespace, next to its vector
// width. Include this after the ISA's vector header, with LANCER_ISA defined. The types
// specialise vtypes<1> in lancer::LANCER_ISA; the operations live in the nested namespace
// lancer::LANCER_ISA::width1, so that a function instantiated at width 1 brings them in
// with `using namespace width1;` while vector code of the same namespace never sees a float
// overload next to its broadcasting ones. lancer::scalar, where width 1 is the only width,
// brings them in for all its code (vfloat1_scalar.h). They call compiler builtins only, no
// inline function of std, so no copy built with one ISA's flags can stand in for another's.
//
// Semantics chosen to match the x86 instructions lane for lane (tested against them in
// the scalar namespace):
//   min(a, b) = a < b ? a : b and max(a, b) = a > b ? a : b: the second operand when either
//     is NaN or both are zero (minps/maxps).
//   fmadd/fmsub/fnmadd round once (fmaf), like the AVX2 and AVX-512 instructions.
//   truncate_to_int/round_to_int give INT32_MIN for NaN and out-of-range inputs (cvtps2dq's
//     "integer indefinite"); round_to_int rounds to nearest even.
// Differences from the vector types, by design:
//   rcp and rsqrt are exact divisions here (the vectors use an approximation plus one
//     Newton-Raphson step, see their headers for the error bound).
//   Int arithmetic is plain C++: overflow is undefined, where the vectors wrap.
#pragma once

#include "simd/isa_namespace.h"

#include <cstdint>

#include "simd/simd_types.h"

namespace lancer::LANCER_ISA {

template <>
struct vtypes<1> {
  using Float = float;
  using Int = std::int32_t;
  using Bool = bool;
  static constexpr int size = 1;
};
static_assert(vtypes<1>::size == 1);

namespace width1 {

// rcp is one correctly rounded division (half an ulp, 2^-24); rsqrt rounds twice.
inline constexpr float kRcpMaxRelError = 6.0e-8f;
inline constexpr float kRsqrtMaxRelError = 1.2e-7f;

// ---- Factories ------------------------------------------------------------------------
// Lanes [0, count) on; count is clamped to [0, 1].
inline bool first_lanes(Lanes<1>, int count) { return count >= 1; }
// Lane i is bit i of bits.
inline bool mask_from_bits(Lanes<1>, int bits) { return (bits & 1) != 0; }

// ---- Loads and stores (masked: off lanes read as 0 and are not touched) ----------------
inline float load(Lanes<1>, const float* p) { return *p; }
inline float loadu(Lanes<1>, const float* p) { return *p; }
inline float load(bool m, const float* p) { return m ? *p : 0.0f; }
inline std::int32_t load(Lanes<1>, const std::int32_t* p) { return *p; }
inline std::int32_t loadu(Lanes<1>, const std::int32_t* p) { return *p; }
inline std::int32_t load(bool m, const std::int32_t* p) { return m ? *p : 0; }

inline void store(float* p, float v) { *p = v; }
inline void storeu(float* p, float v) { *p = v; }
inline void store(bool m, float* p, float v) {
  if (m) *p = v;
}
inline void store(std::int32_t* p, std::int32_t v) { *p = v; }
inline void storeu(std::int32_t* p, std::int32_t v) { *p = v; }
inline void store(bool m, std::int32_t* p, std::int32_t v) {
  if (m) *p = v;
}

// ---- Unary ----------------------------------------------------------------------------
inline float abs(float a) { return __builtin_fabsf(a); }
inline float sqrt(float a) { return __builtin_sqrtf(a); }
inline float rcp(float a) { return 1.0f / a; }
inline float rsqrt(float a) { return 1.0f / __builtin_sqrtf(a); }

// ---- Binary ---------------------------------------------------------------------------
inline float min(float a, float b) { return a < b ? a : b; }
inline float max(float a, float b) { return a > b ? a : b; }

// ---- Fused multiply-add ---------------------------------------------------------------
inline float fmadd(float a, float b, float c) { return __builtin_fmaf(a, b, c); }    // a*b + c
inline float fmsub(float a, float b, float c) { return __builtin_fmaf(a, b, -c); }   // a*b - c
inline float fnmadd(float a, float b, float c) { return __builtin_fmaf(-a, b, c); }  // -(a*b) + c

// ---- Mask logic (&, |, ^, ! are the built-ins) -----------------------------------------
inline bool andnot(bool a, bool b) { return a && !b; }  // a and not b

// ---- Select ---------------------------------------------------------------------------
inline float select(bool m, float a, float b) { return m ? a : b; }
inline std::int32_t select(bool m, std::int32_t a, std::int32_t b) { return m ? a : b; }

// ---- Reductions -----------------------------------------------------------------------
inline bool any(bool m) { return m; }
inline bool all(bool m) { return m; }
inline bool none(bool m) { return !m; }
inline int movemask(bool m) { return m ? 1 : 0; }
inline int popcount(bool m) { return m ? 1 : 0; }
inline float reduce_min(float a) { return a; }
inline float reduce_max(float a) { return a; }
inline float reduce_add(float a) { return a; }
inline std::int32_t reduce_min(std::int32_t a) { return a; }
inline std::int32_t reduce_max(std::int32_t a) { return a; }
inline std::int32_t reduce_add(std::int32_t a) { return a; }

// ---- Int ops (+ - * & | ^ << >> and comparisons are the built-ins) ----------------------
inline std::int32_t andnot(std::int32_t a, std::int32_t b) { return a & ~b; }  // a and not b
// Logical right shift; count in [0, 31] (>> is arithmetic).
inline std::int32_t srl(std::int32_t a, int count) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) >> count);
}
inline std::int32_t min(std::int32_t a, std::int32_t b) { return a < b ? a : b; }
inline std::int32_t max(std::int32_t a, std::int32_t b) { return a > b ? a : b; }

// ---- Gathers: base[index]; masked-off lanes read 0 and are not dereferenced ------------
inline float gather(const float* base, std::int32_t index) { return base[index]; }
inline float gather(bool m, const float* base, std::int32_t index) { return m ? base[index] : 0.0f; }
inline std::int32_t gather(const std::int32_t* base, std::int32_t index) { return base[index]; }
inline std::int32_t gather(bool m, const std::int32_t* base, std::int32_t index) {
  return m ? base[index] : 0;
}

// ---- Conversions and bitcasts ---------------------------------------------------------
inline float to_float(std::int32_t a) { return static_cast<float>(a); }

namespace detail {
// cvtps2dq returns INT32_MIN for NaN and for values outside the int32 range.
inline std::int32_t to_int_or_indefinite(float integral) {
  if (integral >= -2147483648.0f && integral < 2147483648.0f) return static_cast<std::int32_t>(integral);
  return INT32_MIN;
}
}  // namespace detail

inline std::int32_t truncate_to_int(float a) { return detail::to_int_or_indefinite(__builtin_truncf(a)); }
// Rounds to nearest, ties to even (the default rounding mode, as the vector instructions use).
inline std::int32_t round_to_int(float a) { return detail::to_int_or_indefinite(__builtin_nearbyintf(a)); }

inline std::int32_t as_int(float a) { return __builtin_bit_cast(std::int32_t, a); }
inline float as_float(std::int32_t a) { return __builtin_bit_cast(float, a); }

}  // namespace width1
}  // namespace lancer::LANCER_ISA
