// Progressive rendering (render_image with a RenderControl): the image after k passes is
// the spp = k image, checkpoints hand it out on the way, and a stop flag or a time limit
// end the render early with an image that averages what each pixel got.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/primary_block.h"
#include "render/renderer.h"
#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

const Scene& cornell() {
  static const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  return scene;
}

RenderSettings settings(int spp, int threads) {
  RenderSettings s;
  s.width = 24;
  s.height = 20;
  s.spp = spp;
  s.threads = threads;
  s.tile_size = 8;
  s.seed = 3;
  return s;
}

bool same_bits(const ImageRGB& a, const ImageRGB& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

ImageRGB render(const Accelerator& accel, const RenderSettings& s, RenderStats& stats, const ProgressCallback& p = {},
                const RenderControl& c = {}) {
  const PinholeCamera cam = PinholeCamera::from_desc(cornell().cameras.at(0), s.width, s.height);
  return render_image(cornell(), accel, cam, s, stats, p, c);
}

TEST(Progressive, CheckpointAfterKPassesIsTheSppKImage) {
  const KdTree kd(cornell().triangles);
  std::vector<ImageRGB> checkpoints;
  std::vector<int> passes;
  RenderControl control;
  control.checkpoint_s = 1e-9;  // after every pass but the last
  control.on_checkpoint = [&](const ImageRGB& image, int k) {
    checkpoints.push_back(image);
    passes.push_back(k);
  };
  RenderStats stats;
  const ImageRGB full = render(kd, settings(4, 2), stats, {}, control);
  EXPECT_EQ(stats.passes, 4);
  EXPECT_FALSE(stats.stopped);
  EXPECT_EQ(stats.min_spp, 4u);
  EXPECT_EQ(stats.max_spp, 4u);
  ASSERT_EQ(passes, (std::vector<int>{1, 2, 3}));
  for (int k = 1; k <= 3; ++k) {
    RenderStats st;
    EXPECT_TRUE(same_bits(checkpoints[static_cast<std::size_t>(k - 1)], render(kd, settings(k, 1), st)))
        << "checkpoint after " << k << " passes";
  }
  RenderStats st;
  EXPECT_TRUE(same_bits(full, render(kd, settings(4, 1), st)));
}

TEST(Progressive, StopFlagSetBeforeTheStartGivesABlackImageAtOnce) {
  const KdTree kd(cornell().triangles);
  std::atomic<int> stop{2};
  RenderControl control;
  control.stop = &stop;
  RenderStats stats;
  const ImageRGB image = render(kd, settings(8, 2), stats, {}, control);
  EXPECT_TRUE(stats.stopped);
  EXPECT_EQ(stats.passes, 0);
  EXPECT_EQ(stats.max_spp, 0u);
  for (float v : image.rgb) ASSERT_EQ(v, 0.0f);
}

// Stopped in the middle of pass 3 (after a fixed number of tiles, one thread): every pixel
// is exactly the spp = 2 or the spp = 3 image's pixel, and both kinds occur.
TEST(Progressive, StopMidPassAveragesWhatEachPixelGot) {
  const KdTree kd(cornell().triangles);
  std::atomic<int> stop{0};
  RenderControl control;
  control.stop = &stop;
  const std::size_t tiles = 3 * 3;  // 24 x 20 in 8 x 8 tiles
  RenderStats stats;
  const ImageRGB image = render(
      kd, settings(6, 1), stats,
      [&](std::size_t done, std::size_t) {
        if (done == 2 * tiles + 4) stop.store(2);
      },
      control);
  EXPECT_TRUE(stats.stopped);
  EXPECT_EQ(stats.passes, 2);
  EXPECT_EQ(stats.min_spp, 2u);
  EXPECT_EQ(stats.max_spp, 3u);
  RenderStats s2, s3;
  const ImageRGB two = render(kd, settings(2, 1), s2), three = render(kd, settings(3, 1), s3);
  int from_two = 0, from_three = 0;
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    const bool is_two = std::memcmp(&image.rgb[i], &two.rgb[i], 3 * sizeof(float)) == 0;
    const bool is_three = std::memcmp(&image.rgb[i], &three.rgb[i], 3 * sizeof(float)) == 0;
    ASSERT_TRUE(is_two || is_three) << "pixel " << i / 3;
    from_two += is_two && !is_three;
    from_three += is_three && !is_two;
  }
  EXPECT_GT(from_two, 0);
  EXPECT_GT(from_three, 0);
}

