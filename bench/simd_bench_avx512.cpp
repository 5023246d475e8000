// The SIMD-primitive benchmark kernels for AVX-512: width 16. Built with this ISA's flags
// only (lancer_isa_sources in bench/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
// GCC 12's AVX-512 intrinsics initialise their "undefined" vectors from themselves (GCC bug
// 105593). vfloat16_avx512.h silences -Wmaybe-uninitialized for them; inlined into these
// chain loops, rcp14 and sqrt draw the plain -Wuninitialized too. Include the intrinsics
// here first, with both silenced (the header's own include is then a no-op).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif

#define LANCER_ISA avx512
#include "simd/vfloat16_avx512.h"
#include "simd_bench-inl.h"

namespace lancer::avx512 {

bench::SimdKernels simd_bench_kernels() { return simd_bench::make_kernels<16, true>(Isa::Avx512, kRcpMaxRelError); }

}  // namespace lancer::avx512

#endif
