// The scalar oracle's throughput: the watertight kernel alone, and brute force over a
// small soup. These numbers anchor every speed-up the accelerators claim.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "accel/brute_force.h"
#include "accel/watertight.h"
#include "simd/splitmix64.h"

namespace {

using namespace lancer;

// A fixed generator (splitmix64), so runs compare across machines.
struct Rng : SplitMix64 {
  using SplitMix64::SplitMix64;
  glm::vec3 point() { return {uniform(), uniform(), uniform()}; }
};

TriangleSoA soup(std::size_t n) {
  Rng rng(1);
  TriangleSoA t;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 c = rng.point();
    t.push_back(c, c + 0.05f * rng.point(), c + 0.05f * rng.point());
  }
  return t;
}

std::vector<Ray> rays(std::size_t n) {
  Rng rng(2);
  std::vector<Ray> out(n);
  for (auto& r : out) {
    r.org = glm::vec3(0.5f, 0.5f, -1.0f);
    r.dir = rng.point() - r.org;  // toward a point in the unit cube the soup fills
  }
  return out;
}

void BM_WatertightKernel(benchmark::State& state) {
  const TriangleSoA tris = soup(1024);
  const std::vector<Ray> rs = rays(64);
  std::int64_t tests = 0;
  for (auto _ : state) {
    for (const Ray& r : rs) {
      const WatertightRay wr(r);
      TriangleHit h;
      for (std::size_t i = 0; i < tris.size(); ++i)
        benchmark::DoNotOptimize(intersect_watertight(wr, tris.vertex(i, 0), tris.vertex(i, 1), tris.vertex(i, 2), kInfinity, h));
      tests += static_cast<std::int64_t>(tris.size());
    }
  }
  state.counters["tests/s"] = benchmark::Counter(static_cast<double>(tests), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_WatertightKernel)->Name("BM_Watertight/scalar");

void BM_BruteForce(benchmark::State& state) {
  const TriangleSoA tris = soup(static_cast<std::size_t>(state.range(0)));
  const BruteForce oracle(tris);
  const std::vector<Ray> rs = rays(256);
  std::int64_t n = 0;
  for (auto _ : state) {
    for (const Ray& r : rs) benchmark::DoNotOptimize(oracle.intersect(r));
    n += static_cast<std::int64_t>(rs.size());
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BruteForce)->Name("BM_Trace/brute/scalar/soup")->Arg(1024)->Arg(16384);

}  // namespace

BENCHMARK_MAIN();
