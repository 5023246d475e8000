// load_scene: the reader is chosen by extension, and what no reader can fix is refused.
#include "scene/load_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "scene/scene_builder.h"
#include "scene/scene_error.h"
#include "test_paths.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

class LoadScene : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lancer_load_scene_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

  // The message of the SceneError that loading `p` throws, or "" when it loads.
  static std::string error_of(const fs::path& p) {
    try {
      load_scene(p);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(LoadScene, ChoosesTheReaderByExtensionCaseInsensitively) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(load_scene(write("a.obj", tri)).triangle_count(), 1u);
  EXPECT_EQ(load_scene(write("b.OBJ", tri)).triangle_count(), 1u);
  EXPECT_EQ(load_scene(test::scenes_dir() / "cornell-box.gltf").triangle_count(), 32u);
}

TEST_F(LoadScene, MissingFileAndDirectoryAreNamed) {
  const std::string missing = error_of(dir_ / "nope.gltf");
  EXPECT_NE(missing.find("nope.gltf"), std::string::npos) << missing;
  EXPECT_NE(missing.find("no such file"), std::string::npos) << missing;
  fs::create_directories(dir_ / "folder.obj");
  EXPECT_NE(error_of(dir_ / "folder.obj").find("not a regular file"), std::string::npos);
}

TEST_F(LoadScene, UnknownFormatIsRefused) {
  const std::string e = error_of(write("scene.ply", "ply\n"));
  EXPECT_NE(e.find("scene.ply"), std::string::npos) << e;
  EXPECT_NE(e.find(".ply"), std::string::npos) << e;
}

TEST_F(LoadScene, SceneWithoutTrianglesIsRefused) {
  EXPECT_NE(error_of(write("empty.obj", "# nothing\n")).find("no triangles"), std::string::npos);
  // Only zero-area triangles: all dropped, nothing left to render.
  EXPECT_NE(error_of(write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")).find("no triangles"),
            std::string::npos);
  EXPECT_NE(error_of(write("empty.gltf", R"({"asset":{"version":"2.0"}})")).find("no triangles"), std::string::npos);
}

// --frame-time poses a glTF file's animation; an OBJ file has none, and a time must be a
// number on the timeline. A glTF file without animation loads as it is (with a warning).
TEST_F(LoadScene, FrameTimeIsForGltfAndMustBeFinite) {
  const fs::path obj = write("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  try {
    load_scene(obj, std::nullopt, 1.0);
    ADD_FAILURE() << "an OBJ file took a frame time";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("--frame-time: an OBJ file has no animation"), std::string::npos) << e.what();
  }
  const fs::path cornell = test::scenes_dir() / "cornell-box.gltf";
  for (const double t : {std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(load_scene(cornell, std::nullopt, t), SceneError) << t;
  testing::internal::CaptureStderr();
  EXPECT_EQ(load_scene(cornell, std::nullopt, 2.5).triangle_count(), 32u);
  EXPECT_NE(testing::internal::GetCapturedStderr().find("no animation"), std::string::npos);
}

TEST(SceneBuilder, DropsZeroAreaAndRefusesNonFinite) {
  Scene scene;
  SceneBuilder b(scene, "test.obj");
  const glm::vec3 good[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const glm::vec3 line[3] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  const glm::vec3 point[3] = {{5, 5, 5}, {5, 5, 5}, {5, 5, 5}};
  EXPECT_TRUE(b.add_triangle(good, 0, 0));
  EXPECT_FALSE(b.add_triangle(line, 0, 1));
  EXPECT_FALSE(b.add_triangle(point, 0, 2));
  EXPECT_TRUE(b.add_triangle(good, 0, 3));
  EXPECT_EQ(scene.triangle_count(), 2u);
  EXPECT_EQ(scene.stats.degenerate_dropped, 2u);
  EXPECT_EQ(scene.source_triangle_id[1], 3u);  // ids of later triangles do not shift
  const glm::vec3 nan[3] = {{0, 0, 0}, {1, NAN, 0}, {0, 1, 0}};
  const glm::vec3 inf[3] = {{0, 0, 0}, {1, 0, 0}, {0, INFINITY, 0}};
  EXPECT_THROW(b.add_triangle(nan, 0, 4), SceneError);
  EXPECT_THROW(b.add_triangle(inf, 0, 5), SceneError);
  EXPECT_EQ(scene.triangle_count(), 2u);
}

// A tiny but valid triangle far from the origin is kept: the area test is exact.
TEST(SceneBuilder, KeepsTinyTriangles) {
  Scene scene;
  SceneBuilder b(scene, "test.obj");
  const glm::vec3 tiny[3] = {{1000, 1000, 1000}, {1000.0001f, 1000, 1000}, {1000, 1000.0001f, 1000}};
  EXPECT_TRUE(b.add_triangle(tiny, 0, 0));
}

TEST(SceneBuilder, ZeroLengthNormalsFallBackToTheGeometricNormal) {
  Scene scene;
  SceneBuilder b(scene, "test.gltf");
  const glm::vec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const glm::vec3 n[3] = {{0, 0, 2}, {0, 0, 0}, {0, 0, 1}};
  CornerAttributes attribs;
  attribs.normals = n;
  ASSERT_TRUE(b.add_triangle(p, 0, 0, attribs));
  EXPECT_EQ(scene.attrib_flags[0] & kHasNormals, 0);
  EXPECT_EQ(scene.stats.zero_normals_repaired, 1u);
  EXPECT_TRUE(scene.normals.empty()) << "no triangle has usable normals yet";

  // A later triangle with usable normals: the first one's corners are zeros (scene.h's
  // contract for a clear flag), the second's are normalised.
  const glm::vec3 good[3] = {{0, 0, 2}, {0, 0, 1}, {0, 0, 3}};
  attribs.normals = good;
  ASSERT_TRUE(b.add_triangle(p, 0, 1, attribs));
  ASSERT_EQ(scene.normals.size(), 6u);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(scene.normals[c], glm::vec3(0.0f)) << c;
  for (int c = 3; c < 6; ++c) EXPECT_EQ(scene.normals[c], glm::vec3(0, 0, 1)) << c;
  EXPECT_EQ(scene.attrib_flags[1] & kHasNormals, kHasNormals);
}

}  // namespace
}  // namespace lancer
