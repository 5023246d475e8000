// render/ray_batch.h: every ray of a batch traced exactly once, in 64-ray chunks, with the
// oracle's answers in both modes and for any thread count.
#include "render/ray_batch.h"

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <stdexcept>
#include <vector>

#include "accel/brute_force.h"
#include "accel/kd_tree.h"
#include "scene/procedural.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

// Rays from a box around two spheres toward random points near them: some hit, some miss.
std::vector<Ray> random_rays(std::size_t n) {
  std::vector<Ray> rays(n);
  std::uint64_t s = 17;
  auto unit = [&] { return static_cast<float>(splitmix64_mix(s += 0x9E3779B97F4A7C15ull) >> 40) * 0x1.0p-24f; };
  for (Ray& r : rays) {
    r.org = glm::vec3(unit() * 8.0f - 4.0f, unit() * 8.0f - 4.0f, 5.0f);
    const glm::vec3 target(unit() * 4.0f - 2.0f, unit() * 4.0f - 2.0f, unit() * 2.0f - 1.0f);
    r.dir = target - r.org;
    r.tfar = unit() < 0.3f ? 0.7f : kInfinity;  // some rays stop short of the spheres
  }
  return rays;
}

Scene two_spheres() {
  Scene scene;
  append_icosphere(scene, {0.0f, 0.0f, 0.0f}, 1.0f, 3, 0);
  append_icosphere(scene, {1.2f, 0.5f, -1.0f}, 0.7f, 2, 0);
  return scene;
}

bool same_bits(const Hit& a, const Hit& b) {
  return a.prim == b.prim && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
         std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
         std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

TEST(RayBatch, ChunksCoverEveryRayOnceIn64RayPieces) {
  for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{64}, std::size_t{130}}) {
    tbb::task_arena arena(2);
    std::vector<std::atomic<int>> seen(n);
    std::atomic<std::size_t> chunks{0};
    for_each_ray_chunk(arena, n, [&](std::size_t first, std::size_t count) {
      EXPECT_EQ(first % kRayBatchChunk, 0u);
      EXPECT_EQ(count, std::min(kRayBatchChunk, n - first));
      for (std::size_t i = first; i < first + count; ++i) seen[i]++;
      chunks++;
    });
    EXPECT_EQ(chunks.load(), (n + 63) / 64) << n << " rays";
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(seen[i].load(), 1) << "ray " << i << " of " << n;
  }
}

TEST(RayBatch, ClosestHitsAreTheOraclesInBothModesAndAnyThreadCount) {
  const Scene scene = two_spheres();
  const BruteForce oracle(scene.triangles);
  const KdTree kd(scene.triangles);
  const std::vector<Ray> rays = random_rays(1000);  // not a multiple of 64: a partial last chunk
  std::size_t hits_found = 0;
  for (int threads : {1, 2})
    for (TraceMode mode : {TraceMode::Packet, TraceMode::Single}) {
      tbb::task_arena arena(threads);
      std::vector<Hit> hits(rays.size());
      trace_closest(kd, rays, mode, arena, hits);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit expected = oracle.intersect(rays[i]);
        hits_found += expected.valid() ? 1 : 0;
        ASSERT_TRUE(same_bits(hits[i], expected))
            << "ray " << i << ", " << threads << " threads, mode " << trace_mode_name(mode);
      }
    }
  EXPECT_GT(hits_found, 4u * 100u);  // the rays do hit the spheres (4 runs of 1000 rays)
}

TEST(RayBatch, OcclusionIsTheOraclesAndSizesMustMatch) {
  const Scene scene = two_spheres();
  const BruteForce oracle(scene.triangles);
  const KdTree kd(scene.triangles);
  const std::vector<Ray> rays = random_rays(300);
  tbb::task_arena arena(2);
  for (const TraceMode mode : {TraceMode::Packet, TraceMode::Single}) {
    std::vector<std::uint8_t> occluded(rays.size(), 7);
    trace_occluded(kd, rays, mode, arena, occluded);
    std::size_t blocked = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      EXPECT_EQ(occluded[i], oracle.occluded(rays[i]) ? 1 : 0) << "ray " << i;
      blocked += occluded[i];
    }
    EXPECT_GT(blocked, 0u);
    EXPECT_LT(blocked, rays.size());
  }

  std::vector<Hit> short_hits(rays.size() - 1);
  EXPECT_THROW(trace_closest(kd, rays, TraceMode::Packet, arena, short_hits), std::invalid_argument);
  std::vector<std::uint8_t> short_occluded(rays.size() + 1);
  EXPECT_THROW(trace_occluded(kd, rays, TraceMode::Packet, arena, short_occluded), std::invalid_argument);
}

}  // namespace
}  // namespace lancer