// What "stop within a few milliseconds" rests on: the stop flag is read before every
// wavefront (kWavefrontBlocks 8x8 blocks of a tile at most), so once it is set no wavefront
// starts, and each other thread finishes at most the one it is in. With one wavefront per
// tile (tiles of 8x8: one block; of 16x16: four), the callback that sets the flag after D
// tiles of a pass leaves at most D + threads - 1 tiles of that pass done, whatever the load.
TEST(Progressive, NoBlockStartsOnceTheStopFlagIsSet) {
  static_assert(kWavefrontBlocks == 4, "16x16 tiles are one wavefront");
  const KdTree kd(cornell().triangles);
  for (const int tile : {8, 16}) {
    for (const int threads : {1, 2, 4}) {
      for (const std::size_t d : {1u, 5u, 11u}) {
        std::atomic<int> stop{0};
        RenderControl control;
        control.stop = &stop;
        RenderSettings s = settings(1 << 20, threads);
        s.tile_size = tile;
        s.width = 6 * tile;
        s.height = 5 * tile;  // 6 x 5 tiles, one wavefront each
        const std::size_t tiles = 30, pass_of_stop = 2, tile_pixels = static_cast<std::size_t>(tile * tile);
        RenderStats stats;
        render(
            kd, s, stats,
            [&](std::size_t done, std::size_t) {
              if (done == pass_of_stop * tiles + d) stop.store(2);
            },
            control);
        ASSERT_TRUE(stats.stopped);
        EXPECT_EQ(stats.passes, static_cast<int>(pass_of_stop));
        EXPECT_EQ(stats.min_spp, pass_of_stop);
        // Pixels of the stopped pass: whole tiles, at most D + threads - 1 of them.
        const std::size_t extra = tile_pixels * (d + static_cast<std::size_t>(threads) - 1);
        EXPECT_LE(stats.max_spp, pass_of_stop + 1);
        EXPECT_LE(stats.pixels_past_min_spp, extra)
            << tile << "-pixel tiles, " << threads << " threads, stop after " << d << " tiles";
        EXPECT_GE(stats.pixels_past_min_spp, tile_pixels * d) << "the tiles reported done were rendered";
      }
    }
  }
}

// A stop from another thread while a long render runs: it returns with a finite image.
// (The bound only says "it did not hang"; NoBlockStartsOnceTheStopFlagIsSet is the guarantee.)
TEST(Progressive, StopFromAnotherThreadEndsALongRenderPromptly) {
  const KdTree kd(cornell().triangles);
  std::atomic<int> stop{0};
  RenderControl control;
  control.stop = &stop;
  std::chrono::steady_clock::time_point stopped_at;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    stopped_at = std::chrono::steady_clock::now();
    stop.store(2);
  });
  RenderStats stats;
  const ImageRGB image = render(kd, settings(1 << 20, 2), stats, {}, control);
  const double after_stop = std::chrono::duration<double>(std::chrono::steady_clock::now() - stopped_at).count();
  stopper.join();
  EXPECT_TRUE(stats.stopped);
  EXPECT_LT(after_stop, 10.0) << "seconds from the stop flag to the return";
  EXPECT_GE(stats.max_spp, 1u);
  for (float v : image.rgb) ASSERT_TRUE(std::isfinite(v));
}

TEST(Progressive, TimeLimitEndsTheRender) {
  const KdTree kd(cornell().triangles);
  RenderControl control;
  control.time_limit_s = 0.3;
  RenderStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  render(kd, settings(1 << 20, 2), stats, {}, control);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(stats.stopped);
  EXPECT_GE(took, 0.3);
  EXPECT_LT(took, 5.0);
  EXPECT_GE(stats.passes, 1);
}

// The photon mapper is progressive the same way, an iteration being its pass: the image after
// k iterations is the k-iteration render's, bit for bit, and the stop flag and the time limit
// end it between iterations.
RenderSettings sppm_settings(int iterations, int threads) {
  RenderSettings s = settings(iterations, threads);
  s.integrator = IntegratorKind::Sppm;
  s.photons = 2000;
  return s;
}

TEST(ProgressiveSppm, CheckpointAfterKIterationsIsTheKIterationImage) {
  const KdTree kd(cornell().triangles);
  std::vector<ImageRGB> checkpoints;
  std::vector<int> passes;
  RenderControl control;
  control.checkpoint_s = 1e-9;
  control.on_checkpoint = [&](const ImageRGB& image, int k) {
    checkpoints.push_back(image);
    passes.push_back(k);
  };
  RenderStats stats;
  const ImageRGB full = render(kd, sppm_settings(4, 2), stats, {}, control);
  EXPECT_EQ(stats.passes, 4);
  EXPECT_FALSE(stats.stopped);
  ASSERT_EQ(passes, (std::vector<int>{1, 2, 3}));
  for (int k = 1; k <= 3; ++k) {
    RenderStats st;
    EXPECT_TRUE(same_bits(checkpoints[static_cast<std::size_t>(k - 1)], render(kd, sppm_settings(k, 1), st)))
        << "checkpoint after " << k << " iterations";
  }
  RenderStats st;
  EXPECT_TRUE(same_bits(full, render(kd, sppm_settings(4, 1), st)));
}

TEST(ProgressiveSppm, StopFlagAndTimeLimitEndTheRender) {
  const KdTree kd(cornell().triangles);
  {
    std::atomic<int> stop{0};
    RenderControl control;
    control.stop = &stop;
    std::thread stopper([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      stop.store(2);
    });
    RenderStats stats;
    const ImageRGB image = render(kd, sppm_settings(1 << 20, 2), stats, {}, control);
    stopper.join();
    EXPECT_TRUE(stats.stopped);
    EXPECT_GE(stats.passes, 1);
    double sum = 0.0;
    for (float v : image.rgb) {
      ASSERT_TRUE(std::isfinite(v));
      sum += v;
    }
    EXPECT_GT(sum, 0.0);
  }
  RenderControl control;
  control.time_limit_s = 0.3;
  RenderStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  render(kd, sppm_settings(1 << 20, 2), stats, {}, control);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // No upper bound on the time: a loaded machine may take long over an iteration; the render
  // stopped early (of 2^20 iterations) and returned, which is what is tested.
  EXPECT_TRUE(stats.stopped);
  EXPECT_GE(took, 0.3);
  EXPECT_GE(stats.passes, 1);
}

}  // namespace
}  // namespace lancer
