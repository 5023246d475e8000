// EXT_mesh_gpu_instancing: a 5 x 5 x 5 grid of instanced boxes, each where its TRS puts
// it after the node's own transform, and malformed instancing refused with a message.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/gltf_instancing.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// A box of side 0.2 around the origin: 8 corners, 12 triangles.
int add_box_mesh(GltfBuilder& b) {
  std::vector<glm::vec3> corners;
  for (int k = 0; k < 8; ++k) corners.emplace_back(k & 1 ? 0.1f : -0.1f, k & 2 ? 0.1f : -0.1f, k & 4 ? 0.1f : -0.1f);
  const std::vector<std::uint16_t> indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                              2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return b.add_mesh({{"POSITION", b.add_vec3(corners)}}, 4, b.add_indices(indices));
}

// The grid's translations: (i, j, k) for i, j, k in 0..4; every instance turned 90 degrees
// about z and scaled 2x along x.
GltfBuilder instanced_grid() {
  GltfBuilder b;
  const int mesh = add_box_mesh(b);
  std::vector<glm::vec3> t, s;
  std::vector<glm::vec4> r;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        t.emplace_back(float(i), float(j), float(k));
        r.emplace_back(0.0f, 0.0f, std::sqrt(0.5f), std::sqrt(0.5f));
        s.emplace_back(2.0f, 1.0f, 1.0f);
      }
  const json attributes = {{"TRANSLATION", b.add_vec3(t)}, {"ROTATION", b.add_vec4(r)}, {"SCALE", b.add_vec3(s)}};
  b.set_scene({b.add_node({{"mesh", mesh},
                           {"translation", {10.0, 0.0, 0.0}},
                           {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}})});
  b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  b.doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  return b;
}

class GltfInstancing : public gltf_test::GltfTempDir {};

TEST_F(GltfInstancing, GridOf125BoxesEachWhereItsTransformPutsIt) {
  const auto file = path("grid.gltf");
  instanced_grid().write_data_uri_gltf(file);
  const Scene s = read_gltf(file);
  ASSERT_EQ(s.triangle_count(), 125u * 12u);
  // Instance n's box: corners at node (10, 0, 0) + t_n + R_z(90) * (2x, y, z): its x extent
  // is 0.2 (the y side), its y extent 0.4 (the scaled x side).
  for (std::size_t n = 0; n < 125; ++n) {
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (std::size_t tri = 12 * n; tri < 12 * n + 12; ++tri)
      for (int c = 0; c < 3; ++c) {
        lo = glm::min(lo, s.triangles.vertex(std::uint32_t(tri), c));
        hi = glm::max(hi, s.triangles.vertex(std::uint32_t(tri), c));
      }
    const glm::vec3 centre = 0.5f * (lo + hi);
    const glm::vec3 expected(10.0f + float(n / 25), float(n / 5 % 5), float(n % 5));
    EXPECT_NEAR(glm::length(centre - expected), 0.0f, 1e-5f) << "instance " << n;
    EXPECT_NEAR(hi.x - lo.x, 0.2f, 1e-5f) << "instance " << n;
    EXPECT_NEAR(hi.y - lo.y, 0.4f, 1e-5f) << "instance " << n;
    EXPECT_NEAR(hi.z - lo.z, 0.2f, 1e-5f) << "instance " << n;
  }
}

TEST_F(GltfInstancing, MalformedInstancingIsRefused) {
  {
    GltfBuilder b = instanced_grid();
    b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] =
        b.add_vec3(std::vector<glm::vec3>{{1, 1, 1}});
    expect_error(b, "SCALE has 1 instances but another attribute has 125");
  }
  {
    GltfBuilder b = instanced_grid();
    b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["ROTATION"] =
        b.add_vec4(std::vector<glm::vec4>(125, glm::vec4(0.0f)));
    expect_error(b, "ROTATION is not a usable quaternion");
  }
  {
    GltfBuilder b = instanced_grid();
    b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = {{"_ID", 0}};
    expect_error(b, "has none of TRANSLATION, ROTATION and SCALE");
  }
  {
    GltfBuilder b = instanced_grid();
    b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] = 99;
    expect_error(b, "accessor index 99 out of range");
  }
  {
    GltfBuilder b = instanced_grid();
    b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] = 1e300;
    expect_error(b, "TRANSLATION must be an accessor index");
  }
  {
    // 2^21 instances of a 12-triangle box copied into world space (--instancing off): more
    // triangles than copies are allowed to make.
    GltfBuilder b = instanced_grid();
    json accessor = {{"componentType", GltfBuilder::kFloat}, {"count", 1 << 21}, {"type", "VEC3"}};
    const int zeros = b.push("accessors", accessor);  // no bufferView: all zeros
    auto& attributes = b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
    attributes = {{"TRANSLATION", zeros}};
    b.write_data_uri_gltf(path("copies.gltf"));
    try {
      const Scene s = read_gltf(path("copies.gltf"), -1, std::nullopt, InstancingMode::Off);
      ADD_FAILURE() << "loaded " << s.triangle_count() << " triangles";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("2097152 instances of a mesh of up to 36 triangles exceed the limit"),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace lancer
