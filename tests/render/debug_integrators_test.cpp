// The debug views: normals, depth and primitive ids.
#include "render/debug_integrators.h"

#include <cmath>
#include <set>
#include <tuple>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "render/renderer.h"
#include "render_test_scenes.h"

namespace lancer {
namespace {

ImageRGB render_debug(const Scene& scene, const PinholeCamera& cam, IntegratorKind kind, int spp = 2,
                      std::uint64_t seed = 0) {
  const BruteForce accel(scene.triangles);
  RenderSettings s;
  s.width = cam.width();
  s.height = cam.height();
  s.spp = spp;
  s.integrator = kind;
  s.seed = seed;
  RenderStats stats;
  return render_image(scene, accel, cam, s, stats);
}

// A floor at z = 0 facing +z, filling the view of a camera 3 above it looking down.
struct Floor {
  Scene scene;
  Floor() { test::add_square_z(scene, 0, 0, 0, 100, true, test::add_material(scene, test::diffuse_material({1, 1, 1}))); }
};

PinholeCamera down_camera(float z, int w = 17, int h = 17) {
  return PinholeCamera::look_at({0.1f, 0.2f, z}, {0.1f, 0.2f, 0}, {0, 1, 0}, 0.8f, w, h);
}

TEST(DebugNormals, StoredNormalMappedToColour) {
  const Floor f;
  for (float z : {3.0f, -3.0f}) {  // from above and from below: the stored normal either way
    const ImageRGB img = render_debug(f.scene, down_camera(z), IntegratorKind::Normals);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) EXPECT_EQ(img.at(x, y), glm::vec3(0.5f, 0.5f, 1.0f)) << x << "," << y;
  }
}

TEST(DebugViews, MissIsBlack) {
  const Floor f;
  const PinholeCamera up = PinholeCamera::look_at({0, 0, 3}, {0, 0, 10}, {0, 1, 0}, 0.8f, 8, 8);
  for (IntegratorKind k : {IntegratorKind::Normals, IntegratorKind::Depth, IntegratorKind::PrimId}) {
    const ImageRGB img = render_debug(f.scene, up, k);
    for (float v : img.rgb) EXPECT_EQ(v, 0.0f);
  }
}

TEST(DebugDepth, DistanceAlongTheUnitRay) {
  const Floor f;
  const PinholeCamera cam = down_camera(3.0f);
  const ImageRGB img = render_debug(f.scene, cam, IntegratorKind::Depth, 4);
  // Every sample's depth is 3 / cos(angle off the axis), between 3 and the corner's value.
  const float corner = 3.0f / glm::dot(cam.generate(0, 0).dir, cam.forward());
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::vec3 d = img.at(x, y);
      EXPECT_EQ(d.x, d.y);
      EXPECT_EQ(d.x, d.z);
      EXPECT_GE(d.x, 3.0f * (1 - 1e-6f));
      EXPECT_LE(d.x, corner * (1 + 1e-6f));
    }
  // The centre pixel is within a fraction of a pixel of the axis.
  EXPECT_NEAR(img.at(8, 8).x, 3.0f, 1e-3f);
  // Further from the centre is deeper.
  EXPECT_GT(img.at(0, 8).x, img.at(4, 8).x);
  EXPECT_GT(img.at(4, 8).x, img.at(8, 8).x);
}

TEST(DebugPrimId, ColourOfTheSourceTriangle) {
  const Floor f;
  ASSERT_EQ(f.scene.triangle_count(), 2u);
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 0.8f, 16, 16);
  const ImageRGB img = render_debug(f.scene, cam, IntegratorKind::PrimId, 1);
  // The quad is split along the diagonal through (-100, -100) and (100, 100): triangle 0 has
  // x > y (lower right in the image), triangle 1 the upper left.
  const glm::vec3 c0 = primid_color(f.scene.source_triangle_id[0]);
  const glm::vec3 c1 = primid_color(f.scene.source_triangle_id[1]);
  EXPECT_NE(c0, c1);
  EXPECT_EQ(img.at(14, 14), c0);
  EXPECT_EQ(img.at(1, 1), c1);
}

TEST(DebugPrimId, ColoursAreDistinctAndVisible) {
  std::set<std::tuple<float, float, float>> colours;
  for (std::uint32_t id = 0; id < 1000; ++id) {
    const glm::vec3 c = primid_color(id);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(c[k], 0.15f);
      EXPECT_LE(c[k], 1.0f);
    }
    colours.insert({c.x, c.y, c.z});
  }
  EXPECT_GE(colours.size(), 995u);
}

}  // namespace
}  // namespace lancer
