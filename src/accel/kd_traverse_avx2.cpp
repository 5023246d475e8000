// The kd-tree traversal kernels for AVX2: 8 lanes, blocks 8 triangles wide. Built with this ISA's
// flags only (lancer_isa_sources in src/accel/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA avx2
#include "simd/vfloat8_avx2.h"
#include "accel/kd_traverse-inl.h"
#include "accel/kd_packet-inl.h"

namespace lancer::avx2 {

static_assert(vfloat<8>::size == 8);

template Hit kd_intersect<8, 8>(const KdTreeView&, const Ray&);
template Hit kd_intersect_counted<8, 8>(const KdTreeView&, const Ray&, KdTraversalCounts&);
template bool kd_occluded<8, 8>(const KdTreeView&, const Ray&);
template bool kd_occluded_counted<8, 8>(const KdTreeView&, const Ray&, KdTraversalCounts&);
template void kd_intersect_packet<8, 8>(const KdTreeView&, const Ray*, Hit*, int);
template void kd_occluded_packet<8, 8>(const KdTreeView&, const Ray*, bool*, int);

KdKernels kd_kernels() {
  return {Isa::Avx2, 8, &kd_intersect<8, 8>, &kd_intersect_counted<8, 8>, &kd_occluded<8, 8>,
          &kd_occluded_counted<8, 8>,
          &kd_intersect_packet<8, 8>, &kd_occluded_packet<8, 8>};
}

}  // namespace lancer::avx2

#endif
