// Motion blur: a render with the shutter open is the average of still renders over the
// shutter, within noise, shadows and bounces included (every ray of a path carries its
// camera sample's time); camera samples' times are stratified per pixel.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "accel/accel_factory.h"
#include "caustic_test_support.h"
#include "render/camera.h"
#include "render/pixel_filter.h"
#include "render/primary_block.h"
#include "render/renderer.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// A block sliding 3 units along x over the first second, over a floor, under a lamp: the
// block and its shadow both blur.
GltfBuilder sliding_block() {
  GltfBuilder b;
  const int grey = b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0.7, 0.7, 0.7, 1.0}},
                                                                   {"metallicFactor", 0.0}}}});
  const int red = b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.2, 0.1, 1.0}},
                                                                  {"metallicFactor", 0.0}}}});
  const int lamp = b.push("materials", {{"emissiveFactor", {8.0, 8.0, 8.0}}});
  const std::vector<std::uint16_t> quad = {0, 1, 2, 0, 2, 3};
  const int floor = b.add_mesh(
      {{"POSITION", b.add_vec3(std::vector<glm::vec3>{{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}})}}, 4,
      b.add_indices(quad), grey);
  const int light = b.add_mesh(
      {{"POSITION",
        b.add_vec3(std::vector<glm::vec3>{{-0.7f, 4, -0.7f}, {0.7f, 4, -0.7f}, {0.7f, 4, 0.7f}, {-0.7f, 4, 0.7f}})}},
      4, b.add_indices(quad), lamp);
  std::vector<glm::vec3> corners;
  for (int k = 0; k < 8; ++k) corners.emplace_back(k & 1 ? 0.5f : -0.5f, k & 2 ? 1.0f : 0.2f, k & 4 ? 0.5f : -0.5f);
  const std::vector<std::uint16_t> box = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                          2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  const int block = b.add_mesh({{"POSITION", b.add_vec3(corners)}}, 4, b.add_indices(box), red);
  b.set_scene({b.add_node({{"mesh", floor}}), b.add_node({{"mesh", light}}), b.add_node({{"mesh", block}})});
  gltf_test::animate(b, 2, "translation", {0.0f, 1.0f}, {-1.5f, 0, 0, 1.5f, 0, 0}, "VEC3", "LINEAR");
  return b;
}

class MotionBlur : public gltf_test::GltfTempDir {
 protected:
  static constexpr int kSize = 32;

