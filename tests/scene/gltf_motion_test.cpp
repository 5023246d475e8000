// --shutter: drawings that move while the shutter is open get motions sampled at
// kShutterSteps times; what cannot move (deforming meshes, emitters, cameras) stays as at
// the opening, with a warning; still files and wrong shutters are told apart.
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/load_scene.h"
#include "scene/scene_error.h"
#include "scene/scene_instancing.h"
#include "scene/scene_warning.h"

namespace lancer {
namespace {

using gltf_test::animate;
using gltf_test::GltfBuilder;
using gltf_test::json;

// A triangle at node 0, moved by animation 0 from x = -1 (t = 0) to x = 1 (t = 2), and a
// still one at node 1 drawing another mesh.
GltfBuilder sliding_triangle(const char* interpolation = "LINEAR") {
  GltfBuilder b;
  const int moving = b.add_mesh({{"POSITION", b.add_vec3(gltf_test::unit_triangle())}});
  const int still = b.add_mesh({{"POSITION", b.add_vec3(std::vector<glm::vec3>{{0, 0, 5}, {1, 0, 5}, {0, 1, 5}})}});
  b.set_scene({b.add_node({{"mesh", moving}}), b.add_node({{"mesh", still}})});
  animate(b, 0, "translation", {0.0f, 2.0f}, {-1, 0, 0, 1, 0, 0}, "VEC3", interpolation);
  return b;
}

class GltfMotion : public gltf_test::GltfTempDir {
 protected:
  Scene load(const GltfBuilder& b, std::optional<Shutter> shutter, std::vector<std::string>* warnings = nullptr) {
    b.write_data_uri_gltf(path("scene.gltf"));
    SceneWarningLog log;
    Scene s = read_gltf(path("scene.gltf"), -1, std::nullopt, InstancingMode::Auto, shutter);
    if (warnings) *warnings = log.take();
    return s;
  }
};

TEST_F(GltfMotion, AMovingNodeGetsKeysAcrossTheShutter) {
  const Scene s = load(sliding_triangle(), Shutter{0.5, 1.5});
  ASSERT_EQ(s.instancing.motions.size(), 1u);
  ASSERT_EQ(s.instancing.instances.size(), 2u);  // the still triangle in world space, the moving one
  const Instance& moving = s.instancing.instances[1];
  ASSERT_EQ(moving.motion, 0u);
  const std::vector<MotionKey>& keys = s.instancing.motions[0].keys;
  ASSERT_EQ(keys.size(), std::size_t(kShutterSteps));
  for (int k = 0; k < kShutterSteps; ++k) {
    const double t = 0.5 + double(k) / double(kShutterSteps - 1);  // seconds
    EXPECT_NEAR(keys[std::size_t(k)].translation.x, -1.0 + t, 1e-6) << "key " << k;
    EXPECT_EQ(keys[std::size_t(k)].translation.y, 0.0f);
    EXPECT_NEAR(keys[std::size_t(k)].rotation.w, 1.0f, 1e-7f);
  }
  // At the opening (the still drawing of everything else): x = -0.5.
  EXPECT_NEAR(moving.to_world.offset.x, -0.5f, 1e-6f);
  EXPECT_NEAR(instance_at(s.instancing, moving, 0.25f).to_world.offset.x, -0.25f, 1e-6f);
  EXPECT_NEAR(instance_at(s.instancing, moving, 1.0f).to_world.offset.x, 0.5f, 1e-6f);
}

TEST_F(GltfMotion, RotationsAreKeptAsRotations) {
  GltfBuilder b = sliding_triangle();
  // Half a turn about z over [0, 1]: the middle key is a quarter turn, not a shrunken lerp.
  animate(b, 0, "rotation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, 1, 0}, "VEC4", "LINEAR");
  const Scene scene = load(b, Shutter{0.0, 1.0});
  ASSERT_EQ(scene.instancing.motions.size(), 1u);
  const std::vector<MotionKey>& keys = scene.instancing.motions[0].keys;
  const MotionKey& mid = keys[std::size_t(kShutterSteps / 2)];
  // Slerp on the file's channel: 90 degrees about z at t = 0.5.
  EXPECT_NEAR(std::fabs(mid.rotation.z), std::sqrt(0.5f), 1e-5f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mid.stretch[c][c], 1.0f, 1e-5f);
  const Instance at = instance_at(scene.instancing, scene.instancing.instances[1], 0.5f);
  EXPECT_NEAR(glm::determinant(at.to_world.linear), 1.0f, 1e-5f);
}

TEST_F(GltfMotion, NothingMovesWithoutAShutterOrWhenTheShutterIsAnInstant) {
  EXPECT_TRUE(load(sliding_triangle(), std::nullopt).instancing.motions.empty());
  const Scene instant = load(sliding_triangle(), Shutter{1.0, 1.0});
  EXPECT_TRUE(instant.instancing.motions.empty());
  // Posed at the shutter's opening, as --frame-time 1 would pose it.
  EXPECT_NEAR(instant.bounds().lo.x, 0.0f, 1e-6f);
  // STEP within the shutter: the jump is still a motion between keys.
  EXPECT_EQ(load(sliding_triangle("STEP"), Shutter{1.5, 2.5}).instancing.motions.size(), 1u);
  // Before the first key and after the last the channel holds: no motion there.
  EXPECT_TRUE(load(sliding_triangle(), Shutter{3.0, 4.0}).instancing.motions.empty());
}

TEST_F(GltfMotion, EmittersAndDeformingMeshesStayWithAWarning) {
  GltfBuilder b = sliding_triangle();
  const int light = b.push("materials", {{"emissiveFactor", {1.0, 1.0, 1.0}}});
  b.doc["meshes"][0]["primitives"][0]["material"] = light;
  std::vector<std::string> warnings;
  const Scene s = load(b, Shutter{0.0, 2.0}, &warnings);
  EXPECT_TRUE(s.instancing.motions.empty());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("moving lights are not blurred"), std::string::npos) << warnings[0];

  GltfBuilder m = sliding_triangle();
  const int target = m.add_vec3(std::vector<glm::vec3>(3, glm::vec3(0.0f, 0.0f, 0.5f)));
  m.doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", target}}};
  m.doc["nodes"][0]["weights"] = {1.0};
  const Scene morphed = load(m, Shutter{0.0, 2.0}, &warnings);
  EXPECT_TRUE(morphed.instancing.motions.empty());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("deforming meshes are not blurred"), std::string::npos) << warnings[0];
}

TEST_F(GltfMotion, AMovingCameraGetsKeys) {
  GltfBuilder b = sliding_triangle();
  b.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}});
  b.doc["scenes"][0]["nodes"].push_back(b.add_node({{"camera", 0}, {"translation", {0.0, 0.0, 5.0}}}));
  const int camera_node = int(b.doc["nodes"].size()) - 1;
  animate(b, camera_node, "translation", {0.0f, 1.0f}, {0, 0, 5, 2, 0, 5}, "VEC3", "LINEAR");
  const Scene s = load(b, Shutter{0.0, 1.0});
  EXPECT_TRUE(s.instancing.motions.empty());  // the triangles stay
  ASSERT_EQ(s.cameras.size(), 1u);
  const std::vector<MotionKey>& keys = s.cameras[0].motion;
  ASSERT_EQ(keys.size(), std::size_t(kShutterSteps));
  EXPECT_NEAR(keys.front().translation.x, 0.0f, 1e-6f);
  EXPECT_NEAR(keys.back().translation.x, 2.0f, 1e-6f);
  EXPECT_TRUE(load(b, std::nullopt).cameras[0].motion.empty());
}

