// The scalar kd-tree traversal kernels (width 1: one triangle at a time), on every
// machine. Blocks stay 4 wide, the smallest padding the layout allows.
#define LANCER_ISA scalar
#include "simd/vfloat1_scalar.h"
#include "accel/kd_traverse-inl.h"
#include "accel/kd_packet-inl.h"

namespace lancer::scalar {

template Hit kd_intersect<1, 4>(const KdTreeView&, const Ray&);
template Hit kd_intersect_counted<1, 4>(const KdTreeView&, const Ray&, KdTraversalCounts&);
template bool kd_occluded<1, 4>(const KdTreeView&, const Ray&);
template bool kd_occluded_counted<1, 4>(const KdTreeView&, const Ray&, KdTraversalCounts&);
template void kd_intersect_packet<1, 4>(const KdTreeView&, const Ray*, Hit*, int);
template void kd_occluded_packet<1, 4>(const KdTreeView&, const Ray*, bool*, int);

KdKernels kd_kernels() {
  return {Isa::Scalar, 4, &kd_intersect<1, 4>, &kd_intersect_counted<1, 4>, &kd_occluded<1, 4>,
          &kd_occluded_counted<1, 4>,
          &kd_intersect_packet<1, 4>, &kd_occluded_packet<1, 4>};
}

}  // namespace lancer::scalar

namespace lancer {

// The generic entry to the float setup (kd_traverse_setup.h): the scalar namespace's copy,
// built with the baseline flags like the rest of the generic code.
bool kd_setup_ray_float(const KdTreeView& tree, const Ray& ray, KdRaySetup& s) {
  return scalar::kd::setup_float(tree, ray, s);
}

}  // namespace lancer
