// A plain table of function pointers into one ISA's instantiation of the vector-op test
// kernels (vector_ops_test-inl.h), so the GoogleTest code, which is compiled with generic
// flags only, can check the CPU first and never runs or links ISA-compiled gtest code.
//
// Every function runs over `count` lanes (a multiple of the table's width), one vector at a
// time; masks travel as one int32 per lane, 0 or 1.
#pragma once

#include <cstdint>

namespace lancer::test {

enum class FloatUnary { Neg, Abs, Sqrt, Rcp, Rsqrt };
enum class FloatBinary { Add, Sub, Mul, Div, Min, Max };
enum class FloatTernary { Fmadd, Fmsub, Fnmadd };
enum class Compare { Lt, Le, Gt, Ge, Eq, Ne };
enum class MaskLogic { And, Or, Xor, Andnot, Not };
enum class IntUnary { Neg, ShiftLeft, ShiftRightArithmetic, ShiftRightLogical };
enum class IntBinary { Add, Sub, Mul, And, Or, Xor, Andnot, Min, Max };
enum class FloatToInt { Truncate, Round, Bits };
enum class IntToFloat { Convert, Bits };

struct MaskReductions {
  std::int32_t any, all, none, movemask, popcount;
};

struct VectorOpsTable {
  int width;
  float rcp_max_rel_error;
  float rsqrt_max_rel_error;

  // Factories and lane access: out has `width` lanes.
  void (*broadcast)(float f, std::int32_t i, bool b, float* out_f, std::int32_t* out_i, std::int32_t* out_b);
  void (*first_lanes)(int count, std::int32_t* out);
  void (*mask_from_bits)(int bits, std::int32_t* out);
  void (*lane_access)(const float* f, const std::int32_t* i, const std::int32_t* m, float* out_f,
                      std::int32_t* out_i, std::int32_t* out_m);

  // Loads and stores. Masked store writes src's active lanes into dst.
  void (*copy_float)(bool aligned, const float* src, float* dst, int count);
  void (*copy_int)(bool aligned, const std::int32_t* src, std::int32_t* dst, int count);
  void (*masked_load_float)(const std::int32_t* mask, const float* src, float* out, int count);
  void (*masked_load_int)(const std::int32_t* mask, const std::int32_t* src, std::int32_t* out, int count);
  void (*masked_store_float)(const std::int32_t* mask, const float* src, float* dst, int count);
  void (*masked_store_int)(const std::int32_t* mask, const std::int32_t* src, std::int32_t* dst, int count);
  // load(first_lanes(n), src) into out[0, width): the partial load at the end of an array.
  void (*load_first)(const float* src, int n, float* out);
  // store(first_lanes(n), dst, value): the partial store at the end of an array.
  void (*store_first)(float value, int n, float* dst);

  // Float arithmetic and comparisons.
  void (*float_unary)(FloatUnary op, const float* a, float* out, int count);
  void (*float_binary)(FloatBinary op, const float* a, const float* b, float* out, int count);
  void (*float_ternary)(FloatTernary op, const float* a, const float* b, const float* c, float* out, int count);
  void (*float_compare)(Compare op, const float* a, const float* b, std::int32_t* out, int count);

  // Masks, select and reductions (reductions write one result per vector).
  void (*mask_logic)(MaskLogic op, const std::int32_t* a, const std::int32_t* b, std::int32_t* out, int count);
  void (*select_float)(const std::int32_t* mask, const float* a, const float* b, float* out, int count);
  void (*select_int)(const std::int32_t* mask, const std::int32_t* a, const std::int32_t* b, std::int32_t* out,
                     int count);
  void (*mask_reductions)(const std::int32_t* mask, MaskReductions* out, int count);
  void (*float_reductions)(const float* a, float* out_min, float* out_max, float* out_add, int count);

  // Int ops.
  void (*int_unary)(IntUnary op, const std::int32_t* a, int shift, std::int32_t* out, int count);
  void (*int_binary)(IntBinary op, const std::int32_t* a, const std::int32_t* b, std::int32_t* out, int count);
  void (*int_compare)(Compare op, const std::int32_t* a, const std::int32_t* b, std::int32_t* out, int count);
  void (*int_reductions)(const std::int32_t* a, std::int32_t* out_min, std::int32_t* out_max,
                         std::int32_t* out_add, int count);

  // Gathers (mask may be null: unmasked gather) and conversions.
  void (*gather_float)(const float* base, const std::int32_t* index, const std::int32_t* mask, float* out,
                       int count);
  void (*gather_int)(const std::int32_t* base, const std::int32_t* index, const std::int32_t* mask,
                     std::int32_t* out, int count);
  void (*float_to_int)(FloatToInt op, const float* a, std::int32_t* out, int count);
  void (*int_to_float)(IntToFloat op, const std::int32_t* a, float* out, int count);

  // The inner step of a watertight ray/triangle test over `width` triangles (Woop et al.
  // 2013): edge functions U, V, W from sheared 2D vertices, then "all signs equal and the
  // determinant is non-zero". Writes hit (0/1) per triangle and U+V+W.
  void (*edge_test)(const float* const xy[6], std::int32_t* hit, float* det, int count);
};

}  // namespace lancer::test

// One table per ISA, each defined in its own translation unit (vector_ops_<isa>_test.cpp).
namespace lancer::scalar::test {
extern const lancer::test::VectorOpsTable kVectorOps;
}
#if defined(__x86_64__) || defined(_M_X64)
namespace lancer::sse4::test {
extern const lancer::test::VectorOpsTable kVectorOps;
}
namespace lancer::avx2::test {
extern const lancer::test::VectorOpsTable kVectorOps;
}
namespace lancer::avx512::test {
extern const lancer::test::VectorOpsTable kVectorOps;
}
#endif
