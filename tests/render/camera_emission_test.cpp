// The emission seen directly, estimated by camera rays of its own (render/camera_emission.h):
// which blocks it covers, and that it splits the term with the path without bias and with
// less variance, against a scene whose image is known exactly.
#include "render/camera_emission.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/renderer.h"
#include "render_test_scenes.h"
#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

// The Cornell box's light shows at the top middle of its image; the floor's corners see none.
TEST(CameraEmission, CoversTheBlocksThatShowTheLightAndNoOthers) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box.gltf");
  const KdTree kd(scene.triangles);
  const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), 256, 256);
  TileRunner runner(2);
  const PixelFilter filter = PixelFilter::box();
  const CameraEmission emission(scene, kd, camera, filter, 256, 256, 4, runner);
  ASSERT_EQ(emission.cell_count(), 32u * 32u);
  // The light spans about x 105-150, y 31-40 at this size (its pixels there are 14-17 in red).
  EXPECT_TRUE(emission.covers(124, 35));
  EXPECT_TRUE(emission.covers(149, 41));
  EXPECT_FALSE(emission.covers(4, 252));
  EXPECT_FALSE(emission.covers(131, 131));
  EXPECT_FALSE(emission.covers(-1, 35));
  EXPECT_FALSE(emission.covers(124, 256));
  // mark() sets exactly covers() on a block's rays, wherever the block lies.
  PrimaryBlock primary;
  const PixelBlock straddling{101, 30, 109, 38};
  primary.add(camera, filter, straddling, 0, 0);
  EXPECT_TRUE(emission.mark(straddling, primary, 0));
  for (int i = 0; i < straddling.pixel_count(); ++i)
    EXPECT_EQ(primary.emission_apart()[i], emission.covers(101 + i % 8, 30 + i / 8)) << i;
  const PixelBlock far_off{0, 248, 8, 256};
  primary.add(camera, filter, far_off, 0, 0);
  EXPECT_FALSE(emission.mark(far_off, primary, 64));
  // The light's cells and their neighbours: a few percent of the image.
  EXPECT_GT(emission.covered_cells(), 6u);
  EXPECT_LT(emission.covered_cells(), 64u);
}

TEST(CameraEmission, CoversNothingWithoutAnEmissiveMaterial) {
  Scene scene;
  test::add_square_z(scene, 0.0f, 0.0f, -2.0f, 1.0f, true, test::add_material(scene, test::diffuse_material(glm::vec3(0.5f))));
  const KdTree kd(scene.triangles);
  const PinholeCamera camera =
      PinholeCamera::look_at(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0.0f, 1.0f, 0.0f), 1.0f, 40, 24);
  TileRunner runner(1);
  const PixelFilter filter = PixelFilter::box();
  const CameraEmission emission(scene, kd, camera, filter, 40, 24, 4, runner);
  EXPECT_EQ(emission.cell_count(), 5u * 3u);
  EXPECT_EQ(emission.covered_cells(), 0u);
}

// Renders `scene` four times (seeds 0-3) without the estimate and four times with four rays
// per sample, against `exact` (the red channel, row by row): each way's summed squared
// error, mean image sum and camera-emission rays.
struct AgainstExact {
  double error[2] = {0.0, 0.0}, mean_sum[2] = {0.0, 0.0};
  std::uint64_t emission_rays[2] = {0, 0};
};
AgainstExact render_against_exact(const Scene& scene, const KdTree& kd, const PinholeCamera& camera,
                                  RenderSettings s, const std::vector<double>& exact) {
  AgainstExact r;
  for (int with = 0; with < 2; ++with) {
    s.emitter_samples = with ? 4 : 0;
    for (std::uint64_t seed = 0; seed < 4; ++seed) {
      s.seed = seed;
      RenderStats stats;
      const ImageRGB image = render_image(scene, kd, camera, s, stats);
      r.emission_rays[with] += stats.path_batches.emission_rays;
      for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
          const double got = image.at(x, y).x, want = exact[static_cast<std::size_t>(y * s.width + x)];
          r.error[with] += (got - want) * (got - want);
          r.mean_sum[with] += got / 4.0;
        }
    }
  }
  return r;
}

