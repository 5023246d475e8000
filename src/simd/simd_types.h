// Width-generic names for the SIMD types; nothing ISA-specific lives here (no intrinsics).
//
// Each ISA has its own namespace so an inline wrapper compiled with AVX-512 flags can never
// be merged by the linker with the SSE4 copy of the same function (the ODR trap):
//   lancer::scalar  width 1: float, int32_t, bool         (vfloat1_scalar.h)
//   lancer::sse4    width 4: vfloat4, vint4, vbool4       (vfloat4_sse4.h)
//   lancer::avx2    width 8: vfloat8, vint8, vbool8       (vfloat8_avx2.h)
//   lancer::avx512  width 16: vfloat16, vint16, vbool16   (vfloat16_avx512.h)
// Each of those headers specialises `vtypes<N>` for its width inside its namespace, so a
// kernel template over N that is compiled inside that namespace can write vfloat<N>,
// vint<N> and vbool<N>. Width 1 exists in every namespace too (vfloat1-inl.h, its
// operations in the nested namespace width1), so one template serves a vector of rays and
// a single ray in each ISA. Operations are free functions; ones that cannot be told apart by
// their arguments (loads, mask factories) take a `Lanes<N>` tag: `load(Lanes<N>{}, p)`.
#pragma once

namespace lancer {

// Selects the width of an overloaded factory function, e.g. load(Lanes<8>{}, p).
template <int N>
struct Lanes {
  static constexpr int size = N;
};

namespace scalar {
template <int N>
struct vtypes;  // members: Float, Int, Bool, size
template <int N>
using vfloat = typename vtypes<N>::Float;
template <int N>
using vint = typename vtypes<N>::Int;
template <int N>
using vbool = typename vtypes<N>::Bool;
}  // namespace scalar

namespace sse4 {
template <int N>
struct vtypes;
template <int N>
using vfloat = typename vtypes<N>::Float;
template <int N>
using vint = typename vtypes<N>::Int;
template <int N>
using vbool = typename vtypes<N>::Bool;
}  // namespace sse4

namespace avx2 {
template <int N>
struct vtypes;
template <int N>
using vfloat = typename vtypes<N>::Float;
template <int N>
using vint = typename vtypes<N>::Int;
template <int N>
using vbool = typename vtypes<N>::Bool;
}  // namespace avx2

namespace avx512 {
template <int N>
struct vtypes;
template <int N>
using vfloat = typename vtypes<N>::Float;
template <int N>
using vint = typename vtypes<N>::Int;
template <int N>
using vbool = typename vtypes<N>::Bool;
}  // namespace avx512

}  // namespace lancer
