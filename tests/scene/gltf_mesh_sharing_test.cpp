// Meshes drawn more than once stored once (--instancing): every drawing through its
// instance is where, and shaded as, the flattened copy of the same file puts it; posed,
// singular and single drawings stay in world space; ids follow the flattened numbering.
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include "scene/gltf_mesh_sharing.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_instancing.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// A four-triangle tent with normals, tangents and texture coordinates, so each attribute's
// move to world space is checked.
int add_tent_mesh(GltfBuilder& b) {
  const std::vector<glm::vec3> p = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, 1, 0}};
  std::vector<glm::vec3> n;
  for (const glm::vec3& v : p) n.push_back(glm::normalize(v + glm::vec3(0.0f, 2.0f, 0.0f)));
  const std::vector<glm::vec4> t = {{1, 0, 0, 1}, {1, 0, 0, 1}, {0, 0, 1, -1}, {0, 1, 1, 1}, {1, 1, 0, -1}};
  const std::vector<glm::vec2> uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}};
  const std::vector<std::uint16_t> indices = {0, 4, 1, 1, 4, 2, 2, 4, 3, 3, 4, 0};
  return b.add_mesh({{"POSITION", b.add_vec3(p)},
                     {"NORMAL", b.add_vec3(n)},
                     {"TANGENT", b.add_vec4(t)},
                     {"TEXCOORD_0", b.add_vec2(uv)}},
                    4, b.add_indices(indices));
}

// The tent drawn by five nodes and three EXT_mesh_gpu_instancing instances (turned,
// non-uniformly scaled, mirrored, and once through a singular matrix), and a one-triangle
// mesh drawn once.
GltfBuilder shared_tents() {
  GltfBuilder b;
  const int tent = add_tent_mesh(b);
  const int single = b.add_mesh({{"POSITION", b.add_vec3(gltf_test::unit_triangle())}});
  std::vector<int> roots;
  roots.push_back(b.add_node({{"mesh", tent}, {"translation", {1.0, 0.5, -2.0}}}));
  roots.push_back(b.add_node({{"mesh", tent},
                              {"rotation", {0.0, std::sin(0.3), 0.0, std::cos(0.3)}},
                              {"scale", {1.0, 2.0, 0.5}},
                              {"translation", {-3.0, 0.0, 0.0}}}));
  roots.push_back(b.add_node({{"mesh", tent}, {"scale", {-1.0, 1.0, 1.0}}, {"translation", {0.0, 3.0, 0.0}}}));
  // Singular: copied flat into x = 0, where two faces keep their area and two lose it.
  roots.push_back(b.add_node({{"mesh", tent}, {"scale", {0.0, 1.0, 1.0}}}));
  roots.push_back(b.add_node({{"mesh", single}, {"translation", {0.0, 0.0, 5.0}}}));
  const std::vector<glm::vec3> t = {{0, 0, 10}, {2, 0, 10}, {4, 0, 10}};
  const std::vector<glm::vec4> r = {{0, 0, 0, 1}, {0, 0, std::sin(0.5f), std::cos(0.5f)}, {0, 0, 0, 1}};
  const std::vector<glm::vec3> s = {{1, 1, 1}, {1, 3, 1}, {1, -1, 1}};
  const json attributes = {{"TRANSLATION", b.add_vec3(t)}, {"ROTATION", b.add_vec4(r)}, {"SCALE", b.add_vec3(s)}};
  roots.push_back(b.add_node({{"mesh", tent},
                              {"scale", {2.0, 2.0, 2.0}},
                              {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}}));
  b.set_scene(roots);
  b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  return b;
}

float distance_scale(const glm::vec3& a) { return 1.0f + std::max(std::fabs(a.x), std::max(std::fabs(a.y), std::fabs(a.z))); }

class GltfMeshSharing : public gltf_test::GltfTempDir {
 protected:
  Scene load(InstancingMode mode) {
    const auto file = path("tents.gltf");
    shared_tents().write_data_uri_gltf(file);
    return read_gltf(file, -1, std::nullopt, mode);
  }
};

