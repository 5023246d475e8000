// glTF skins and morph targets in the pose the file gives, or its animation at a time: a two-bone
// strip whose second joint turns 90 degrees bends 90 degrees, the skinned node's own
// transform is ignored, morph weights (node over mesh) move the vertices, and malformed
// skins are refused with a message.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// A strip along +x from 0 to 2, 0.2 wide (y in [-0.1, 0.1]), as 4 quads; joint 0 at the
// origin holds the vertices with x <= 1, joint 1 (its child, at x = 1) the others.
// Joint 1 turns 90 degrees about +z. The mesh node is translated by (5, 5, 5), which a
// skinned mesh must ignore.
GltfBuilder two_bone_strip() {
  GltfBuilder b;
  std::vector<glm::vec3> positions, normals;
  std::vector<std::uint8_t> joints;
  std::vector<glm::vec4> weights;
  for (int i = 0; i <= 4; ++i)
    for (float y : {-0.1f, 0.1f}) {
      const float x = 0.5f * float(i);
      positions.emplace_back(x, y, 0.0f);
      normals.emplace_back(0.0f, 0.0f, 1.0f);
      joints.insert(joints.end(), {std::uint8_t(x <= 1.0f ? 0 : 1), 0, 0, 0});
      weights.emplace_back(1.0f, 0.0f, 0.0f, 0.0f);
    }
  std::vector<std::uint16_t> indices;
  for (std::uint16_t i = 0; i < 4; ++i) {
    const std::uint16_t a = std::uint16_t(2 * i), c = std::uint16_t(a + 2);
    indices.insert(indices.end(), {a, c, std::uint16_t(a + 1), std::uint16_t(a + 1), c, std::uint16_t(c + 1)});
  }
  const int j = b.add_accessor(b.add_view(joints.data(), joints.size()), GltfBuilder::kUByte, positions.size(), "VEC4");
  const int mesh = b.add_mesh({{"POSITION", b.add_vec3(positions)},
                               {"NORMAL", b.add_vec3(normals)},
                               {"JOINTS_0", j},
                               {"WEIGHTS_0", b.add_vec4(weights)}},
                              4, b.add_indices(indices));
  // Inverse bind matrices: joint 0 bound at the origin, joint 1 at (1, 0, 0).
  const std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
                                  1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1};
  const int ibm_accessor =
      b.add_accessor(b.add_view(ibm.data(), ibm.size() * sizeof(float)), GltfBuilder::kFloat, 2, "MAT4");
  const double s = std::sqrt(0.5);
  const int joint1 = b.add_node({{"translation", {1.0, 0.0, 0.0}}, {"rotation", {0.0, 0.0, s, s}}});
  const int joint0 = b.add_node({{"children", {joint1}}});
  b.push("skins", {{"joints", {joint0, joint1}}, {"inverseBindMatrices", ibm_accessor}});
  const int skinned = b.add_node({{"mesh", mesh}, {"skin", 0}, {"translation", {5.0, 5.0, 5.0}}});
  b.set_scene({joint0, skinned});
  return b;
}

class GltfSkins : public gltf_test::GltfTempDir {
 protected:
  Scene load(const GltfBuilder& b, std::optional<double> frame_time = std::nullopt) {
    b.write_data_uri_gltf(path("file.gltf"));
    return read_gltf(path("file.gltf"), -1, frame_time);
  }
};

TEST_F(GltfSkins, TwoBoneStripBendsNinetyDegrees) {
  const Scene s = load(two_bone_strip());
  ASSERT_EQ(s.triangle_count(), 8u);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (std::uint32_t t = 0; t < s.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c) {
      lo = glm::min(lo, s.triangles.vertex(t, c));
      hi = glm::max(hi, s.triangles.vertex(t, c));
    }
  // The first half stays on the x axis, the second turns to run up +y from (1, 0): the
  // tip (2, +-0.1) goes to (1 -+ 0.1, 1). Nothing is moved by the node's (5, 5, 5).
  EXPECT_NEAR(lo.x, 0.0f, 1e-6f);
  EXPECT_NEAR(hi.x, 1.1f, 1e-6f);
  EXPECT_NEAR(lo.y, -0.1f, 1e-6f);
  EXPECT_NEAR(hi.y, 1.0f, 1e-6f);
  EXPECT_NEAR(hi.z - lo.z, 0.0f, 1e-6f);
  // The last quad (triangles 6, 7) now runs along +y: its edges are x = 0.9 and x = 1.1.
  for (std::uint32_t t = 6; t < 8; ++t)
    for (int c = 0; c < 3; ++c) {
      const glm::vec3 p = s.triangles.vertex(t, c);
      EXPECT_NEAR(std::min(std::abs(p.x - 0.9f), std::abs(p.x - 1.1f)), 0.0f, 1e-6f) << "triangle " << t;
      EXPECT_GE(p.y, 0.5f - 1e-6f) << "triangle " << t;
    }
  // Every triangle still faces +z (a rotation mirrors nothing), normals too.
  for (std::uint32_t t = 0; t < s.triangle_count(); ++t) {
    const glm::vec3 e1 = s.triangles.vertex(t, 1) - s.triangles.vertex(t, 0);
    const glm::vec3 e2 = s.triangles.vertex(t, 2) - s.triangles.vertex(t, 0);
    EXPECT_GT(glm::cross(e1, e2).z, 0.0f) << "triangle " << t;
    EXPECT_NEAR(glm::length(s.normals[3 * t] - glm::vec3(0, 0, 1)), 0.0f, 1e-6f) << "triangle " << t;
  }
}

