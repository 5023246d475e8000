// The triangle-test benchmark kernel for SSE4.2: 4 lanes, blocks 4 wide (as
// kd_traverse_sse4.cpp). Built with this ISA's flags only (lancer_isa_sources in
// bench/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA sse4
#include "simd/vfloat4_sse4.h"
#include "triangle_bench-inl.h"

namespace lancer::sse4 {

bench::TriangleKernels triangle_bench_kernels() { return triangle_bench::make_kernels<4, 4>(Isa::Sse4); }

}  // namespace lancer::sse4

#endif
