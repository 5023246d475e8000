// The triangle-test benchmark kernel for AVX2: 8 lanes, blocks 8 wide (as
// kd_traverse_avx2.cpp). Built with this ISA's flags only (lancer_isa_sources in
// bench/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA avx2
#include "simd/vfloat8_avx2.h"
#include "triangle_bench-inl.h"

namespace lancer::avx2 {

bench::TriangleKernels triangle_bench_kernels() { return triangle_bench::make_kernels<8, 8>(Isa::Avx2); }

}  // namespace lancer::avx2

#endif
