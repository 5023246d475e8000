// The SIMD-primitive benchmark kernels for AVX2 + FMA: width 8. Built with this ISA's
// flags only (lancer_isa_sources in bench/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA avx2
#include "simd/vfloat8_avx2.h"
#include "simd_bench-inl.h"

namespace lancer::avx2 {

bench::SimdKernels simd_bench_kernels() { return simd_bench::make_kernels<8, true>(Isa::Avx2, kRcpMaxRelError); }

}  // namespace lancer::avx2

#endif
