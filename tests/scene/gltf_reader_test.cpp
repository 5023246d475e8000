// glTF reader on well-formed files built in code: geometry, topology conversion,
// transforms, attributes, materials, cameras, lights and the three containers
// (.gltf with a data URI, .gltf with an external .bin, .glb). Bad input is covered in
// gltf_reader_errors_test.cpp.
#include "scene/gltf_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;
using gltf_test::unit_triangle;

constexpr float kEps = 1e-5f;

void expect_vec3(const glm::vec3& got, const glm::vec3& want, float eps = kEps) {
  EXPECT_NEAR(got.x, want.x, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
  EXPECT_NEAR(got.y, want.y, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
  EXPECT_NEAR(got.z, want.z, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
}

void expect_triangle(const Scene& s, std::size_t i, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                     float eps = kEps) {
  ASSERT_LT(i, s.triangle_count());
  SCOPED_TRACE("triangle " + std::to_string(i));
  expect_vec3(s.triangles.vertex(i, 0), a, eps);
  expect_vec3(s.triangles.vertex(i, 1), b, eps);
  expect_vec3(s.triangles.vertex(i, 2), c, eps);
}

glm::vec3 geometric_normal(const Scene& s, std::size_t i) {
  const glm::vec3 a = s.triangles.vertex(i, 0), b = s.triangles.vertex(i, 1), c = s.triangles.vertex(i, 2);
  return glm::normalize(glm::cross(b - a, c - a));
}

class GltfReader : public gltf_test::GltfTempDir {};

TEST_F(GltfReader, SingleTriangleWithDefaultMaterial) {
  GltfBuilder b;
  b.single_node_scene(b.add_mesh({{"POSITION", b.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})}}));
  b.write_data_uri_gltf(path("tri.gltf"));
  const Scene s = read_gltf(path("tri.gltf"));
  EXPECT_EQ(s.source, path("tri.gltf").string());
  ASSERT_EQ(s.triangle_count(), 1u);
  expect_triangle(s, 0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.0f);
  EXPECT_EQ(s.source_triangle_id[0], 0u);
  EXPECT_EQ(s.attrib_flags[0], 0u) << "no NORMAL/TEXCOORD_0/TANGENT: no flags";
  // glTF default material: white, metallic 1, roughness 1.
  ASSERT_EQ(s.materials.size(), 1u);
  ASSERT_EQ(s.material_id[0], 0u);
  EXPECT_EQ(s.materials[0].base_color, glm::vec4(1.0f));
  EXPECT_EQ(s.materials[0].metallic, 1.0f);
  EXPECT_EQ(s.materials[0].roughness, 1.0f);
  // Attributes no triangle has take no memory.
  EXPECT_TRUE(s.normals.empty());
  EXPECT_TRUE(s.texcoords.empty());
  EXPECT_TRUE(s.tangents.empty());
}

template <typename Index>
void check_indexed_quad(const std::filesystem::path& file) {
  GltfBuilder b;
  const int pos = b.add_vec3({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  const int idx = b.add_indices(std::vector<Index>{0, 1, 2, 0, 2, 3});
  b.single_node_scene(b.add_mesh({{"POSITION", pos}}, 4, idx));
  b.write_data_uri_gltf(file);
  const Scene s = read_gltf(file);
  ASSERT_EQ(s.triangle_count(), 2u);
  expect_triangle(s, 0, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, 0.0f);
  expect_triangle(s, 1, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0.0f);
  EXPECT_EQ(s.source_triangle_id, (std::vector<std::uint32_t>{0, 1}));
}

TEST_F(GltfReader, IndexedQuadWithUint8Indices) { check_indexed_quad<std::uint8_t>(path("q8.gltf")); }
TEST_F(GltfReader, IndexedQuadWithUint16Indices) { check_indexed_quad<std::uint16_t>(path("q16.gltf")); }
TEST_F(GltfReader, IndexedQuadWithUint32Indices) { check_indexed_quad<std::uint32_t>(path("q32.gltf")); }

TEST_F(GltfReader, NonIndexedTriangles) {
  GltfBuilder b;
  b.single_node_scene(
      b.add_mesh({{"POSITION", b.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}})}}));
  b.write_data_uri_gltf(path("two.gltf"));
  const Scene s = read_gltf(path("two.gltf"));
  ASSERT_EQ(s.triangle_count(), 2u);
  expect_triangle(s, 0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.0f);
  expect_triangle(s, 1, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}, 0.0f);
}

