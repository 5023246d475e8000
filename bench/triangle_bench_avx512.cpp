// The triangle-test benchmark kernel for AVX-512: 16 lanes, blocks 16 wide (as
// kd_traverse_avx512.cpp). Built with this ISA's flags only (lancer_isa_sources in
// bench/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA avx512
#include "simd/vfloat16_avx512.h"
#include "triangle_bench-inl.h"

namespace lancer::avx512 {

bench::TriangleKernels triangle_bench_kernels() { return triangle_bench::make_kernels<16, 16>(Isa::Avx512); }

}  // namespace lancer::avx512

#endif
