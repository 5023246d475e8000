// lancer-bench's scene suite: names and order, SPD names of any valid size, the models
// folder, and the camera and light each scene's ray sets start from.
#include "bench_suite.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "temp_dir.h"
#include "test_paths.h"

namespace lancer::bench {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> names(const std::vector<SuiteScene>& suite) {
  std::vector<std::string> out;
  for (const SuiteScene& s : suite) out.push_back(s.name);
  return out;
}

class BenchSuite : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(models_ / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::ofstream(models_ / "notes.txt") << "not a mesh\n";
    std::ofstream(models_ / "balls-3.OBJ") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";  // name taken by the SPD scene
  }
  test::TempDir temp_{"lancer_bench_suite"};
  const fs::path& models_ = temp_.path();
};

TEST_F(BenchSuite, BuiltInsThenSpdThenModelsByFileName) {
  const std::vector<SuiteScene> suite = default_suite(test::scenes_dir(), models_);
  const std::vector<std::string> expected = {
      "cornell-box", "cornell-box-spheres", "balls-3", "gears-4", "mount-7", "rings-5",
      "tetra-8",     "balls-3.OBJ",         "tri"};
  EXPECT_EQ(names(suite), expected);
  EXPECT_EQ(suite[0].file, test::scenes_dir() / "cornell-box.gltf");
  EXPECT_EQ(suite[3].kind, SuiteScene::Kind::Spd);
  EXPECT_EQ(suite[3].spd, "gears");
  EXPECT_EQ(suite[3].spd_size, 4);
  EXPECT_EQ(suite.back().origin, "models");
  EXPECT_EQ(names(default_suite(test::scenes_dir(), {})).size(), 7u);  // no models folder
}

TEST_F(BenchSuite, SelectKeepsTheGivenOrderAndAcceptsAnySpdSize) {
  const std::vector<SuiteScene> suite = default_suite(test::scenes_dir(), models_);
  const std::vector<SuiteScene> picked = select_scenes(suite, {"tri", "gears-2", "cornell-box", "tri"});
  EXPECT_EQ(names(picked), (std::vector<std::string>{"tri", "gears-2", "cornell-box"}));
  EXPECT_EQ(picked[1].spd_size, 2);
  for (const char* bad : {"nosuch", "gears-0", "gears-45", "gears-", "-3", "gears-x", "notes"}) {
    try {
      select_scenes(suite, {bad});
      ADD_FAILURE() << bad << " was accepted";
    } catch (const UnknownScene& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("unknown scene '" + std::string(bad) + "'"), std::string::npos) << what;
      EXPECT_NE(what.find("cornell-box-spheres"), std::string::npos) << what;  // lists the known names
    }
  }
}

TEST_F(BenchSuite, SceneWithoutLightGetsOneAndTheCameraIsSquare) {
  const std::vector<SuiteScene> suite = default_suite(test::scenes_dir(), models_);
  const BenchScene tri = load_bench_scene(select_scenes(suite, {"tri"})[0], 16);
  EXPECT_TRUE(tri.added_light);
  ASSERT_EQ(tri.scene.lights.size(), 1u);
  EXPECT_GT(tri.scene.lights[0].position.y, 1.0f);  // above the triangle
  EXPECT_EQ(tri.camera.width(), 16);
  EXPECT_EQ(tri.camera.height(), 16);
  // The camera frames the bounding box tightly: every corner is in the image, and the widest
  // reaches close to its border (image coordinates in [-1, 1]).
  const PinholeCamera& cam = tri.camera;
  const Bounds3 bounds = tri.scene.bounds();
  float widest = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? bounds.hi.x : bounds.lo.x, (corner & 2) ? bounds.hi.y : bounds.lo.y,
                      (corner & 4) ? bounds.hi.z : bounds.lo.z);
    const glm::vec3 rel = p - cam.origin();
    const float depth = glm::dot(rel, cam.forward());
    ASSERT_GT(depth, 0.0f);
    const float x = glm::dot(rel, cam.x_axis()) / (glm::dot(cam.x_axis(), cam.x_axis()) * depth);
    const float y = glm::dot(rel, cam.y_axis()) / (glm::dot(cam.y_axis(), cam.y_axis()) * depth);
    EXPECT_LE(std::fabs(x), 1.0f) << "corner " << corner;
    EXPECT_LE(std::fabs(y), 1.0f) << "corner " << corner;
    widest = std::max({widest, std::fabs(x), std::fabs(y)});
  }
  EXPECT_GT(widest, 0.9f);

  const BenchScene box = load_bench_scene(suite[0], 24);
  EXPECT_FALSE(box.added_light);  // the Cornell box has its emissive ceiling light
  EXPECT_TRUE(box.scene.lights.empty());
  EXPECT_EQ(box.camera.width(), 24);
  EXPECT_EQ(box.camera.height(), 24);
  EXPECT_EQ(box.scene.triangles.size(), 32u);

  const BenchScene spd = load_bench_scene(select_scenes(suite, {"tetra-2"})[0], 8);
  EXPECT_FALSE(spd.added_light);  // the SPD lights
  EXPECT_EQ(spd.scene.triangles.size(), 16u);
}

}  // namespace
}  // namespace lancer::bench
