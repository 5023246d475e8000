// render_image: settings checks, tiles, progress, statistics and pixel sampling.
#include "render/renderer.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "render/tile_scheduler.h"
#include "render_test_scenes.h"

namespace lancer {
namespace {

using test::add_material;
using test::add_square_z;

// A floor at z = 0 lit by a point light, seen from above: every camera ray hits it.
Scene lit_floor() {
  Scene scene;
  add_square_z(scene, 0, 0, 0, 100, true, add_material(scene, test::diffuse_material({0.5f, 0.5f, 0.5f})));
  PunctualLight l;
  l.position = {0, 0, 2};
  l.intensity = 5.0f;
  scene.lights.push_back(l);
  return scene;
}

RenderSettings small_settings(int w, int h) {
  RenderSettings s;
  s.width = w;
  s.height = h;
  s.spp = 2;
  return s;
}

TEST(RenderSettings, IntegratorNamesRoundTrip) {
  for (IntegratorKind k : {IntegratorKind::Path, IntegratorKind::Whitted, IntegratorKind::Normals,
                           IntegratorKind::Albedo, IntegratorKind::Depth, IntegratorKind::Ao, IntegratorKind::PrimId})
    EXPECT_EQ(parse_integrator(integrator_name(k)), k);
  EXPECT_EQ(integrator_name(IntegratorKind::PrimId), "primid");
  EXPECT_EQ(integrator_name(IntegratorKind::Path), "path");
  EXPECT_FALSE(parse_integrator("bidirectional").has_value());
  EXPECT_FALSE(parse_integrator("").has_value());
  EXPECT_FALSE(parse_integrator("Whitted").has_value());
}

TEST(Renderer, RejectsInvalidSettings) {
  const Scene scene = lit_floor();
  const BruteForce accel(scene.triangles);
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 0.8f, 8, 6);
  RenderStats stats;
  auto expect_rejected = [&](void (*change)(RenderSettings&)) {
    RenderSettings s = small_settings(8, 6);
    change(s);
    EXPECT_THROW(render_image(scene, accel, cam, s, stats), std::invalid_argument);
  };
  expect_rejected([](RenderSettings& s) { s.width = 9; });  // camera is 8 x 6
  expect_rejected([](RenderSettings& s) { s.spp = 0; });
  expect_rejected([](RenderSettings& s) { s.tile_size = 0; });
  expect_rejected([](RenderSettings& s) { s.threads = -1; });
  expect_rejected([](RenderSettings& s) { s.max_depth = -1; });
  expect_rejected([](RenderSettings& s) { s.light_samples = -2; });
  expect_rejected([](RenderSettings& s) { s.emitter_samples = -1; });
  expect_rejected([](RenderSettings& s) { s.emitter_samples = 65; });
  // Its rays' sample indices would wrap around 2^32.
  expect_rejected([](RenderSettings& s) { s.spp = 1 << 27, s.emitter_samples = 64; });
  EXPECT_NO_THROW(render_image(scene, accel, cam, small_settings(8, 6), stats));
}

TEST(Tiles, CoverEveryPixelOnce) {
  for (auto [w, h, t] : {std::tuple{64, 64, 16}, std::tuple{37, 5, 16}, std::tuple{1, 1, 8}, std::tuple{10, 33, 7}}) {
    std::vector<int> covered(static_cast<std::size_t>(w) * h, 0);
    const std::vector<Tile> tiles = make_tiles(w, h, t);
    EXPECT_EQ(tiles.size(), static_cast<std::size_t>(((w + t - 1) / t) * ((h + t - 1) / t)));
    for (const Tile& tile : tiles) {
      EXPECT_LE(tile.x1 - tile.x0, t);
      EXPECT_LE(tile.y1 - tile.y0, t);
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) ++covered[static_cast<std::size_t>(y) * w + x];
    }
    EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }));
  }
  EXPECT_THROW(make_tiles(0, 4, 4), std::invalid_argument);
}

