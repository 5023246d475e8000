// The .glb writer: what read_gltf gives back is what was written (bit-identical
// positions in the same order, materials, cameras, lights), corners are welded, the
// write is atomic and deterministic, and failures say what went wrong.
#include "scene/gltf_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "scene/gltf_reader.h"
#include "scene/load_scene.h"
#include "scene/procedural.h"
#include "scene/scene_error.h"
#include "scene/spd.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

class GltfWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lancer_gltf_writer_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool same_float_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_materials(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (std::size_t i = 0; i < a.materials.size(); ++i) {
    const Material &x = a.materials[i], &y = b.materials[i];
    SCOPED_TRACE("material " + std::to_string(i));
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.base_color, y.base_color);
    EXPECT_EQ(x.metallic, y.metallic);
    EXPECT_EQ(x.roughness, y.roughness);
    EXPECT_EQ(x.emissive_factor, y.emissive_factor);
    EXPECT_EQ(x.emissive_strength, y.emissive_strength);
    EXPECT_EQ(x.alpha_mode, y.alpha_mode);
    EXPECT_EQ(x.alpha_cutoff, y.alpha_cutoff);
    EXPECT_EQ(x.double_sided, y.double_sided);
    EXPECT_EQ(x.ior, y.ior);
    EXPECT_EQ(x.transmission, y.transmission);
    EXPECT_EQ(x.thickness, y.thickness);
    EXPECT_EQ(x.attenuation_distance, y.attenuation_distance);
    EXPECT_EQ(x.attenuation_color, y.attenuation_color);
    EXPECT_EQ(x.specular, y.specular);
    EXPECT_EQ(x.specular_color, y.specular_color);
    EXPECT_EQ(x.clearcoat, y.clearcoat);
    EXPECT_EQ(x.clearcoat_roughness, y.clearcoat_roughness);
    EXPECT_EQ(x.sheen_color, y.sheen_color);
    EXPECT_EQ(x.sheen_roughness, y.sheen_roughness);
    EXPECT_EQ(x.unlit, y.unlit);
  }
}

void expect_same_view(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (std::size_t i = 0; i < a.cameras.size(); ++i) {
    EXPECT_EQ(a.cameras[i].name, b.cameras[i].name);
    EXPECT_EQ(a.cameras[i].camera_to_world, b.cameras[i].camera_to_world);
    EXPECT_EQ(a.cameras[i].yfov, b.cameras[i].yfov);
    EXPECT_EQ(a.cameras[i].aspect_ratio, b.cameras[i].aspect_ratio);
  }
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (std::size_t i = 0; i < a.lights.size(); ++i) {
    const PunctualLight &x = a.lights[i], &y = b.lights[i];
    SCOPED_TRACE("light " + std::to_string(i));
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.color, y.color);
    EXPECT_EQ(x.intensity, y.intensity);
    EXPECT_EQ(x.range, y.range);
    EXPECT_EQ(x.position, y.position);
    EXPECT_NEAR(glm::dot(x.direction, y.direction), 1.0f, 1e-6f);
    EXPECT_EQ(x.inner_cone, y.inner_cone);
    EXPECT_EQ(x.outer_cone, y.outer_cone);
  }
}

void expect_same_scene(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.triangle_count(), b.triangle_count());
  for (std::size_t t = 0; t < a.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = a.triangles.vertex(t, k), q = b.triangles.vertex(t, k);
      ASSERT_TRUE(same_float_bits(p.x, q.x) && same_float_bits(p.y, q.y) && same_float_bits(p.z, q.z))
          << "triangle " << t << " corner " << k;
    }
    ASSERT_EQ(a.material_id[t], b.material_id[t]) << "triangle " << t;
    ASSERT_EQ(a.attrib_flags[t] & kHasNormals, b.attrib_flags[t] & kHasNormals) << "triangle " << t;
    if (a.attrib_flags[t] & kHasNormals) {
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(glm::dot(a.normals[3 * t + k], b.normals[3 * t + k]), 1.0f, 1e-6f) << "triangle " << t;
    }
  }
  expect_same_materials(a, b);
  expect_same_view(a, b);
}

TEST_F(GltfWriterTest, EverySpdSceneRoundTrips) {
  for (std::string_view name : spd_names()) {
    SCOPED_TRACE(std::string(name));
    const Scene scene = make_spd(name, spd_size_range(name).min + 1, {1, 6});
    const fs::path file = dir_ / (std::string(name) + ".glb");
    write_glb(scene, file);
    const Scene back = load_scene(file);
    expect_same_scene(scene, back);
    EXPECT_EQ(back.stats.degenerate_dropped, 0u);
  }
}

