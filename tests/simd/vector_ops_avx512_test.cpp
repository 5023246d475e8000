// The width-16 instantiation of the vector-op test kernels, in lancer::avx512. No GoogleTest
// code here: the checks run in the generic vector_ops_*_test.cpp files through the table.
// Compiled with the avx512 flags only (tests/CMakeLists.txt); empty on non-x86 machines.
#if defined(__x86_64__) || defined(_M_X64)
#define LANCER_ISA avx512
#include "simd/vfloat16_avx512.h"
#include "vector_ops_test-inl.h"

namespace lancer::avx512::test {
constinit const VectorOpsTable kVectorOps = make_vector_ops_table<16>();
}  // namespace lancer::avx512::test
#endif
