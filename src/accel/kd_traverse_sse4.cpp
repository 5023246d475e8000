// The kd-tree traversal kernels for SSE4.2: 4 lanes, blocks 4 triangles wide. Built with this ISA's
// flags only (lancer_isa_sources in src/accel/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA sse4
#include "simd/vfloat4_sse4.h"
#include "accel/kd_traverse-inl.h"
#include "accel/kd_packet-inl.h"

namespace lancer::sse4 {

static_assert(vfloat<4>::size == 4);

template Hit kd_intersect<4, 4>(const KdTreeView&, const Ray&);
template Hit kd_intersect_counted<4, 4>(const KdTreeView&, const Ray&, KdTraversalCounts&);
template bool kd_occluded<4, 4>(const KdTreeView&, const Ray&);
template bool kd_occluded_counted<4, 4>(const KdTreeView&, const Ray&, KdTraversalCounts&);
template void kd_intersect_packet<4, 4>(const KdTreeView&, const Ray*, Hit*, int);
template void kd_occluded_packet<4, 4>(const KdTreeView&, const Ray*, bool*, int);

KdKernels kd_kernels() {
  return {Isa::Sse4, 4, &kd_intersect<4, 4>, &kd_intersect_counted<4, 4>, &kd_occluded<4, 4>,
          &kd_occluded_counted<4, 4>,
          &kd_intersect_packet<4, 4>, &kd_occluded_packet<4, 4>};
}

}  // namespace lancer::sse4

#endif