// A scene using what the writer supports beyond the SPD: every material extension,
// alpha modes, runs with and without normals interleaved, cameras with and without an
// aspect ratio, and all three light types.
Scene varied_scene() {
  Scene s;
  s.source = "varied";
  Material plain;
  plain.name = "plain";
  Material fancy;
  fancy.name = "fancy";
  fancy.base_color = {0.25f, 0.5f, 0.75f, 0.5f};
  fancy.metallic = 0.3f;
  fancy.roughness = 0.7f;
  fancy.emissive_factor = {1.0f, 0.5f, 0.125f};
  fancy.emissive_strength = 4.0f;
  fancy.alpha_mode = AlphaMode::Mask;
  fancy.alpha_cutoff = 0.25f;
  fancy.double_sided = true;
  fancy.ior = 1.33f;
  fancy.transmission = 0.6f;
  fancy.thickness = 0.25f;
  fancy.attenuation_distance = 2.0f;
  fancy.attenuation_color = {0.5f, 0.75f, 1.0f};
  fancy.specular = 0.5f;
  fancy.specular_color = {0.9f, 0.8f, 0.7f};
  fancy.clearcoat = 0.75f;
  fancy.clearcoat_roughness = 0.25f;
  fancy.sheen_color = {0.5f, 0.25f, 0.125f};
  fancy.sheen_roughness = 0.375f;
  Material blend;
  blend.name = "blend";
  blend.alpha_mode = AlphaMode::Blend;
  blend.unlit = true;
  s.materials = {plain, fancy, blend};
  append_uv_sphere(s, {0.0f, 0.0f, 0.0f}, 1.0f, 8, 5, 1, /*smooth_normals=*/true);
  append_uv_sphere(s, {3.0f, 0.0f, 0.0f}, 0.5f, 6, 4, 1, /*smooth_normals=*/false);
  append_box(s, Bounds3{{-1.0f, -3.0f, -1.0f}, {1.0f, -2.0f, 1.0f}}, 0);
  append_icosphere(s, {0.0f, 3.0f, -0.0f}, 0.25f, 1, 2);
  append_quad(s, {-5, -5, -5}, {5, -5, -5}, {5, -5, 5}, {-5, -5, 5}, 1);

  CameraDesc wide;
  wide.name = "wide";
  wide.camera_to_world = glm::mat4(glm::vec4(0, 0, -1, 0), glm::vec4(0, 1, 0, 0), glm::vec4(1, 0, 0, 0),
                                   glm::vec4(10.5f, 0.25f, -0.125f, 1));
  wide.yfov = 1.1f;
  wide.aspect_ratio = 16.0f / 9.0f;
  CameraDesc plain_camera;
  plain_camera.name = "plain";
  s.cameras = {wide, plain_camera};

  PunctualLight point;
  point.name = "point";
  point.color = {1.0f, 0.9f, 0.8f};
  point.intensity = 123.5f;
  point.position = {1.0f, 2.0f, 3.0f};
  point.range = 40.0f;
  PunctualLight spot;
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.position = {-1.0f, 4.0f, 0.5f};
  spot.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  spot.inner_cone = 0.2f;
  spot.outer_cone = 0.6f;
  PunctualLight sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::vec3(0.0f, 1.0f, 0.0f);  // straight up: the frame's other branch
  sun.intensity = 3.0f;
  s.lights = {point, spot, sun};
  return s;
}

TEST_F(GltfWriterTest, MaterialsRunsCamerasAndLightsRoundTrip) {
  const Scene scene = varied_scene();
  const fs::path file = dir_ / "varied.glb";
  write_glb(scene, file);
  expect_same_scene(scene, read_gltf(file));
}

TEST_F(GltfWriterTest, CornersAreWeldedIntoIndexedVertices) {
  // An icosphere of 1280 triangles has 642 distinct corners (with their normals):
  // welded, the file holds 642 * 24 bytes of vertices and 3840 * 4 of indices, about
  // 31 KB; unwelded it would need 3840 * 24 = 92 KB of vertices.
  Scene s;
  append_icosphere(s, {0.0f, 0.0f, 0.0f}, 1.0f, 3, 0);
  const fs::path file = dir_ / "ico.glb";
  write_glb(s, file);
  EXPECT_LT(fs::file_size(file), 642u * 24 + 3840u * 4 + 4096);
  expect_same_scene(s, load_scene(file));
}

TEST_F(GltfWriterTest, SameSceneSameBytesAndNoTemporaryLeft) {
  const Scene scene = make_spd("gears", 1);
  write_glb(scene, dir_ / "a.glb");
  write_glb(scene, dir_ / "b.glb");
  EXPECT_EQ(bytes_of(dir_ / "a.glb"), bytes_of(dir_ / "b.glb"));
  EXPECT_FALSE(fs::exists(dir_ / "a.glb.tmp"));
  // Overwriting replaces the file.
  write_glb(make_spd("tetra", 1), dir_ / "a.glb");
  EXPECT_EQ(load_scene(dir_ / "a.glb").triangle_count(), 4u);
}

std::string write_error(const Scene& scene, const fs::path& path) {
  try {
    write_glb(scene, path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no SceneError thrown)";
}

TEST_F(GltfWriterTest, MissingDirectoryIsAClearError) {
  const fs::path file = dir_ / "no" / "such" / "dir" / "out.glb";
  const std::string message = write_error(make_spd("tetra", 1), file);
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(file));
}

TEST_F(GltfWriterTest, UnwritableTargetIsAClearError) {
  // A directory where the file should go: the final rename fails and nothing is left.
  fs::create_directories(dir_ / "taken.glb");
  const std::string message = write_error(make_spd("tetra", 1), dir_ / "taken.glb");
  EXPECT_NE(message.find("taken.glb"), std::string::npos) << message;
  EXPECT_NE(message.find("rename"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(dir_ / "taken.glb.tmp"));
}

TEST_F(GltfWriterTest, RefusesEmptyScenesAndTextures) {
  Scene empty;
  empty.materials.emplace_back();
  EXPECT_NE(write_error(empty, dir_ / "e.glb").find("no triangles"), std::string::npos);
  Scene textured = make_spd("tetra", 1);
  textured.materials[0].base_color_texture.texture = 0;
  EXPECT_NE(write_error(textured, dir_ / "t.glb").find("uses textures"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "e.glb"));
  EXPECT_FALSE(fs::exists(dir_ / "t.glb"));
}

}  // namespace
}  // namespace lancer