TEST_F(GltfSkins, JointsOutsideTheirRangeAndBadSkinsAreRefused) {
  {
    GltfBuilder b = two_bone_strip();
    b.doc["skins"][0]["joints"] = {0};  // one joint, but vertices name joint 1
    expect_error(b, "joint 1 out of range (the skin has 1 joints)");
  }
  {
    GltfBuilder b = two_bone_strip();
    b.doc["skins"][0]["joints"] = {0, 1, 0};
    expect_error(b, "skin 0 has 3 joints but 2 inverseBindMatrices");
  }
  {
    GltfBuilder b = two_bone_strip();
    b.doc["nodes"][2]["skin"] = 4;
    expect_error(b, "skin index 4 out of range");
  }
  {
    GltfBuilder b = two_bone_strip();
    b.doc["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
    expect_error(b, "has JOINTS_0 without WEIGHTS_0");
  }
  {
    GltfBuilder b = two_bone_strip();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] =
        b.add_vec4(std::vector<glm::vec4>(10, glm::vec4(0.0f)));
    expect_error(b, "vertex 0 has no joint weight");
  }
}

// One triangle with one morph target moving its third vertex up by (0, 0, 1).
GltfBuilder morphing_triangle() {
  GltfBuilder b;
  const int pos = b.add_vec3(gltf_test::unit_triangle());
  const int delta = b.add_vec3(std::vector<glm::vec3>{{0, 0, 0}, {0, 0, 0}, {0, 0, 1}});
  json prim = {{"attributes", {{"POSITION", pos}}}, {"mode", 4}, {"targets", json::array({{{"POSITION", delta}}})}};
  b.push("meshes", {{"primitives", json::array({prim})}, {"weights", {0.25}}});
  b.single_node_scene(0);
  return b;
}

float third_vertex_z(const Scene& s) {
  float z = 0.0f;
  for (int c = 0; c < 3; ++c) z = std::max(z, s.triangles.vertex(0, c).z);
  return z;
}

TEST_F(GltfSkins, MorphWeightsMoveTheVerticesNodeWeightsFirst) {
  EXPECT_NEAR(third_vertex_z(load(morphing_triangle())), 0.25f, 1e-6f) << "the mesh's weight";
  GltfBuilder b = morphing_triangle();
  b.doc["nodes"][0]["weights"] = {0.75};
  EXPECT_NEAR(third_vertex_z(load(b)), 0.75f, 1e-6f) << "the node's weight overrides the mesh's";
  b.doc["nodes"][0]["weights"] = {0.5, 0.5};
  expect_error(b, "has 1 morph targets but 2 weights are given");
}

using gltf_test::animate;

float highest_y(const Scene& s) {
  float hi = -1e30f;
  for (std::uint32_t t = 0; t < s.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c) hi = std::max(hi, s.triangles.vertex(t, c).y);
  return hi;
}

TEST_F(GltfSkins, FirstAnimationFramePosesTheJoints) {
  // The strip's second joint (node 0) straight at rest; animation 0 starts it at 90
  // degrees about z and ends straight: the still shows the bend, for each interpolation.
  const float s = std::sqrt(0.5f);
  GltfBuilder b = two_bone_strip();
  b.doc["nodes"][0]["rotation"] = {0.0, 0.0, 0.0, 1.0};
  EXPECT_NEAR(highest_y(load(b)), 0.1f, 1e-6f) << "the rest pose is straight";
  animate(b, 0, "rotation", {0.5f, 2.0f}, {0, 0, s, s, 0, 0, 0, 1}, "VEC4", "LINEAR");
  EXPECT_NEAR(highest_y(load(b)), 1.0f, 1e-6f) << "LINEAR: keyframe 0";
  animate(b, 0, "rotation", {0.5f, 2.0f}, {0, 0, 0, 1, 0, 0, s, s, 0, 0, 0, 1, /**/ 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1},
          "VEC4", "CUBICSPLINE");
  EXPECT_NEAR(highest_y(load(b)), 1.0f, 1e-6f) << "CUBICSPLINE: keyframe 0's value, between its tangents";
  animate(b, 0, "rotation", {0.5f, 2.0f}, {0, 0, s, s}, "VEC4", "STEP");
  expect_error(b, "the output has 1 elements, expected 2");
}

