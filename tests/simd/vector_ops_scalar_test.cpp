// The width-1 instantiation of the vector-op test kernels, in lancer::scalar. No GoogleTest
// code here: the checks run in the generic vector_ops_*_test.cpp files through the table.
// Compiled with the generic flags, like every user of lancer::scalar.
#define LANCER_ISA scalar
#include "simd/vfloat1_scalar.h"
#include "vector_ops_test-inl.h"

namespace lancer::scalar::test {
constinit const VectorOpsTable kVectorOps = make_vector_ops_table<1>();
}  // namespace lancer::scalar::test