TEST(Tiles, OneThreadMeansNoConcurrency) {
  const std::vector<Tile> tiles = make_tiles(64, 64, 8);
  std::atomic<int> active{0}, most{0};
  std::atomic<std::size_t> calls{0};
  for_each_tile(
      tiles, 1,
      [&](const Tile&) {
        const int now = ++active;
        int prev = most.load();
        while (now > prev && !most.compare_exchange_weak(prev, now)) {
        }
        volatile double sink = 0;
        for (int i = 0; i < 20000; ++i) sink = sink + i;
        --active;
      },
      [&](std::size_t, std::size_t) { ++calls; });
  EXPECT_EQ(most.load(), 1);
  EXPECT_EQ(calls.load(), tiles.size());
}

TEST(Renderer, ProgressAfterEveryTileOfEveryPass) {
  const Scene scene = lit_floor();
  const BruteForce accel(scene.triangles);
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 0.8f, 40, 24);
  RenderSettings s = small_settings(40, 24);
  s.tile_size = 16;
  s.threads = 2;
  std::mutex m;
  std::vector<std::size_t> done;
  std::size_t total = 0;
  RenderStats stats;
  render_image(scene, accel, cam, s, stats, [&](std::size_t d, std::size_t t) {
    std::lock_guard<std::mutex> lock(m);
    done.push_back(d);
    total = t;
  });
  // One report per tile of each pass (one pass per sample): 3 x 2 tiles, spp passes.
  const std::size_t expected = 6u * static_cast<std::size_t>(s.spp);
  EXPECT_EQ(total, expected);
  std::sort(done.begin(), done.end());
  std::vector<std::size_t> all(expected);
  for (std::size_t i = 0; i < expected; ++i) all[i] = i + 1;
  EXPECT_EQ(done, all);
}

TEST(Renderer, CountsEveryRayAndTime) {
  const Scene scene = lit_floor();
  const BruteForce accel(scene.triangles);
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 0.8f, 20, 10);
  RenderSettings s = small_settings(20, 10);
  s.spp = 3;
  s.threads = 2;
  s.tile_size = 4;
  s.integrator = IntegratorKind::Whitted;
  RenderStats stats;
  render_image(scene, accel, cam, s, stats);
  EXPECT_EQ(stats.rays, 2u * 20 * 10 * 3);  // one camera ray and one shadow ray per sample
  EXPECT_GT(stats.seconds, 0.0);
  s.integrator = IntegratorKind::Depth;
  render_image(scene, accel, cam, s, stats);
  EXPECT_EQ(stats.rays, 20u * 10 * 3);
}

TEST(Renderer, JitterCoversThePixelAndBoxFilters) {
  // An emitter covering x > 0 seen straight on; the edge x = 0 runs through the middle of
  // the centre column of a 5 pixel wide image, so that column averages to half the emission.
  Scene scene;
  const std::uint32_t light = add_material(scene, test::emissive_material({1, 1, 1}));
  append_quad(scene, {0, -50, 0}, {50, -50, 0}, {50, 50, 0}, {0, 50, 0}, light);
  const BruteForce accel(scene.triangles);
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 0.5f, 5, 3);
  RenderSettings s = small_settings(5, 3);
  s.spp = 1024;
  RenderStats stats;
  const ImageRGB img = render_image(scene, accel, cam, s, stats);
  EXPECT_EQ(img.at(0, 1), glm::vec3(0.0f));
  EXPECT_EQ(img.at(4, 1), glm::vec3(1.0f));
  // Binomial: standard deviation 0.5 / 32 = 0.016; allow 4 sigma.
  EXPECT_NEAR(img.at(2, 1).x, 0.5f, 0.063f);
  // One sample per pixel still jitters: with the path's own camera ray alone (no emission
  // estimate apart, render/camera_emission.h) the centre column is 0 or 1 depending on the seed.
  s.spp = 1;
  s.emitter_samples = 0;
  int lit = 0;
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    s.seed = seed;
    lit += render_image(scene, accel, cam, s, stats).at(2, 1).x == 1.0f;
  }
  EXPECT_GT(lit, 5);
  EXPECT_LT(lit, 35);
  // The emission estimate's four rays of a sample are one Sobol' net of four points, one in
  // each quarter of the pixel's width: two see the emitter, whatever the seed.
  s.emitter_samples = 4;
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    s.seed = seed;
    EXPECT_EQ(render_image(scene, accel, cam, s, stats).at(2, 1).x, 0.5f) << "seed " << seed;
  }
}

}  // namespace
}  // namespace lancer