  PinholeCamera camera(bool shutter) const {
    PinholeCamera c = PinholeCamera::look_at({0.0f, 6.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.8f, kSize, kSize);
    c.set_shutter_open(shutter);
    return c;
  }
  ImageRGB render(const Scene& scene, const PinholeCamera& cam, int spp, std::uint64_t seed) const {
    const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", scene.triangles, scene.instancing);
    RenderSettings s;
    s.width = s.height = kSize;
    s.spp = spp;
    s.max_depth = 3;
    s.threads = 2;
    s.seed = seed;
    RenderStats stats;
    return render_image(scene, *accel, cam, s, stats);
  }
};

TEST_F(MotionBlur, OpenShutterIsTheAverageOfStillsOverIt) {
  sliding_block().write_data_uri_gltf(path("slide.gltf"));
  const Scene blurred = read_gltf(path("slide.gltf"), -1, std::nullopt, InstancingMode::Auto, Shutter{0.0, 1.0});
  ASSERT_EQ(blurred.instancing.motions.size(), 1u);
  constexpr int kStills = 32, kSpp = 4;
  std::vector<Scene> stills;
  for (int k = 0; k < kStills; ++k)
    stills.push_back(read_gltf(path("slide.gltf"), -1, (k + 0.5) / kStills));
  const test::SeedStats moving =
      test::over_seeds(6, [&](std::uint64_t seed) { return render(blurred, camera(true), kStills * kSpp, seed); });
  const test::SeedStats average = test::over_seeds(6, [&](std::uint64_t seed) {
    ImageRGB sum;
    for (int k = 0; k < kStills; ++k) {
      const ImageRGB image = render(stills[std::size_t(k)], camera(false), kSpp, seed * 1000 + std::uint64_t(k));
      if (k == 0) sum = image;
      else
        for (std::size_t i = 0; i < sum.rgb.size(); ++i) sum.rgb[i] += image.rgb[i];
    }
    for (float& v : sum.rgb) v /= float(kStills);
    return sum;
  });
  const int resolved = test::expect_same_block_means(average, moving, "motion blur", 0.1);
  EXPECT_GE(resolved, 8) << "too few blocks resolve a 10% difference";
  // And it is not the still at the opening: the block has left that place.
  const test::SeedStats opening =
      test::over_seeds(6, [&](std::uint64_t seed) { return render(stills[0], camera(false), kStills * kSpp, seed); });
  int differ = 0;
  for (std::size_t i = 0; i < opening.mean.size(); ++i)
    differ += std::fabs(opening.mean[i] - moving.mean[i]) >
              5.0 * std::hypot(opening.stderr_[i], moving.stderr_[i]);
  EXPECT_GE(differ, 6) << "the blurred image should differ from the first still";
}

TEST(MotionBlurSamples, CameraRayTimesAreStratifiedPerPixel) {
  PinholeCamera cam = PinholeCamera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.8f, 8, 8);
  PrimaryBlock still;
  still.generate(cam, PixelFilter::box(), {0, 0, 8, 8}, 0, 3);
  for (int i = 0; i < still.size(); ++i) EXPECT_EQ(still.ray(i).time, 0.0f);
  cam.set_shutter_open(true);
  constexpr int kSamples = 16;
  for (int pixel : {0, 9, 63}) {
    std::set<int> strata;
    for (int s = 0; s < kSamples; ++s) {
      PrimaryBlock block;
      block.generate(cam, PixelFilter::box(), {0, 0, 8, 8}, s, 3);
      const float t = block.ray(pixel).time;
      ASSERT_GE(t, 0.0f);
      ASSERT_LT(t, 1.0f);
      strata.insert(int(t * kSamples));
    }
    EXPECT_EQ(strata.size(), std::size_t(kSamples)) << "pixel " << pixel << ": one sample per 1/16 of the shutter";
  }
}

}  // namespace
}  // namespace lancer

namespace lancer {
namespace {

// A camera sliding 2 units along x over the shutter: its rays at time t leave from where
// it is then, in the same directions (it does not turn).
TEST(MotionBlurCamera, RaysLeaveFromWhereTheCameraIsAtTheirTime) {
  CameraDesc desc;
  desc.camera_to_world[3] = glm::vec4(0.0f, 0.0f, 5.0f, 1.0f);
  for (int k = 0; k < 3; ++k) {
    MotionKey key;
    key.translation = glm::vec3(float(k), 0.0f, 5.0f);
    desc.motion.push_back(key);
  }
  const PinholeCamera cam = PinholeCamera::from_desc(desc, 8, 8);
  ASSERT_TRUE(cam.moves());
  for (float t : {0.0f, 0.25f, 0.5f, 1.0f}) {
    Ray r = cam.generate(3.5f, 4.5f);
    r.time = t;
    const Ray m = cam.moved(r);
    EXPECT_NEAR(m.org.x, r.org.x + 2.0f * t, 1e-5f) << "time " << t;
    EXPECT_NEAR(m.org.z, r.org.z, 1e-5f);
    EXPECT_NEAR(glm::length(m.dir - r.dir), 0.0f, 1e-6f);
    EXPECT_EQ(m.time, t);
  }
  desc.motion.clear();
  EXPECT_FALSE(PinholeCamera::from_desc(desc, 8, 8).moves());
}

}  // namespace
}  // namespace lancer