// An emissive square facing a pinhole camera on its axis, nothing else: each pixel's value
// is the radiance times the fraction of the pixel the square's image covers, a square of
// half-side 7.3 pixels about the image centre. Rendered with and without the estimate, the
// mean stays the exact one, and the per-pixel error falls several times over (the edges
// are the only noise there is). For the path tracer (alone and with the caustic photon
// map) and for SPPM's camera paths alike.
class EmitterImage : public ::testing::TestWithParam<IntegratorKind> {};

TEST_P(EmitterImage, SplitsTheDirectEmissionWithoutBiasAndWithLessNoise) {
  constexpr int kSize = 32;
  constexpr float kHalfPixels = 7.3f;
  const glm::vec3 radiance(2.0f, 1.0f, 0.5f);
  const float vfov = 0.8f;
  const float focal = 0.5f * kSize / std::tan(0.5f * vfov);  // pixels per unit at distance 1
  const float distance = 3.0f, half = kHalfPixels * distance / focal;
  Scene scene;
  test::add_square_z(scene, 0.0f, 0.0f, -distance, half, true, test::add_material(scene, test::emissive_material(radiance)));
  const KdTree kd(scene.triangles);
  const PinholeCamera camera = PinholeCamera::look_at(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f),
                                                      glm::vec3(0.0f, 1.0f, 0.0f), vfov, kSize, kSize);
  const auto covered = [&](int p) {  // overlap of [p, p + 1] with the image's [c - h, c + h]
    const double lo = 0.5 * kSize - kHalfPixels, hi = 0.5 * kSize + kHalfPixels;
    return std::max(0.0, std::min<double>(p + 1, hi) - std::max<double>(p, lo));
  };
  RenderSettings s;
  s.width = s.height = kSize;
  s.spp = 16;
  s.threads = 2;
  s.max_depth = 2;
  s.integrator = GetParam();
  std::vector<double> exact(kSize * kSize);
  double exact_mean = 0.0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) exact_mean += exact[y * kSize + x] = radiance.x * covered(x) * covered(y);
  const AgainstExact r = render_against_exact(scene, kd, camera, s, exact);
  const double* error = r.error;
  const double* mean = r.mean_sum;
  const std::uint64_t* emission_rays = r.emission_rays;
  EXPECT_EQ(emission_rays[0], 0u);
  EXPECT_EQ(emission_rays[1], 4u * 16u * 4u * kSize * kSize);  // every block shows the square
  // The image sums to the square's area in pixels times the radiance, up to the noise of
  // its 58 edge pixels (measured for the path tracer: 0.002 % and 0.02 % off; counting the
  // emission twice or not at all would be 100 % off).
  EXPECT_NEAR(mean[0], exact_mean, 0.002 * exact_mean);
  EXPECT_NEAR(mean[1], exact_mean, 0.002 * exact_mean);
  // Four rays per sample, one Sobol' net of 64 points per pixel: the edge variance falls
  // about 4^1.5 = 8 times (measured: 15 times).
  EXPECT_GT(error[0], 0.0);
  EXPECT_LT(error[1], error[0] / 4.0);
}

INSTANTIATE_TEST_SUITE_P(CameraEmission, EmitterImage,
                         ::testing::Values(IntegratorKind::Path, IntegratorKind::Photon, IntegratorKind::Sppm),
                         [](const ::testing::TestParamInfo<IntegratorKind>& param_info) {
                           return std::string(integrator_name(param_info.param));
                         });

