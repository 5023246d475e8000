// BM_TriangleTest/<isa>/w<N>: ray-triangle tests per second (items_per_second) of the
// kd-tree's leaf test kd::test_lanes<N, B> at each ISA's width (scalar 1, sse4 4, avx2 8,
// avx512 16), on a fixed, seeded set of 256 triangles and 64 rays (triangle_bench_data.h),
// every ray against every triangle, blocks laid out as in the kd-tree's leaves. The
// per-ray setup (kd::make_leaf_ray) is done before timing, as traversal does it once per
// ray. BM_TriangleTest/scalar/watertight times the scalar reference kernel itself
// (intersect_watertight, watertight.h) on the same pairs.
//
// Registered at start-up for the ISAs this CPU supports only. Before timing, each
// benchmark checks the kernel's answers against the scalar watertight kernel's (same hits,
// bit-identical t) and fails with the reason otherwise.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <string>

#include "accel/watertight.h"
#include "simd/isa.h"
#include "triangle_bench_data.h"

namespace {

using namespace lancer;
using namespace lancer::bench;

constexpr double kPairs = double(kBenchRays) * kBenchTriangles;

void report(benchmark::State& state, const TriangleBenchData& data) {
  state.SetItemsProcessed(state.iterations() * std::int64_t(kPairs));
  state.counters["hit_fraction"] = double(data.hits) / kPairs;
}

void bm_triangle_test(benchmark::State& state, TriangleKernels kernels) {
  const TriangleBenchData& data = triangle_bench_data();
  const AlignedVector<float> blocks = triangle_blocks(data.triangles, kernels.block_width);
  AlignedVector<unsigned char> leaf_rays(kernels.leaf_ray_size * kBenchRays);
  kernels.prepare(data.rays.data(), kBenchRays, leaf_rays.data());
  std::int64_t edge_zero_lanes = 0;
  const std::string error = check_triangle_kernels(kernels, data, blocks.data(), leaf_rays.data(), edge_zero_lanes);
  if (!error.empty()) {
    state.SkipWithError(error.c_str());
    return;
  }
  for (auto _ : state)
    benchmark::DoNotOptimize(kernels.count_hits(leaf_rays.data(), kBenchRays, blocks.data(), kBenchTriangles, kInfinity));
  report(state, data);
  state.counters["edge_zero_lanes"] = double(edge_zero_lanes);  // left to the scalar kernel in traversal
}

// The reference kernel, one pair at a time, reading the same SoA arrays.
std::int64_t watertight_hits(const TriangleBenchData& data, const WatertightRay* rays) {
  const TriangleSoA& tri = data.triangles;
  std::int64_t hits = 0;
  for (int r = 0; r < kBenchRays; ++r)
    for (int i = 0; i < kBenchTriangles; ++i) {
      TriangleHit h;
      hits += intersect_watertight(rays[r], tri.vertex(i, 0), tri.vertex(i, 1), tri.vertex(i, 2), kInfinity, h);
    }
  return hits;
}

void bm_watertight(benchmark::State& state) {
  const TriangleBenchData& data = triangle_bench_data();
  std::vector<WatertightRay> rays;
  for (const Ray& r : data.rays) rays.emplace_back(r);
  // The reference checks itself only for doing the same work here as when it was recorded.
  const std::int64_t hits = watertight_hits(data, rays.data());
  if (hits != data.hits) {
    state.SkipWithError(("the timed loop counts " + std::to_string(hits) + " hits, the recorded tests " +
                         std::to_string(data.hits))
                            .c_str());
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(watertight_hits(data, rays.data()));
  report(state, data);
}

struct Registration {
  Registration() {
    for (Isa isa : supported_isas()) {
      const std::optional<TriangleKernels> kernels = triangle_kernels_for(isa);
      if (!kernels) continue;
      const std::string name =
          "BM_TriangleTest/" + std::string(isa_name(isa)) + "/w" + std::to_string(kernels->width);
      benchmark::RegisterBenchmark(name.c_str(), bm_triangle_test, *kernels);
    }
    benchmark::RegisterBenchmark("BM_TriangleTest/scalar/watertight", bm_watertight);
  }
} registration;

}  // namespace