TEST_F(GltfMeshSharing, EveryDrawingMatchesItsFlattenedCopy) {
  const Scene flat = load(InstancingMode::Off);
  const Scene shared = load(InstancingMode::On);
  ASSERT_TRUE(flat.instancing.empty());
  ASSERT_FALSE(shared.instancing.empty());
  // The world-space mesh (the single triangle and the two faces of the singular node's
  // copy that keep an area) and the tent, stored once; its six unposed, invertible drawings.
  ASSERT_EQ(shared.instancing.meshes.size(), 2u);
  EXPECT_EQ(shared.instancing.meshes[0].count, 3u);
  EXPECT_EQ(shared.instancing.meshes[1].count, 4u);
  ASSERT_EQ(shared.instancing.instances.size(), 1u + 6u);
  EXPECT_EQ(shared.triangle_count(), 7u);
  EXPECT_EQ(shared.drawn_triangle_count(), flat.triangle_count());
  EXPECT_EQ(shared.stats.degenerate_dropped, flat.stats.degenerate_dropped);
  EXPECT_EQ(flat.stats.degenerate_dropped, 2u);

  std::map<std::uint32_t, std::uint32_t> flat_by_id;
  for (std::uint32_t i = 0; i < flat.triangle_count(); ++i) flat_by_id[flat.source_triangle_id[i]] = i;
  std::size_t matched = 0, mirrored = 0;
  for (std::uint32_t k = 0; k < shared.instancing.instances.size(); ++k) {
    const Instance& inst = shared.instancing.instances[k];
    const MeshRange& mesh = shared.instancing.meshes[inst.mesh];
    const bool mirror = glm::determinant(inst.to_world.linear) < 0.0f;
    mirrored += mirror ? 1 : 0;
    const glm::mat3 normal_matrix = glm::transpose(inst.to_object.linear);
    for (std::uint32_t prim = mesh.first; prim < mesh.first + mesh.count; ++prim) {
      const std::uint32_t id = shared.source_id(prim, k);
      ASSERT_EQ(flat_by_id.count(id), 1u) << "instance " << k << " triangle " << prim << " id " << id;
      const std::uint32_t f = flat_by_id[id];
      ++matched;
      // The flattened copy of a mirrored drawing has its second and third corners swapped.
      const int corner_of[3] = {0, mirror ? 2 : 1, mirror ? 1 : 2};
      ASSERT_EQ(shared.attrib_flags[prim], flat.attrib_flags[f]);
      const bool attributes = (flat.attrib_flags[f] & kHasNormals) != 0;
      for (int c = 0; c < 3; ++c) {
        const glm::vec3 want = flat.triangles.vertex(f, corner_of[c]);
        const glm::vec3 got = inst.to_world.point(shared.triangles.vertex(prim, c));
        EXPECT_LT(glm::length(got - want), 1e-5f * distance_scale(want)) << "instance " << k << " corner " << c;
        if (!attributes) continue;
        const std::size_t sc = 3 * std::size_t(prim) + std::size_t(c), fc = 3 * std::size_t(f) + std::size_t(corner_of[c]);
        const glm::vec3 n = glm::normalize(normal_matrix * shared.normals[sc]);
        EXPECT_LT(glm::length(n - flat.normals[fc]), 1e-5f) << "instance " << k << " normal " << c;
        const glm::vec3 t = glm::normalize(inst.to_world.vector(glm::vec3(shared.tangents[sc])));
        EXPECT_LT(glm::length(t - glm::vec3(flat.tangents[fc])), 1e-5f) << "instance " << k << " tangent " << c;
        EXPECT_EQ(mirror ? -shared.tangents[sc].w : shared.tangents[sc].w, flat.tangents[fc].w);
        EXPECT_EQ(shared.texcoords[sc], flat.texcoords[fc]);
      }
      EXPECT_EQ(shared.material_id[prim], flat.material_id[f]);
    }
  }
  EXPECT_EQ(matched, flat.triangle_count());
  EXPECT_EQ(mirrored, 2u);  // the node scaled by -1 in x, the instance scaled by -1 in y

  const Bounds3 a = shared.bounds(), b = flat.bounds();
  EXPECT_LT(glm::length(a.lo - b.lo), 1e-4f);
  EXPECT_LT(glm::length(a.hi - b.hi), 1e-4f);
}

