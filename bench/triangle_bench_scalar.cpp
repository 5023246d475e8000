// The triangle-test benchmark kernel at width 1 (one triangle per test, blocks 4 wide, as
// kd_traverse_scalar.cpp), on every machine.
#define LANCER_ISA scalar
#include "simd/vfloat1_scalar.h"
#include "triangle_bench-inl.h"

namespace lancer::scalar {

bench::TriangleKernels triangle_bench_kernels() { return triangle_bench::make_kernels<1, 4>(Isa::Scalar); }

}  // namespace lancer::scalar
