// The triangle-test micro-benchmark kernels (BM_TriangleTest/<isa>/w<N>): the kd-tree's
// leaf test kd::test_lanes<N, B> (src/accel/kd_traverse-inl.h) run over blocks of
// triangles, one table per ISA. Declarations only: nothing here is compiled with ISA flags.
// The kernels are templates in triangle_bench-inl.h, instantiated per ISA
// (triangle_bench_scalar.cpp, _sse4.cpp, _avx2.cpp, _avx512.cpp); data, reference and
// timing loops are generic (triangle_bench_data.cpp, triangle_bench.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "accel/ray.h"
#include "simd/isa.h"

namespace lancer::bench {

// What the leaf test says about one (ray, triangle) pair.
enum class LaneStatus : std::uint8_t {
  Miss = 0,
  Hit = 1,       // tnear <= t < limit; t as the kernel computed it
  EdgeZero = 2,  // an edge function is exactly 0: traversal hands this lane to the scalar kernel
};

struct TriangleKernels {
  Isa isa;
  int width;                     // triangles per vector test: 1, 4, 8 or 16
  int block_width;               // the kd-tree's block width for this ISA (slots per SoA block)
  std::size_t leaf_ray_size;     // bytes of one prepared ray (kd::LeafRay<width>), 64-byte aligned
  // Writes the leaf test's per-ray constants of rays[0 .. count) to leaf_rays (count *
  // leaf_ray_size bytes, 64-byte aligned). Not timed: traversal does it once per ray.
  void (*prepare)(const Ray* rays, int count, void* leaf_rays);
  // Tests every prepared ray against slots [0, slot_count) of `blocks` (block_width wide,
  // slot_count a multiple of it) and returns the number of hit lanes (tnear <= t < limit,
  // no edge function exactly 0). This is what is timed.
  std::int64_t (*count_hits)(const void* leaf_rays, int ray_count, const float* blocks, int slot_count, float limit);
  // The same tests, recording each pair: status[r * slot_count + s] and, for hits, t there.
  void (*record)(const void* leaf_rays, int ray_count, const float* blocks, int slot_count, float limit,
                 LaneStatus* status, float* t);
};

}  // namespace lancer::bench

// One table per ISA, each defined in its own translation unit.
namespace lancer::scalar {
bench::TriangleKernels triangle_bench_kernels();
}
#if defined(__x86_64__) || defined(_M_X64)
namespace lancer::sse4 {
bench::TriangleKernels triangle_bench_kernels();
}
namespace lancer::avx2 {
bench::TriangleKernels triangle_bench_kernels();
}
namespace lancer::avx512 {
bench::TriangleKernels triangle_bench_kernels();
}
#endif