TEST_F(GltfMeshSharing, AutoSharesOnlyWhereCopiesWouldCostManyTriangles) {
  // Eight drawings of a four-triangle tent would add 28 triangles: copied.
  const Scene small = load(InstancingMode::Auto);
  EXPECT_TRUE(small.instancing.empty());
  EXPECT_EQ(small.triangle_count(), load(InstancingMode::Off).triangle_count());

  // Two drawings of a mesh of 2^16 triangles: shared.
  GltfBuilder b;
  std::vector<glm::vec3> p;
  std::vector<std::uint32_t> indices;
  const int n = 1 << 16;
  for (int i = 0; i < n; ++i) {
    p.insert(p.end(), {{float(i), 0, 0}, {float(i) + 1, 0, 0}, {float(i), 1, 0}});
    indices.insert(indices.end(), {std::uint32_t(3 * i), std::uint32_t(3 * i + 1), std::uint32_t(3 * i + 2)});
  }
  const int mesh = b.add_mesh({{"POSITION", b.add_vec3(p)}}, 4, b.add_indices(indices));
  b.set_scene({b.add_node({{"mesh", mesh}}), b.add_node({{"mesh", mesh}, {"translation", {0.0, 0.0, 1.0}}})});
  b.write_data_uri_gltf(path("big.gltf"));
  const Scene big = read_gltf(path("big.gltf"));
  ASSERT_EQ(big.instancing.instances.size(), 2u);
  EXPECT_EQ(big.triangle_count(), std::size_t(n));
  EXPECT_EQ(big.drawn_triangle_count(), 2 * std::size_t(n));
  // The second drawing's ids follow the first's, as in the flattened file.
  EXPECT_EQ(big.source_id(0, 0), 0u);
  EXPECT_EQ(big.source_id(0, 1), std::uint32_t(n));
}

TEST_F(GltfMeshSharing, SkinnedAndMorphedDrawingsStayInWorldSpace) {
  GltfBuilder b = shared_tents();
  // Morph weights on one drawing: its own shape, so its own copy.
  const int target = b.add_vec3(std::vector<glm::vec3>(5, glm::vec3(0.0f, 0.5f, 0.0f)));
  b.doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", target}}};
  b.doc["nodes"][0]["weights"] = {1.0};
  b.write_data_uri_gltf(path("morphed.gltf"));
  const Scene s = read_gltf(path("morphed.gltf"), -1, std::nullopt, InstancingMode::On);
  ASSERT_EQ(s.instancing.meshes.size(), 2u);
  EXPECT_EQ(s.instancing.meshes[0].count, 1u + 2u + 4u);  // single, singular and morphed drawings
  EXPECT_EQ(s.instancing.instances.size(), 1u + 5u);
  bool lifted = false;
  for (std::uint32_t i = 0; i < s.instancing.meshes[0].count; ++i)
    for (int c = 0; c < 3; ++c) lifted |= s.triangles.vertex(i, c).y == 2.0f;  // apex 1 + 0.5, moved up 0.5
  EXPECT_TRUE(lifted);
}

TEST(SceneInstancing, MakeInstanceRefusesSingularAndIllConditionedMatrices) {
  EXPECT_FALSE(make_instance(0, glm::dmat4(0.0)));
  glm::dmat4 flat(1.0);
  flat[2][2] = 1e-9;  // condition number 1e9
  EXPECT_FALSE(make_instance(0, flat));
  glm::dmat4 nan(1.0);
  nan[3][0] = std::nan("");
  EXPECT_FALSE(make_instance(0, nan));
  EXPECT_FALSE(make_instance(0, glm::dmat4(1e12)));  // uniform, but beyond what the accelerator bounds
  glm::dmat4 ok(1.0);
  ok[0][0] = -2.0;
  ok[3] = glm::dvec4(1.0, 2.0, 3.0, 1.0);
  const std::optional<Instance> inst = make_instance(7, ok);
  ASSERT_TRUE(inst);
  EXPECT_EQ(inst->mesh, 7u);
  const glm::vec3 p(0.25f, -1.0f, 4.0f);
  EXPECT_EQ(inst->to_object.point(inst->to_world.point(p)), p);
}

TEST(SceneInstancing, ReorderRefusesAnythingButAPermutation) {
  Scene s;
  for (int i = 0; i < 3; ++i) s.triangles.push_back({float(i), 0, 0}, {float(i) + 1, 0, 0}, {float(i), 1, 0});
  s.material_id = {0, 1, 2};
  s.source_triangle_id = {10, 11, 12};
  s.attrib_flags = {0, 0, 0};
  EXPECT_THROW(reorder_triangles(s, std::vector<std::uint32_t>{0, 1}), std::invalid_argument);
  EXPECT_THROW(reorder_triangles(s, std::vector<std::uint32_t>{0, 1, 1}), std::invalid_argument);
  reorder_triangles(s, std::vector<std::uint32_t>{2, 0, 1});
  EXPECT_EQ(s.source_triangle_id, (std::vector<std::uint32_t>{12, 10, 11}));
  EXPECT_EQ(s.material_id, (std::vector<std::uint32_t>{2, 0, 1}));
  EXPECT_EQ(s.triangles.vertex(0, 0).x, 2.0f);
}

}  // namespace
}  // namespace lancer
