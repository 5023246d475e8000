// The SIMD-primitive benchmark kernels at width 1 (plain float), on every machine. Built
// without auto-vectorisation (bench/CMakeLists.txt), so width 1 means one float per
// instruction and the copy loop stays a loop rather than a memcpy call.
#define LANCER_ISA scalar
#include "simd/vfloat1_scalar.h"
#include "simd_bench-inl.h"

namespace lancer::scalar {

bench::SimdKernels simd_bench_kernels() {
  // No fma: std::fma is a libm call on the baseline build, not an instruction.
  return simd_bench::make_kernels<1, false>(Isa::Scalar, kRcpMaxRelError);
}

}  // namespace lancer::scalar