// Which pixels estimate emission apart depends on the pixel alone, never on the block or
// tile it is rendered in: with a lens so wide that the light's blur runs far past the cells
// its corner rays found (and their neighbours), tiles of 5, 12 and 16 pixels (blocks that
// straddle covered and uncovered cells) give the same bytes.
TEST(CameraEmission, ThePixelsThatUseItDoNotDependOnTheTiles) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box.gltf");
  const KdTree kd(scene.triangles);
  PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), 64, 64);
  camera.set_thin_lens(0.05f, 0.3f);  // the light, 1 m away, blurred over about 10 % of the image
  RenderSettings s;
  s.width = s.height = 64;
  s.spp = 2;
  s.threads = 2;
  s.max_depth = 3;
  std::vector<ImageRGB> images;
  std::uint64_t emission_rays = 0;
  for (const int tile : {16, 5, 12}) {
    s.tile_size = tile;
    RenderStats stats;
    images.push_back(render_image(scene, kd, camera, s, stats));
    if (tile == 16) emission_rays = stats.path_batches.emission_rays;
    else EXPECT_EQ(stats.path_batches.emission_rays, emission_rays) << "tile " << tile;
  }
  EXPECT_GT(emission_rays, 0u);
  EXPECT_EQ(images[1].rgb, images[0].rgb);
  EXPECT_EQ(images[2].rgb, images[0].rgb);
}

// A first surface of coverage below 1 is the path's to count (it passes it or stops there
// by chance), so an emitter drawn with BLEND at alpha 0.5 renders the very same image with
// the estimate as without, although its rays are traced.
TEST(CameraEmission, LeavesASurfaceOfPartialCoverageToThePath) {
  Material glow = test::emissive_material(glm::vec3(2.0f, 1.0f, 0.5f));
  glow.alpha_mode = AlphaMode::Blend;
  glow.base_color.w = 0.5f;
  Scene scene;
  test::add_square_z(scene, 0.0f, 0.0f, -3.0f, 0.5f, true, test::add_material(scene, glow));
  test::add_square_z(scene, 0.0f, 0.0f, -4.0f, 2.0f, true,
                     test::add_material(scene, test::diffuse_material(glm::vec3(0.5f))));
  const KdTree kd(scene.triangles);
  const PinholeCamera camera = PinholeCamera::look_at(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f),
                                                      glm::vec3(0.0f, 1.0f, 0.0f), 0.8f, 24, 24);
  RenderSettings s;
  s.width = s.height = 24;
  s.spp = 8;
  s.threads = 2;
  ImageRGB images[2];
  std::uint64_t emission_rays[2] = {0, 0};
  for (int with = 0; with < 2; ++with) {
    s.emitter_samples = with ? 4 : 0;
    RenderStats stats;
    images[with] = render_image(scene, kd, camera, s, stats);
    emission_rays[with] = stats.path_batches.emission_rays;
  }
  EXPECT_EQ(emission_rays[0], 0u);
  EXPECT_GT(emission_rays[1], 0u);
  EXPECT_EQ(images[0].rgb, images[1].rgb);
  EXPECT_GT(images[0].at(12, 12).x, 0.0f);
}

// The estimate counts emission only toward the sides the material emits to (glTF 2.0,
// "Double Sided"), as the path does: a single-sided emitter that is a volume boundary
// (thickness > 0, so its back face is not culled) seen from behind shows nothing, with or
// without the estimate, although its pixels are chosen (they see an emissive material); made
// double-sided, its back shows the radiance, both ways alike.
TEST(CameraEmission, CountsEmissionOnlyTowardTheSidesThatEmit) {
  constexpr int kSize = 24;
  for (const bool double_sided : {false, true}) {
    Material glow = test::emissive_material(glm::vec3(2.0f, 1.0f, 0.5f));
    glow.thickness = 0.1f;
    glow.double_sided = double_sided;
    Scene scene;
    test::add_square_z(scene, 0.0f, 0.0f, -3.0f, 0.5f, /*facing_up=*/false, test::add_material(scene, glow));
    const KdTree kd(scene.triangles);
    const PinholeCamera camera = PinholeCamera::look_at(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f),
                                                        glm::vec3(0.0f, 1.0f, 0.0f), 0.8f, kSize, kSize);
    RenderSettings s;
    s.width = s.height = kSize;
    s.spp = 8;
    s.threads = 2;
    double sum[2] = {0.0, 0.0};
    std::uint64_t emission_rays[2] = {0, 0};
    for (int with = 0; with < 2; ++with) {
      s.emitter_samples = with ? 4 : 0;
      RenderStats stats;
      const ImageRGB image = render_image(scene, kd, camera, s, stats);
      emission_rays[with] = stats.path_batches.emission_rays;
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) sum[with] += image.at(x, y).x;
    }
    EXPECT_EQ(emission_rays[0], 0u);
    EXPECT_GT(emission_rays[1], 0u) << "the back-facing emitter's pixels are chosen";
    if (!double_sided) {
      EXPECT_EQ(sum[0], 0.0);
      EXPECT_EQ(sum[1], 0.0);
    } else {
      EXPECT_GT(sum[0], 0.0);
      EXPECT_NEAR(sum[1], sum[0], 0.01 * sum[0]);
    }
  }
}