TEST_F(GltfReader, TriangleStripAlternatesWinding) {
  // A planar strip: every triangle must come out counter-clockwise (facing +z).
  const std::vector<glm::vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 2, 0}};
  GltfBuilder b;
  b.single_node_scene(b.add_mesh({{"POSITION", b.add_vec3(v)}}, 5));
  b.write_data_uri_gltf(path("strip.gltf"));
  const Scene s = read_gltf(path("strip.gltf"));
  ASSERT_EQ(s.triangle_count(), 3u);
  // glTF spec: p_i = {v_i, v_{i+1+i%2}, v_{i+2-i%2}}.
  expect_triangle(s, 0, v[0], v[1], v[2], 0.0f);
  expect_triangle(s, 1, v[1], v[3], v[2], 0.0f);
  expect_triangle(s, 2, v[2], v[3], v[4], 0.0f);
  for (std::size_t i = 0; i < 3; ++i) expect_vec3(geometric_normal(s, i), {0, 0, 1});
}

TEST_F(GltfReader, IndexedTriangleFan) {
  // Centre vertex stored last, reached through the indices.
  const std::vector<glm::vec3> v = {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}, {0, 0, 0}};
  GltfBuilder b;
  const int idx = b.add_indices(std::vector<std::uint16_t>{4, 0, 1, 2, 3});
  b.single_node_scene(b.add_mesh({{"POSITION", b.add_vec3(v)}}, 6, idx));
  b.write_data_uri_gltf(path("fan.gltf"));
  const Scene s = read_gltf(path("fan.gltf"));
  ASSERT_EQ(s.triangle_count(), 3u);
  // glTF spec: p_i = {v_{i+1}, v_{i+2}, v_0}.
  expect_triangle(s, 0, v[0], v[1], v[4], 0.0f);
  expect_triangle(s, 1, v[1], v[2], v[4], 0.0f);
  expect_triangle(s, 2, v[2], v[3], v[4], 0.0f);
  for (std::size_t i = 0; i < 3; ++i) expect_vec3(geometric_normal(s, i), {0, 0, 1});
}

