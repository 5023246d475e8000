// KHR_mesh_quantization: integer mesh attributes read as the extension defines them, and
// refused with a message that names the extension when a file does not declare it.
#include <cmath>
#include <cstdint>
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

constexpr int kByte = 5120, kShort = 5122;

// One triangle: POSITION as SHORT (not normalized, scaled back by the node), NORMAL as
// normalized BYTE, TEXCOORD_0 as normalized SHORT, TANGENT as normalized SHORT.
GltfBuilder quantized_triangle(bool declare) {
  GltfBuilder b;
  // VEC3 of 16 or 8 bits, each element padded to 4-byte alignment as the spec requires.
  const std::vector<std::int16_t> pos = {0, 0, 0, 0, 1000, 0, 0, 0, 0, 2000, -500, 0};
  const std::vector<std::int8_t> nrm = {0, 0, 127, 0, 0, 90, 90, 0, -127, 0, 0, 0};
  const std::vector<std::int16_t> uv = {0, 0, 32767, 0, -32767, 16384};
  const std::vector<std::int16_t> tan = {32767, 0, 0, 32767, 0, 32767, 0, -32767, 0, 0, 32767, 32767};
  const int p = b.add_accessor(b.add_view(pos.data(), pos.size() * 2, 8), kShort, 3, "VEC3");
  const int n = b.add_accessor(b.add_view(nrm.data(), nrm.size(), 4), kByte, 3, "VEC3", true);
  const int t = b.add_accessor(b.add_view(uv.data(), uv.size() * 2), kShort, 3, "VEC2", true);
  const int g = b.add_accessor(b.add_view(tan.data(), tan.size() * 2), kShort, 3, "VEC4", true);
  const int mesh = b.add_mesh({{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}, {"TANGENT", g}});
  b.set_scene({b.add_node({{"mesh", mesh}, {"scale", {0.001, 0.001, 0.001}}})});
  if (declare) {
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  }
  return b;
}

class GltfQuantization : public gltf_test::GltfTempDir {};

TEST_F(GltfQuantization, IntegerAttributesAreDecodedAsTheExtensionSays) {
  const auto file = path("q.gltf");
  quantized_triangle(true).write_data_uri_gltf(file);
  const Scene s = read_gltf(file);
  ASSERT_EQ(s.triangle_count(), 1u);
  // Positions: the shorts times the node's scale.
  EXPECT_EQ(s.triangles.vertex(0, 0), glm::vec3(0, 0, 0));
  EXPECT_NEAR(s.triangles.vertex(0, 1).x, 1.0f, 1e-6f);
  EXPECT_NEAR(s.triangles.vertex(0, 2).y, 2.0f, 1e-6f);
  EXPECT_NEAR(s.triangles.vertex(0, 2).z, -0.5f, 1e-6f);
  // Normals: c / 127, then unit; -127 is exactly -1.
  EXPECT_NEAR(glm::length(s.normals[0] - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(s.normals[1] - glm::normalize(glm::vec3(0, 1, 1))), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(s.normals[2] - glm::vec3(-1, 0, 0)), 0.0f, 1e-6f);
  // Texture coordinates: max(c / 32767, -1).
  EXPECT_NEAR(s.texcoords[1].x, 1.0f, 1e-6f);
  EXPECT_NEAR(s.texcoords[2].x, -1.0f, 1e-6f);
  EXPECT_NEAR(s.texcoords[2].y, 16384.0f / 32767.0f, 1e-6f);
  ASSERT_EQ(s.tangents.size(), 3u);
  EXPECT_NEAR(s.tangents[0].x, 1.0f, 1e-6f);
  EXPECT_NEAR(s.tangents[1].w, -1.0f, 1e-6f);
}

TEST_F(GltfQuantization, IntegerAttributesWithoutTheExtensionAreRefused) {
  const auto file = path("undeclared.gltf");
  quantized_triangle(false).write_data_uri_gltf(file);
  try {
    read_gltf(file);
    ADD_FAILURE() << "loaded a file with SHORT positions that does not use KHR_mesh_quantization";
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("POSITION"), std::string::npos) << msg;
    EXPECT_NE(msg.find("KHR_mesh_quantization"), std::string::npos) << msg;
  }
}

TEST_F(GltfQuantization, NormalsMustBeNormalized) {
  GltfBuilder b = quantized_triangle(true);
  b.doc["accessors"][1].erase("normalized");
  const auto file = path("raw-normals.gltf");
  b.write_data_uri_gltf(file);
  try {
    read_gltf(file);
    ADD_FAILURE() << "loaded BYTE normals that are not normalized";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("NORMAL"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lancer
