// The triangle-test benchmark kernels, as templates over the vector width N and the block
// width B, compiled once per ISA inside namespace lancer::LANCER_ISA by
// triangle_bench_<isa>.cpp (see triangle_bench_kernels.h). They run the kd-tree's own leaf
// test, kd::test_lanes<N, B> from kd_traverse-inl.h (Woop, Benthin & Wald 2013, in
// watertight.h's order of operations), over SoA blocks laid out as the kd-tree lays out its
// leaves. Like kd_traverse-inl.h, they call no inline function of namespace lancer or std
// (the ODR trap, see simd_types.h).
#pragma once

#include "simd/isa_namespace.h"

#include <cstddef>
#include <cstdint>

#include "accel/kd_traverse-inl.h"
#include "triangle_bench_kernels.h"

namespace lancer::LANCER_ISA {
namespace triangle_bench {

template <int N, int B>
void prepare(const Ray* rays, int count, void* leaf_rays) {
  static_assert(alignof(kd::LeafRay<N>) <= 64, "the caller's buffer is 64-byte aligned");
  // LeafRay is an implicit-lifetime aggregate; the buffer comes from operator new.
  kd::LeafRay<N>* out = static_cast<kd::LeafRay<N>*>(leaf_rays);
  for (int i = 0; i < count; ++i) out[i] = kd::make_leaf_ray<N, B>(rays[i]);
}

// Lane 0 of slot `slot`'s x row of vertex 0, as kd::closest computes it.
template <int B>
inline const float* slot_lanes(const float* blocks, int slot) {
  return blocks + std::size_t(slot / B) * (9 * B) + slot % B;
}

// The timed loop: one vector test per N slots and ray; the hit mask is counted without a
// branch (traversal branches on it; here random hits would add mispredictions that depend
// on the data set rather than on the test).
template <int N, int B>
std::int64_t count_hits(const void* leaf_rays, int ray_count, const float* blocks, int slot_count, float limit) {
  static_assert(B % N == 0, "a vector covers lanes of one block");
  const kd::LeafRay<N>* rays = static_cast<const kd::LeafRay<N>*>(leaf_rays);
  const vfloat<N> lim(limit);
  std::int64_t hits = 0;
  for (int r = 0; r < ray_count; ++r) {
    const kd::LeafRay<N>& lr = rays[r];
    for (int slot = 0; slot < slot_count; slot += N) {
      const kd::LaneTest<N> lt = kd::test_lanes<N, B>(slot_lanes<B>(blocks, slot), lr, lim);
      hits += __builtin_popcount(static_cast<unsigned>(lt.hit_bits));
    }
  }
  return hits;
}

template <int N, int B>
void record(const void* leaf_rays, int ray_count, const float* blocks, int slot_count, float limit,
            bench::LaneStatus* status, float* t) {
  const kd::LeafRay<N>* rays = static_cast<const kd::LeafRay<N>*>(leaf_rays);
  const vfloat<N> lim(limit);
  for (int r = 0; r < ray_count; ++r)
    for (int slot = 0; slot < slot_count; slot += N) {
      const kd::LaneTest<N> lt = kd::test_lanes<N, B>(slot_lanes<B>(blocks, slot), rays[r], lim);
      alignas(64) float ts[N];
      store(ts, lt.t);
      for (int l = 0; l < N; ++l) {
        const std::size_t at = std::size_t(r) * std::size_t(slot_count) + std::size_t(slot + l);
        status[at] = (lt.zero_bits >> l) & 1  ? bench::LaneStatus::EdgeZero
                     : (lt.hit_bits >> l) & 1 ? bench::LaneStatus::Hit
                                              : bench::LaneStatus::Miss;
        t[at] = ts[l];
      }
    }
}

template <int N, int B>
bench::TriangleKernels make_kernels(Isa isa) {
  return {isa, N, B, sizeof(kd::LeafRay<N>), &prepare<N, B>, &count_hits<N, B>, &record<N, B>};
}

}  // namespace triangle_bench
}  // namespace lancer::LANCER_ISA
