// The vector-op test kernels, as templates over the width N, compiled once per ISA inside
// lancer::LANCER_ISA::test by vector_ops_<isa>_test.cpp, which includes its ISA's vector
// header first. They only run operations and write results; the expected values (a scalar
// loop lane by lane) and all checks live in the generic GoogleTest files, so no gtest code
// is ever compiled with ISA flags.
//
// Deliberately free of standard-library templates: anything instantiated here is compiled
// with this ISA's flags, and a shared template instance could be merged with generic code.
#pragma once

#include <cstdint>

#include "simd/isa_namespace.h"
#include "vector_ops_table.h"

namespace lancer::LANCER_ISA::test {

using lancer::test::Compare;
using lancer::test::FloatBinary;
using lancer::test::FloatTernary;
using lancer::test::FloatToInt;
using lancer::test::FloatUnary;
using lancer::test::IntBinary;
using lancer::test::IntToFloat;
using lancer::test::IntUnary;
using lancer::test::MaskLogic;
using lancer::test::MaskReductions;
using lancer::test::VectorOpsTable;

// ---- Helpers: masks travel as 0/1 per lane ----------------------------------------------
template <int N>
vbool<N> read_mask(const std::int32_t* lanes) {
  return loadu(Lanes<N>{}, lanes) != vint<N>(0);
}
template <int N>
void write_mask(std::int32_t* lanes, vbool<N> m) {
  storeu(lanes, select(m, vint<N>(1), vint<N>(0)));
}

// ---- Factories and lane access ----------------------------------------------------------
template <int N>
void run_broadcast(float f, std::int32_t i, bool b, float* out_f, std::int32_t* out_i, std::int32_t* out_b) {
  storeu(out_f, vfloat<N>(f));
  storeu(out_i, vint<N>(i));
  write_mask<N>(out_b, vbool<N>(b));
}
template <int N>
void run_first_lanes(int count, std::int32_t* out) {
  write_mask<N>(out, first_lanes(Lanes<N>{}, count));
}
template <int N>
void run_mask_from_bits(int bits, std::int32_t* out) {
  write_mask<N>(out, mask_from_bits(Lanes<N>{}, bits));
}
template <int N>
void run_lane_access(const float* f, const std::int32_t* i, const std::int32_t* m, float* out_f,
                     std::int32_t* out_i, std::int32_t* out_m) {
  const vfloat<N> vf = loadu(Lanes<N>{}, f);
  const vint<N> vi = loadu(Lanes<N>{}, i);
  const vbool<N> vm = read_mask<N>(m);
  if constexpr (N == 1) {
    out_f[0] = vf;
    out_i[0] = vi;
    out_m[0] = vm;
  } else {
    for (int k = 0; k < N; ++k) {
      out_f[k] = vf[k];
      out_i[k] = vi[k];
      out_m[k] = vm[k];
    }
  }
}

// ---- Loads and stores ---------------------------------------------------------------------
template <int N, typename T>
void run_copy(bool aligned, const T* src, T* dst, int count) {
  for (int i = 0; i < count; i += N) {
    if (aligned) {
      store(dst + i, load(Lanes<N>{}, src + i));
    } else {
      storeu(dst + i, loadu(Lanes<N>{}, src + i));
    }
  }
}
template <int N, typename T>
void run_masked_load(const std::int32_t* mask, const T* src, T* out, int count) {
  for (int i = 0; i < count; i += N) storeu(out + i, load(read_mask<N>(mask + i), src + i));
}
template <int N, typename T>
void run_masked_store(const std::int32_t* mask, const T* src, T* dst, int count) {
  for (int i = 0; i < count; i += N) store(read_mask<N>(mask + i), dst + i, loadu(Lanes<N>{}, src + i));
}
template <int N>
void run_load_first(const float* src, int n, float* out) {
  storeu(out, load(first_lanes(Lanes<N>{}, n), src));
}
template <int N>
void run_store_first(float value, int n, float* dst) {
  store(first_lanes(Lanes<N>{}, n), dst, vfloat<N>(value));
}

// ---- Float arithmetic and comparisons ---------------------------------------------------
template <int N>
vfloat<N> apply(FloatUnary op, vfloat<N> a) {
  switch (op) {
    case FloatUnary::Neg: return -a;
    case FloatUnary::Abs: return abs(a);
    case FloatUnary::Sqrt: return sqrt(a);
    case FloatUnary::Rcp: return rcp(a);
    case FloatUnary::Rsqrt: return rsqrt(a);
  }
  return a;
}
template <int N>
vfloat<N> apply(FloatBinary op, vfloat<N> a, vfloat<N> b) {
  switch (op) {
    case FloatBinary::Add: return a + b;
    case FloatBinary::Sub: return a - b;
    case FloatBinary::Mul: return a * b;
    case FloatBinary::Div: return a / b;
    case FloatBinary::Min: return min(a, b);
    case FloatBinary::Max: return max(a, b);
  }
  return a;
}
template <int N>
vfloat<N> apply(FloatTernary op, vfloat<N> a, vfloat<N> b, vfloat<N> c) {
  switch (op) {
    case FloatTernary::Fmadd: return fmadd(a, b, c);
    case FloatTernary::Fmsub: return fmsub(a, b, c);
    case FloatTernary::Fnmadd: return fnmadd(a, b, c);
  }
  return a;
}
// Shared by float and int lanes.
template <typename V>
auto compare(Compare op, V a, V b) {
  switch (op) {
    case Compare::Lt: return a < b;
    case Compare::Le: return a <= b;
    case Compare::Gt: return a > b;
    case Compare::Ge: return a >= b;
    case Compare::Eq: return a == b;
    case Compare::Ne: return a != b;
  }
  return a < b;  // unreachable
}

template <int N>
void run_float_unary(FloatUnary op, const float* a, float* out, int count) {
  for (int i = 0; i < count; i += N) storeu(out + i, apply<N>(op, loadu(Lanes<N>{}, a + i)));
}
template <int N>
void run_float_binary(FloatBinary op, const float* a, const float* b, float* out, int count) {
  for (int i = 0; i < count; i += N)
    storeu(out + i, apply<N>(op, loadu(Lanes<N>{}, a + i), loadu(Lanes<N>{}, b + i)));
}
template <int N>
void run_float_ternary(FloatTernary op, const float* a, const float* b, const float* c, float* out, int count) {
  for (int i = 0; i < count; i += N)
    storeu(out + i, apply<N>(op, loadu(Lanes<N>{}, a + i), loadu(Lanes<N>{}, b + i), loadu(Lanes<N>{}, c + i)));
}
template <int N, typename T>
void run_compare(Compare op, const T* a, const T* b, std::int32_t* out, int count) {
  for (int i = 0; i < count; i += N)
    write_mask<N>(out + i, compare(op, loadu(Lanes<N>{}, a + i), loadu(Lanes<N>{}, b + i)));
}

// ---- Masks, select and reductions -------------------------------------------------------
template <int N>
vbool<N> apply(MaskLogic op, vbool<N> a, vbool<N> b) {
  switch (op) {
    case MaskLogic::And: return a & b;
    case MaskLogic::Or: return a | b;
    case MaskLogic::Xor: return a ^ b;
    case MaskLogic::Andnot: return andnot(a, b);
    case MaskLogic::Not: return !a;
  }
  return a;
}
template <int N>
void run_mask_logic(MaskLogic op, const std::int32_t* a, const std::int32_t* b, std::int32_t* out, int count) {
  for (int i = 0; i < count; i += N)
    write_mask<N>(out + i, apply<N>(op, read_mask<N>(a + i), read_mask<N>(b + i)));
}
template <int N, typename T>
void run_select(const std::int32_t* mask, const T* a, const T* b, T* out, int count) {
  for (int i = 0; i < count; i += N)
    storeu(out + i, select(read_mask<N>(mask + i), loadu(Lanes<N>{}, a + i), loadu(Lanes<N>{}, b + i)));
}
template <int N>
void run_mask_reductions(const std::int32_t* mask, MaskReductions* out, int count) {
  for (int i = 0; i < count; i += N) {
    const vbool<N> m = read_mask<N>(mask + i);
    out[i / N] = {any(m), all(m), none(m), movemask(m), popcount(m)};
  }
}
template <int N, typename T>
void run_reductions(const T* a, T* out_min, T* out_max, T* out_add, int count) {
  for (int i = 0; i < count; i += N) {
    const auto v = loadu(Lanes<N>{}, a + i);
    out_min[i / N] = reduce_min(v);
    out_max[i / N] = reduce_max(v);
    out_add[i / N] = reduce_add(v);
  }
}

// ---- Int ops ------------------------------------------------------------------------------
template <int N>
vint<N> apply(IntUnary op, vint<N> a, int shift) {
  switch (op) {
    case IntUnary::Neg: return -a;
    case IntUnary::ShiftLeft: return a << shift;
    case IntUnary::ShiftRightArithmetic: return a >> shift;
    case IntUnary::ShiftRightLogical: return srl(a, shift);
  }
  return a;
}
template <int N>
vint<N> apply(IntBinary op, vint<N> a, vint<N> b) {
  switch (op) {
    case IntBinary::Add: return a + b;
    case IntBinary::Sub: return a - b;
    case IntBinary::Mul: return a * b;
    case IntBinary::And: return a & b;
    case IntBinary::Or: return a | b;
    case IntBinary::Xor: return a ^ b;
    case IntBinary::Andnot: return andnot(a, b);
    case IntBinary::Min: return min(a, b);
    case IntBinary::Max: return max(a, b);
  }
  return a;
}
template <int N>
void run_int_unary(IntUnary op, const std::int32_t* a, int shift, std::int32_t* out, int count) {
  for (int i = 0; i < count; i += N) storeu(out + i, apply<N>(op, loadu(Lanes<N>{}, a + i), shift));
}
template <int N>
void run_int_binary(IntBinary op, const std::int32_t* a, const std::int32_t* b, std::int32_t* out, int count) {
  for (int i = 0; i < count; i += N)
    storeu(out + i, apply<N>(op, loadu(Lanes<N>{}, a + i), loadu(Lanes<N>{}, b + i)));
}

// ---- Gathers and conversions --------------------------------------------------------------
template <int N, typename T>
void run_gather(const T* base, const std::int32_t* index, const std::int32_t* mask, T* out, int count) {
  for (int i = 0; i < count; i += N) {
    const vint<N> idx = loadu(Lanes<N>{}, index + i);
    if (mask) {
      storeu(out + i, gather(read_mask<N>(mask + i), base, idx));
    } else {
      storeu(out + i, gather(base, idx));
    }
  }
}
template <int N>
void run_float_to_int(FloatToInt op, const float* a, std::int32_t* out, int count) {
  for (int i = 0; i < count; i += N) {
    const vfloat<N> v = loadu(Lanes<N>{}, a + i);
    switch (op) {
      case FloatToInt::Truncate: storeu(out + i, truncate_to_int(v)); break;
      case FloatToInt::Round: storeu(out + i, round_to_int(v)); break;
      case FloatToInt::Bits: storeu(out + i, as_int(v)); break;
    }
  }
}
template <int N>
void run_int_to_float(IntToFloat op, const std::int32_t* a, float* out, int count) {
  for (int i = 0; i < count; i += N) {
    const vint<N> v = loadu(Lanes<N>{}, a + i);
    storeu(out + i, op == IntToFloat::Convert ? to_float(v) : as_float(v));
  }
}

// ---- Watertight edge functions over N triangles (Woop, Benthin & Wald, JCGT 2013) ---------
// xy = {ax, ay, bx, by, cx, cy}: vertices already translated and sheared into ray space.
template <int N>
void run_edge_test(const float* const xy[6], std::int32_t* hit, float* det, int count) {
  for (int i = 0; i < count; i += N) {
    const vfloat<N> ax = loadu(Lanes<N>{}, xy[0] + i), ay = loadu(Lanes<N>{}, xy[1] + i);
    const vfloat<N> bx = loadu(Lanes<N>{}, xy[2] + i), by = loadu(Lanes<N>{}, xy[3] + i);
    const vfloat<N> cx = loadu(Lanes<N>{}, xy[4] + i), cy = loadu(Lanes<N>{}, xy[5] + i);
    const vfloat<N> u = cx * by - cy * bx;
    const vfloat<N> v = ax * cy - ay * cx;
    const vfloat<N> w = bx * ay - by * ax;
    const vfloat<N> zero(0.0f);
    const vbool<N> some_negative = (u < zero) | (v < zero) | (w < zero);
    const vbool<N> some_positive = (u > zero) | (v > zero) | (w > zero);
    const vfloat<N> d = u + v + w;
    const vbool<N> inside = andnot(!(some_negative & some_positive), abs(d) == zero);
    write_mask<N>(hit + i, inside);
    storeu(det + i, d);
  }
}

// ---- The table -------------------------------------------------------------------------------
template <int N>
constexpr VectorOpsTable make_vector_ops_table() {
  return VectorOpsTable{
      .width = N,
      .rcp_max_rel_error = kRcpMaxRelError,
      .rsqrt_max_rel_error = kRsqrtMaxRelError,
      .broadcast = &run_broadcast<N>,
      .first_lanes = &run_first_lanes<N>,
      .mask_from_bits = &run_mask_from_bits<N>,
      .lane_access = &run_lane_access<N>,
      .copy_float = &run_copy<N, float>,
      .copy_int = &run_copy<N, std::int32_t>,
      .masked_load_float = &run_masked_load<N, float>,
      .masked_load_int = &run_masked_load<N, std::int32_t>,
      .masked_store_float = &run_masked_store<N, float>,
      .masked_store_int = &run_masked_store<N, std::int32_t>,
      .load_first = &run_load_first<N>,
      .store_first = &run_store_first<N>,
      .float_unary = &run_float_unary<N>,
      .float_binary = &run_float_binary<N>,
      .float_ternary = &run_float_ternary<N>,
      .float_compare = &run_compare<N, float>,
      .mask_logic = &run_mask_logic<N>,
      .select_float = &run_select<N, float>,
      .select_int = &run_select<N, std::int32_t>,
      .mask_reductions = &run_mask_reductions<N>,
      .float_reductions = &run_reductions<N, float>,
      .int_unary = &run_int_unary<N>,
      .int_binary = &run_int_binary<N>,
      .int_compare = &run_compare<N, std::int32_t>,
      .int_reductions = &run_reductions<N, std::int32_t>,
      .gather_float = &run_gather<N, float>,
      .gather_int = &run_gather<N, std::int32_t>,
      .float_to_int = &run_float_to_int<N>,
      .int_to_float = &run_int_to_float<N>,
      .edge_test = &run_edge_test<N>,
  };
}

}  // namespace lancer::LANCER_ISA::test