// A camera sliding along x while the shutter is open sees an emissive square move across
// its image: each pixel's exact value is the radiance times the square's coverage of it
// averaged over the shutter. The estimate's camera rays take their samples' times and move
// with the camera (camera_ray, which the paths use too), so with the estimate the image
// stays the exact one up to noise, and the per-pixel error falls; rays made where the camera
// was at the opening would show the square unblurred, far from it.
TEST(CameraEmission, FollowsAMovingCamera) {
  constexpr int kSize = 32;
  constexpr float kHalfPixels = 5.3f;
  const glm::vec3 radiance(2.0f, 1.0f, 0.5f);
  const float vfov = 0.8f, distance = 3.0f, slide = 1.0f;
  const float focal = 0.5f * kSize / std::tan(0.5f * vfov);  // pixels per unit at distance 1
  const float half = kHalfPixels * distance / focal;
  const double shift = slide * focal / distance;  // pixels the square moves left over the shutter
  Scene scene;
  test::add_square_z(scene, 0.0f, 0.0f, -distance, half, true, test::add_material(scene, test::emissive_material(radiance)));
  const KdTree kd(scene.triangles);
  CameraDesc desc;
  desc.yfov = vfov;
  for (const float x : {0.0f, slide}) {
    MotionKey key;
    key.translation = glm::vec3(x, 0.0f, 0.0f);
    desc.motion.push_back(key);
  }
  PinholeCamera camera = PinholeCamera::from_desc(desc, kSize, kSize);
  camera.set_shutter_open(true);
  ASSERT_TRUE(camera.moves());
  const auto overlap = [](double p, double lo, double hi) {
    return std::max(0.0, std::min(p + 1.0, hi) - std::max(p, lo));
  };
  std::vector<double> exact(kSize * kSize, 0.0);
  constexpr int kSteps = 4096;
  for (int x = 0; x < kSize; ++x) {
    double blurred = 0.0;  // the x coverage, averaged over the shutter
    for (int k = 0; k < kSteps; ++k) {
      const double centre = 0.5 * kSize - shift * (k + 0.5) / kSteps;
      blurred += overlap(x, centre - kHalfPixels, centre + kHalfPixels) / kSteps;
    }
    for (int y = 0; y < kSize; ++y)
      exact[y * kSize + x] = radiance.x * blurred * overlap(y, 0.5 * kSize - kHalfPixels, 0.5 * kSize + kHalfPixels);
  }
  RenderSettings s;
  s.width = s.height = kSize;
  s.spp = 16;
  s.threads = 2;
  s.max_depth = 1;
  double exact_sum = 0.0;
  for (const double e : exact) exact_sum += e;
  const AgainstExact r = render_against_exact(scene, kd, camera, s, exact);
  EXPECT_EQ(r.emission_rays[0], 0u);
  EXPECT_GT(r.emission_rays[1], 0u);
  const double* error = r.error;
  const double* sum = r.mean_sum;
  std::printf("[ info     ] moving camera: sums %.2f and %.2f against %.2f, squared error %.3f and %.3f\n", sum[0],
              sum[1], exact_sum, error[0], error[1]);
  // Four standard deviations of the mean image's sum: each image's sum varies by about the
  // root of its squared error (over a quarter of the total), the mean of four by half that.
  EXPECT_NEAR(sum[0], exact_sum, std::sqrt(error[0]));
  EXPECT_NEAR(sum[1], exact_sum, std::sqrt(error[1]));
  EXPECT_GT(error[0], 0.0);
  EXPECT_LT(error[1], error[0] / 2.0);
}

}  // namespace
}  // namespace lancer
