// The width-4 instantiation of the vector-op test kernels, in lancer::sse4. No GoogleTest
// code here: the checks run in the generic vector_ops_*_test.cpp files through the table.
// Compiled with the sse4 flags only (tests/CMakeLists.txt); empty on non-x86 machines.
#if defined(__x86_64__) || defined(_M_X64)
#define LANCER_ISA sse4
#include "simd/vfloat4_sse4.h"
#include "vector_ops_test-inl.h"

namespace lancer::sse4::test {
constinit const VectorOpsTable kVectorOps = make_vector_ops_table<4>();
}  // namespace lancer::sse4::test
#endif
