// The width-8 instantiation of the vector-op test kernels, in lancer::avx2. No GoogleTest
// code here: the checks run in the generic vector_ops_*_test.cpp files through the table.
// Compiled with the avx2 flags only (tests/CMakeLists.txt); empty on non-x86 machines.
#if defined(__x86_64__) || defined(_M_X64)
#define LANCER_ISA avx2
#include "simd/vfloat8_avx2.h"
#include "vector_ops_test-inl.h"

namespace lancer::avx2::test {
constinit const VectorOpsTable kVectorOps = make_vector_ops_table<8>();
}  // namespace lancer::avx2::test
#endif
