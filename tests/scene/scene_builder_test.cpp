// SceneBuilder: per-corner arrays cost nothing until a triangle has the attribute, then
// line up with the triangles; finished arrays keep no spare capacity.
#include "scene/scene_builder.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace lancer {
namespace {

const glm::vec3 kCorners[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

TEST(SceneBuilder, AttributesNoTriangleHasStayEmpty) {
  Scene scene;
  SceneBuilder builder(scene, "test");
  for (std::uint32_t i = 0; i < 100; ++i) ASSERT_TRUE(builder.add_triangle(kCorners, 0, i));
  builder.finish();
  EXPECT_EQ(scene.triangle_count(), 100u);
  EXPECT_TRUE(scene.normals.empty());
  EXPECT_TRUE(scene.texcoords.empty());
  EXPECT_TRUE(scene.tangents.empty());
  EXPECT_TRUE(scene.texcoords1.empty());
}

TEST(SceneBuilder, ALateAttributePadsTheEarlierCornersWithZeros) {
  Scene scene;
  SceneBuilder builder(scene, "test");
  ASSERT_TRUE(builder.add_triangle(kCorners, 0, 0));
  ASSERT_TRUE(builder.add_triangle(kCorners, 0, 1));
  const glm::vec3 normals[3] = {{0, 0, 2}, {0, 0, 1}, {0, 0, 3}};
  const glm::vec2 uv[3] = {{0.25f, 0.5f}, {1, 0}, {0, 1}};
  CornerAttributes with_normals;
  with_normals.normals = normals;
  ASSERT_TRUE(builder.add_triangle(kCorners, 0, 2, with_normals));
  CornerAttributes with_uv;
  with_uv.texcoords = uv;
  ASSERT_TRUE(builder.add_triangle(kCorners, 0, 3, with_uv));
  builder.finish();

  ASSERT_EQ(scene.normals.size(), 12u);
  for (int c = 0; c < 6; ++c) EXPECT_EQ(scene.normals[c], glm::vec3(0.0f)) << "corner " << c;
  for (int c = 6; c < 9; ++c) EXPECT_EQ(scene.normals[c], glm::vec3(0, 0, 1)) << "corner " << c << ": unit length";
  for (int c = 9; c < 12; ++c) EXPECT_EQ(scene.normals[c], glm::vec3(0.0f)) << "corner " << c;
  ASSERT_EQ(scene.texcoords.size(), 12u);
  EXPECT_EQ(scene.texcoords[8], glm::vec2(0.0f));
  EXPECT_EQ(scene.texcoords[9], glm::vec2(0.25f, 0.5f));
  EXPECT_TRUE(scene.tangents.empty());
  EXPECT_EQ(scene.attrib_flags, (std::vector<std::uint8_t>{0, 0, kHasNormals, kHasTexcoords}));
}

TEST(SceneBuilder, TinyAndHugeNormalsComeOutUnitLength) {
  // Components whose squares are float denormals (1e-20) or overflow (1e30): the length
  // is taken in double, so the normals still come out unit (a fuzzed Draco file had them).
  Scene scene;
  SceneBuilder builder(scene, "test");
  const glm::vec3 normals[3] = {{1e-20f, 2e-20f, 2e-20f}, {0, 3e-23f, 4e-23f}, {1e30f, 0, 1e30f}};
  CornerAttributes attribs;
  attribs.normals = normals;
  ASSERT_TRUE(builder.add_triangle(kCorners, 0, 0, attribs));
  builder.finish();
  ASSERT_EQ(scene.normals.size(), 3u);
  EXPECT_EQ(scene.attrib_flags[0], kHasNormals);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(glm::length(scene.normals[c]), 1.0f, 1e-6f) << "corner " << c;
  EXPECT_NEAR(scene.normals[0].x, 1.0f / 3.0f, 1e-6f);
}

TEST(SceneBuilder, FinishedArraysKeepNoSpareCapacity) {
  Scene scene;
  SceneBuilder builder(scene, "test");
  const glm::vec3 normals[3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  CornerAttributes attribs;
  attribs.normals = normals;
  // 1025 triangles: the arrays grew by doubling to room for 2048.
  for (std::uint32_t i = 0; i < 1025; ++i) ASSERT_TRUE(builder.add_triangle(kCorners, 0, i, attribs));
  builder.finish();
  const std::size_t n = scene.triangle_count();
  ASSERT_EQ(n, 1025u);
  for (int k = 0; k < 3; ++k) EXPECT_LE(scene.triangles.x[k].capacity(), n + n / 16);
  EXPECT_LE(scene.material_id.capacity(), n + n / 16);
  EXPECT_LE(scene.source_triangle_id.capacity(), n + n / 16);
  EXPECT_LE(scene.attrib_flags.capacity(), n + n / 16);
  EXPECT_LE(scene.normals.capacity(), 3 * n + 3 * n / 16);
}

}  // namespace
}  // namespace lancer
