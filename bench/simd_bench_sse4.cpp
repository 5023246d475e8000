// The SIMD-primitive benchmark kernels for SSE4.2: width 4. Built with this ISA's flags
// only (lancer_isa_sources in bench/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA sse4
#include "simd/vfloat4_sse4.h"
#include "simd_bench-inl.h"

namespace lancer::sse4 {

bench::SimdKernels simd_bench_kernels() {
  // No fma: SSE4 has no fused multiply-add (fmadd here is a multiply and an add).
  return simd_bench::make_kernels<4, false>(Isa::Sse4, kRcpMaxRelError);
}

}  // namespace lancer::sse4

#endif