TEST_F(GltfMotion, ShuttersThatAreNotIntervalsAreRefused) {
  sliding_triangle().write_data_uri_gltf(path("scene.gltf"));
  for (const Shutter bad : {Shutter{1.0, 0.5}, Shutter{std::nan(""), 1.0}, Shutter{0.0, INFINITY}}) {
    try {
      load_scene(path("scene.gltf"), std::nullopt, std::nullopt, InstancingMode::Auto, bad);
      ADD_FAILURE() << "accepted --shutter " << bad.open << "," << bad.close;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("not an interval"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(load_scene(path("scene.gltf"), std::nullopt, 1.0, InstancingMode::Auto, Shutter{0.0, 1.0}), SceneError);
}

TEST(MotionKey, PolarDecompositionRebuildsTheMatrix) {
  glm::dmat4 m(1.0);
  const glm::dmat3 r = glm::mat3_cast(glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, 2, 3))));
  glm::dmat3 scale(1.0);
  scale[0][0] = 2.0, scale[1][1] = 0.5, scale[2][2] = -3.0;  // mirrors
  const glm::dmat3 linear = r * scale;
  for (int c = 0; c < 3; ++c) m[c] = glm::dvec4(linear[c], 0.0);
  m[3] = glm::dvec4(4, 5, 6, 1);
  const std::optional<MotionKey> key = motion_key(m);
  ASSERT_TRUE(key);
  EXPECT_LT(glm::determinant(key->stretch), 0.0f);  // the mirror is in the stretch
  const glm::mat3 rebuilt = glm::mat3_cast(key->rotation) * key->stretch;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(rebuilt[c][k], float(linear[c][k]), 1e-5f);
  EXPECT_EQ(key->translation, glm::vec3(4, 5, 6));
  EXPECT_FALSE(motion_key(glm::dmat4(0.0)));
}

}  // namespace
}  // namespace lancer