TEST_F(GltfSkins, FirstAnimationFrameSetsMorphWeightsAndTranslations) {
  GltfBuilder b = morphing_triangle();
  animate(b, 0, "weights", {0.0f, 1.0f}, {0.6f, 0.1f}, "SCALAR", "LINEAR");
  EXPECT_NEAR(third_vertex_z(load(b)), 0.6f, 1e-6f) << "the animation's first weight over the mesh's";
  animate(b, 0, "translation", {0.0f, 1.0f}, {0, 3, 0, 0, 9, 0}, "VEC3", "LINEAR");
  EXPECT_NEAR(highest_y(load(b)), 4.0f, 1e-5f) << "moved up by 3";
  b.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  testing::internal::CaptureStderr();
  EXPECT_NEAR(highest_y(load(b)), 1.0f, 1e-5f) << "a node with a matrix is not animated";
  EXPECT_NE(testing::internal::GetCapturedStderr().find("which has a matrix"), std::string::npos);
}

// --frame-time: the joint's rotation a third of the way from 90 degrees to straight (LINEAR:
// slerp, 60 degrees), held before and after its keys; STEP holds the first key until the
// second; the skinned strip's tip follows its joint.
TEST_F(GltfSkins, FrameTimePosesTheJointsAtThatTime) {
  const float s = std::sqrt(0.5f);
  GltfBuilder b = two_bone_strip();
  EXPECT_EQ(load(b).animation.animations, 0u);
  animate(b, 0, "rotation", {0.5f, 2.0f}, {0, 0, s, s, 0, 0, 0, 1}, "VEC4", "LINEAR");
  const AnimationRange range = load(b).animation;  // what lancer info shows
  EXPECT_EQ(range.animations, 1u);
  EXPECT_EQ(range.channels, 1u);
  EXPECT_EQ(range.start, 0.5);
  EXPECT_EQ(range.end, 2.0);
  // Joint 1 at (1, 0) turned by a about z: the tip's upper corner (2, 0.1) reaches
  // y = sin(a) + 0.1 cos(a).
  auto tip_y = [](double degrees) {
    const double a = degrees * 3.14159265358979323846 / 180.0;
    return static_cast<float>(std::sin(a) + 0.1 * std::cos(a));
  };
  EXPECT_NEAR(highest_y(load(b, 1.0)), tip_y(60.0), 2e-6f) << "LINEAR, a third of the way";
  EXPECT_NEAR(highest_y(load(b, 0.0)), tip_y(90.0), 2e-6f) << "before the first key";
  EXPECT_NEAR(highest_y(load(b, 5.0)), 0.1f, 2e-6f) << "after the last key: straight";
  animate(b, 0, "rotation", {0.5f, 2.0f}, {0, 0, s, s, 0, 0, 0, 1}, "VEC4", "STEP");
  EXPECT_NEAR(highest_y(load(b, 1.99)), tip_y(90.0), 2e-6f) << "STEP holds key 0";
  EXPECT_NEAR(highest_y(load(b, 2.0)), 0.1f, 2e-6f) << "STEP at key 1";
}

TEST_F(GltfSkins, FrameTimeSetsTranslationsAndMorphWeights) {
  GltfBuilder b = morphing_triangle();
  animate(b, 0, "weights", {0.0f, 1.0f}, {0.6f, 0.1f}, "SCALAR", "LINEAR");
  EXPECT_NEAR(third_vertex_z(load(b, 0.5)), 0.35f, 1e-6f);
  // CUBICSPLINE translation, keys at 0 and 2: y from 3 (out-tangent 3) to 5 (in-tangent -1).
  // At t = 1: 3/2 + 2 * 3/8 + 5/2 + 2 * 1/8 = 5, and the triangle's top is at y = 1.
  animate(b, 0, "translation", {0.0f, 2.0f}, {0, 99, 0, 0, 3, 0, 0, 3, 0, /**/ 0, -1, 0, 0, 5, 0, 0, 77, 0}, "VEC3",
          "CUBICSPLINE");
  EXPECT_NEAR(highest_y(load(b, 1.0)), 6.0f, 1e-5f);
  EXPECT_NEAR(highest_y(load(b)), 4.0f, 1e-5f) << "no time: the first key's value";
}

TEST_F(GltfSkins, KeyframeTimesMustIncrease) {
  GltfBuilder b = morphing_triangle();
  animate(b, 0, "translation", {1.0f, 1.0f}, {0, 3, 0, 0, 9, 0}, "VEC3", "LINEAR");
  expect_error(b, "not after the one before");
  animate(b, 0, "translation", {2.0f, 1.0f}, {0, 3, 0, 0, 9, 0}, "VEC3", "LINEAR");
  expect_error(b, "not after the one before");
}

}  // namespace
}  // namespace lancer
