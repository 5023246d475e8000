// The kd-tree traversal kernels for AVX-512: 16 lanes, blocks 16 triangles wide. Built with this ISA's
// flags only (lancer_isa_sources in src/accel/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA avx512
#include "simd/vfloat16_avx512.h"
#include "accel/kd_traverse-inl.h"
#include "accel/kd_packet-inl.h"

namespace lancer::avx512 {

static_assert(vfloat<16>::size == 16);

template Hit kd_intersect<16, 16>(const KdTreeView&, const Ray&);
template Hit kd_intersect_counted<16, 16>(const KdTreeView&, const Ray&, KdTraversalCounts&);
template bool kd_occluded<16, 16>(const KdTreeView&, const Ray&);
template bool kd_occluded_counted<16, 16>(const KdTreeView&, const Ray&, KdTraversalCounts&);
template void kd_intersect_packet<16, 16>(const KdTreeView&, const Ray*, Hit*, int);
template void kd_occluded_packet<16, 16>(const KdTreeView&, const Ray*, bool*, int);

KdKernels kd_kernels() {
  return {Isa::Avx512, 16, &kd_intersect<16, 16>, &kd_intersect_counted<16, 16>, &kd_occluded<16, 16>,
          &kd_occluded_counted<16, 16>,
          &kd_intersect_packet<16, 16>, &kd_occluded_packet<16, 16>};
}

}  // namespace lancer::avx512

#endif