TEST_F(GltfReader, TrsAndMatrixComposeThroughHierarchy) {
  GltfBuilder b;
  const int mesh = b.add_mesh({{"POSITION", b.add_vec3(unit_triangle())}});
  const double h = std::sqrt(0.5);
  // child: matrix translating by (1, 0, 0), column-major.
  const int child = b.add_node({{"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1}}});
  // parent: T(10, 0, 0) * R(90 deg about z) * S(2).
  const int parent = b.add_node(
      {{"translation", {10, 0, 0}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 2, 2}}, {"children", {child}}});
  b.set_scene({parent});
  b.write_data_uri_gltf(path("h.gltf"));
  const Scene s = read_gltf(path("h.gltf"));
  ASSERT_EQ(s.triangle_count(), 1u);
  // p -> p + (1,0,0) -> *2 -> (x, y) to (-y, x) -> + (10, 0, 0), by hand:
  // (0,0,0) -> (10,2,0); (1,0,0) -> (10,4,0); (0,1,0) -> (8,2,0).
  expect_triangle(s, 0, {10, 2, 0}, {10, 4, 0}, {8, 2, 0});
}

TEST_F(GltfReader, TraversalOrderGivesSourceIds) {
  GltfBuilder b;
  const int mesh = b.add_mesh({{"POSITION", b.add_vec3(unit_triangle())}});
  const int child = b.add_node({{"mesh", mesh}, {"translation", {0, 0, 1}}});
  const int a = b.add_node({{"mesh", mesh}, {"children", {child}}});  // z = 0, then its child z = 1
  const int c = b.add_node({{"mesh", mesh}, {"translation", {0, 0, 5}}});
  b.set_scene({c, a});
  b.write_data_uri_gltf(path("order.gltf"));
  Scene s = read_gltf(path("order.gltf"));
  ASSERT_EQ(s.triangle_count(), 3u);
  EXPECT_EQ(s.triangles.vertex(0, 0).z, 5.0f);
  EXPECT_EQ(s.triangles.vertex(1, 0).z, 0.0f);
  EXPECT_EQ(s.triangles.vertex(2, 0).z, 1.0f);
  EXPECT_EQ(s.source_triangle_id, (std::vector<std::uint32_t>{0, 1, 2}));

  // Without scenes: every root node in index order (a, then its child, then c).
  b.doc.erase("scenes");
  b.doc.erase("scene");
  b.write_data_uri_gltf(path("noscene.gltf"));
  s = read_gltf(path("noscene.gltf"));
  ASSERT_EQ(s.triangle_count(), 3u);
  EXPECT_EQ(s.triangles.vertex(0, 0).z, 0.0f);
  EXPECT_EQ(s.triangles.vertex(1, 0).z, 1.0f);
  EXPECT_EQ(s.triangles.vertex(2, 0).z, 5.0f);
}

TEST_F(GltfReader, NormalsUseInverseTransposeUnderNonUniformScale) {
  GltfBuilder b;
  const float r = std::sqrt(0.5f);
  const int pos = b.add_vec3(unit_triangle());
  const int nrm = b.add_vec3({{r, r, 0}, {r, r, 0}, {r, r, 0}});
  const int tan = b.add_vec4({{1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}});
  const int mesh = b.add_mesh({{"POSITION", pos}, {"NORMAL", nrm}, {"TANGENT", tan}});
  b.set_scene({b.add_node({{"mesh", mesh}, {"scale", {2, 1, 1}}})});
  b.write_data_uri_gltf(path("n.gltf"));
  const Scene s = read_gltf(path("n.gltf"));
  ASSERT_EQ(s.triangle_count(), 1u);
  EXPECT_EQ(s.attrib_flags[0], kHasNormals | kHasTangents);
  // diag(2,1,1)^-T (1,1,0) = (1/2, 1, 0), normalised (1, 2, 0) / sqrt 5, not (2, 1, 0).
  const glm::vec3 want = glm::vec3(1, 2, 0) / std::sqrt(5.0f);
  for (int k = 0; k < 3; ++k) expect_vec3(s.normals[std::size_t(k)], want);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(s.tangents[std::size_t(k)], glm::vec4(1, 0, 0, 1));
}

TEST_F(GltfReader, MirroringKeepsFrontFaceAndFlipsTangentSign) {
  for (const glm::vec3 scale : {glm::vec3(-1, 1, 1), glm::vec3(1, 1, -1), glm::vec3(-2, 3, 1)}) {
    SCOPED_TRACE("scale " + std::to_string(scale.x) + " " + std::to_string(scale.y) + " " + std::to_string(scale.z));
    GltfBuilder b;
    const int pos = b.add_vec3(unit_triangle());
    const int nrm = b.add_vec3({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
    const int tan = b.add_vec4({{1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}});
    const int mesh = b.add_mesh({{"POSITION", pos}, {"NORMAL", nrm}, {"TANGENT", tan}});
    b.set_scene({b.add_node({{"mesh", mesh}, {"scale", {scale.x, scale.y, scale.z}}})});
    b.write_data_uri_gltf(path("m.gltf"));
    const Scene s = read_gltf(path("m.gltf"));
    ASSERT_EQ(s.triangle_count(), 1u);
    // The front side (local +z) maps to world +z * sign(scale.z); the geometric
    // normal and the shading normal must both point there.
    const glm::vec3 front(0, 0, scale.z > 0 ? 1 : -1);
    expect_vec3(geometric_normal(s, 0), front);
    for (int k = 0; k < 3; ++k) expect_vec3(s.normals[std::size_t(k)], front);
    const bool mirrored = scale.x * scale.y * scale.z < 0;
    for (int k = 0; k < 3; ++k) {
      const glm::vec4 t = s.tangents[std::size_t(k)];
      expect_vec3(glm::vec3(t), {scale.x > 0 ? 1.0f : -1.0f, 0, 0});
      EXPECT_EQ(t.w, mirrored ? -1.0f : 1.0f);
    }
  }
  // The mirrored triangle lists its corners as (a, c, b).
  GltfBuilder b;
  const int mesh = b.add_mesh({{"POSITION", b.add_vec3(unit_triangle())}});
  b.set_scene({b.add_node({{"mesh", mesh}, {"scale", {-1, 1, 1}}})});
  b.write_data_uri_gltf(path("order.gltf"));
  const Scene s = read_gltf(path("order.gltf"));
  expect_triangle(s, 0, {0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, 0.0f);
}

TEST_F(GltfReader, AttributesFlagsAndNormalizedTexcoords) {
  GltfBuilder b;
  // TEXCOORD_0 as normalized UNSIGNED_BYTE with a padded stride of 4.
  const std::vector<std::uint8_t> uv = {0, 0, 9, 9, 255, 0, 9, 9, 0, 51, 9, 9};
  const int uv_acc = b.add_accessor(b.add_view(uv.data(), uv.size(), 4), GltfBuilder::kUByte, 3, "VEC2", true);
  const int with = b.add_mesh({{"POSITION", b.add_vec3(unit_triangle())}, {"TEXCOORD_0", uv_acc}});
  // A TANGENT without NORMAL is ignored (glTF: flat normals, tangents ignored).
  const int tan = b.add_vec4({{1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}});
  const int without = b.add_mesh({{"POSITION", b.add_vec3(unit_triangle())}, {"TANGENT", tan}});
  b.set_scene({b.add_node({{"mesh", with}}), b.add_node({{"mesh", without}})});
  b.write_data_uri_gltf(path("uv.gltf"));
  const Scene s = read_gltf(path("uv.gltf"));
  ASSERT_EQ(s.triangle_count(), 2u);
  EXPECT_EQ(s.attrib_flags[0], kHasTexcoords);
  EXPECT_EQ(s.texcoords[0], glm::vec2(0, 0));
  EXPECT_EQ(s.texcoords[1], glm::vec2(1, 0));
  EXPECT_EQ(s.texcoords[2], glm::vec2(0, 0.2f));
  EXPECT_EQ(s.attrib_flags[1], 0u);
}

TEST_F(GltfReader, PointsAndLinesAreSkippedAndCounted) {
  GltfBuilder b;
  const int pos = b.add_vec3(unit_triangle());
  json prims = json::array();
  for (int mode : {0, 1, 2, 3, 4}) prims.push_back({{"attributes", {{"POSITION", pos}}}, {"mode", mode}});
  const int mesh = b.push("meshes", {{"primitives", prims}});
  b.single_node_scene(mesh);
  b.write_data_uri_gltf(path("lines.gltf"));
  testing::internal::CaptureStderr();
  const Scene s = read_gltf(path("lines.gltf"));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(s.triangle_count(), 1u);
  EXPECT_EQ(s.source_triangle_id[0], 0u);
  EXPECT_EQ(s.stats.non_triangle_primitives_skipped, 4u);
  // One warning in total, however many primitives were skipped.
  std::size_t warnings = 0;
  for (std::size_t at = err.find("warning"); at != std::string::npos; at = err.find("warning", at + 1)) ++warnings;
  EXPECT_EQ(warnings, 1u) << err;
  EXPECT_NE(err.find("lancer: warning: " + path("lines.gltf").string() + ": skipping point and line primitives"),
            std::string::npos)
      << "the commands' form: " << err;
}

TEST_F(GltfReader, SparseAccessors) {
  GltfBuilder b;
  // Base data with one element replaced: vertex 2 becomes (0, 7, 0).
  const int base = b.add_vec3(unit_triangle());
  const std::vector<std::uint16_t> which = {2};
  const std::vector<glm::vec3> values = {{0, 7, 0}};
  b.doc["accessors"][base]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", b.add_view(which.data(), 2)}, {"componentType", GltfBuilder::kUShort}}},
      {"values", {{"bufferView", b.add_view(values.data(), 12)}}}};
  // No bufferView: zeros, then elements 0 and 2 substituted (element 1 stays 0).
  const std::vector<std::uint8_t> which2 = {0, 2};
  const std::vector<glm::vec3> values2 = {{1, 0, 3}, {0, 1, 3}};
  const int zero =
      b.push("accessors",
             {{"componentType", GltfBuilder::kFloat},
              {"count", 3},
              {"type", "VEC3"},
              {"sparse",
               {{"count", 2},
                {"indices", {{"bufferView", b.add_view(which2.data(), 2)}, {"componentType", GltfBuilder::kUByte}}},
                {"values", {{"bufferView", b.add_view(values2.data(), 24)}}}}}});
  const int m1 = b.add_mesh({{"POSITION", base}});
  const int m2 = b.add_mesh({{"POSITION", zero}});
  b.set_scene({b.add_node({{"mesh", m1}}), b.add_node({{"mesh", m2}})});
  b.write_data_uri_gltf(path("sparse.gltf"));
  const Scene s = read_gltf(path("sparse.gltf"));
  ASSERT_EQ(s.triangle_count(), 2u);
  expect_triangle(s, 0, {0, 0, 0}, {1, 0, 0}, {0, 7, 0}, 0.0f);
  expect_triangle(s, 1, {1, 0, 3}, {0, 0, 0}, {0, 1, 3}, 0.0f);
}

TEST_F(GltfReader, DegenerateTrianglesKeepTheirSourceIds) {
  GltfBuilder b;
  const int pos = b.add_vec3({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  b.single_node_scene(b.add_mesh({{"POSITION", pos}}));
  b.write_data_uri_gltf(path("degenerate.gltf"));
  const Scene s = read_gltf(path("degenerate.gltf"));
  ASSERT_EQ(s.triangle_count(), 1u);
  EXPECT_EQ(s.stats.degenerate_dropped, 1u);
  EXPECT_EQ(s.source_triangle_id, (std::vector<std::uint32_t>{1}));
}

}  // namespace
}  // namespace lancer
