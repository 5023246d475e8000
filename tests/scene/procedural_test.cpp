// Procedural generators: closed, outward-wound meshes with the documented counts, and
// seeded triangle soups that are reproducible and stay inside their box.
#include "scene/procedural.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <tuple>
#include <utility>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/scene_error.h"

namespace lancer {
namespace {

// A vertex compared by its exact bits (so -0.0 and 0.0 differ: no tolerance at all).
using VertexKey = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;

VertexKey key_of(const glm::vec3& p) {
  std::uint32_t b[3];
  std::memcpy(&b[0], &p.x, 4);
  std::memcpy(&b[1], &p.y, 4);
  std::memcpy(&b[2], &p.z, 4);
  return {b[0], b[1], b[2]};
}

struct MeshTopology {
  std::size_t vertices = 0;
  std::size_t edges = 0;
  bool closed = true;  // every undirected edge used exactly twice, once per direction
  std::string problem;
};

// Triangles [first, first + count) of the scene, vertices identified by exact bits.
MeshTopology topology(const Scene& scene, std::size_t first, std::size_t count) {
  std::map<VertexKey, int> ids;
  std::map<std::pair<int, int>, int> directed;  // directed edge -> uses
  for (std::size_t t = first; t < first + count; ++t) {
    int v[3];
    for (int k = 0; k < 3; ++k) v[k] = ids.emplace(key_of(scene.triangles.vertex(t, k)), int(ids.size())).first->second;
    for (int k = 0; k < 3; ++k) ++directed[{v[k], v[(k + 1) % 3]}];
  }
  MeshTopology topo;
  topo.vertices = ids.size();
  std::set<std::pair<int, int>> undirected;
  for (const auto& [edge, uses] : directed) {
    undirected.insert({std::min(edge.first, edge.second), std::max(edge.first, edge.second)});
    const auto reverse = directed.find({edge.second, edge.first});
    if (uses != 1 || reverse == directed.end() || reverse->second != 1) {
      topo.closed = false;
      topo.problem = "edge " + std::to_string(edge.first) + "->" + std::to_string(edge.second) + " used " +
                     std::to_string(uses) + " times, reverse " +
                     std::to_string(reverse == directed.end() ? 0 : reverse->second) + " times";
    }
  }
  topo.edges = undirected.size();
  return topo;
}

glm::vec3 geometric_normal(const Scene& s, std::size_t t) {
  const glm::vec3 a = s.triangles.vertex(t, 0), b = s.triangles.vertex(t, 1), c = s.triangles.vertex(t, 2);
  return glm::cross(b - a, c - a);
}

glm::vec3 centroid(const Scene& s, std::size_t t) {
  return (s.triangles.vertex(t, 0) + s.triangles.vertex(t, 1) + s.triangles.vertex(t, 2)) / 3.0f;
}

void expect_sphere(const Scene& s, glm::vec3 center, float radius, bool smooth) {
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    EXPECT_GT(glm::dot(geometric_normal(s, t), centroid(s, t) - center), 0.0f) << "triangle " << t << " faces inward";
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 d = glm::dvec3(s.triangles.vertex(t, k)) - glm::dvec3(center);
      EXPECT_NEAR(glm::length(d), radius, 1e-6 * radius) << "triangle " << t << " corner " << k;
      if (smooth) {
        const glm::vec3 n = s.normals[3 * t + k];
        EXPECT_NEAR(glm::dot(glm::dvec3(n), glm::normalize(d)), 1.0, 1e-5) << "smooth normal not radial";
      }
    }
    EXPECT_EQ(s.attrib_flags[t] & kHasNormals, smooth ? kHasNormals : 0);
  }
}

struct UvCase {
  int slices, stacks;
};

class UvSphereTest : public ::testing::TestWithParam<UvCase> {};

TEST_P(UvSphereTest, ClosedOutwardAndOnTheSphere) {
  const auto [slices, stacks] = GetParam();
  const glm::vec3 center(1.0f, -2.0f, 3.0f);
  const float radius = 0.75f;
  Scene s;
  append_uv_sphere(s, center, radius, slices, stacks, 0);

  const std::size_t expected_triangles = 2u * slices * (stacks - 1);
  ASSERT_EQ(s.triangle_count(), expected_triangles);
  EXPECT_EQ(s.stats.degenerate_dropped, 0u);
  const MeshTopology topo = topology(s, 0, s.triangle_count());
  EXPECT_TRUE(topo.closed) << topo.problem;
  EXPECT_EQ(topo.vertices, std::size_t(slices) * (stacks - 1) + 2);
  // Euler characteristic of a sphere: V - E + F = 2.
  EXPECT_EQ(std::int64_t(topo.vertices) - std::int64_t(topo.edges) + std::int64_t(expected_triangles), 2);
  expect_sphere(s, center, radius, true);

  ASSERT_EQ(s.materials.size(), 1u) << "the default material is added";
  for (auto id : s.material_id) EXPECT_EQ(id, 0u);
  for (std::size_t t = 0; t < s.triangle_count(); ++t) EXPECT_EQ(s.source_triangle_id[t], t);
}

INSTANTIATE_TEST_SUITE_P(Resolutions, UvSphereTest,
                         ::testing::Values(UvCase{3, 2}, UvCase{4, 3}, UvCase{32, 16}, UvCase{7, 5}, UvCase{64, 33}),
                         [](const auto& test_case) {
                           return std::to_string(test_case.param.slices) + "x" + std::to_string(test_case.param.stacks);
                         });

TEST(UvSphere, FlatShadedStoresNoNormals) {
  Scene s;
  append_uv_sphere(s, glm::vec3(0.0f), 2.0f, 12, 6, 0, /*smooth_normals=*/false);
  expect_sphere(s, glm::vec3(0.0f), 2.0f, false);
}

TEST(UvSphere, AppendsAfterExistingGeometryWithItsMaterial) {
  Scene s;
  s.materials.resize(2);
  append_box(s, Bounds3{glm::vec3(-1.0f), glm::vec3(1.0f)}, 0);
  append_uv_sphere(s, glm::vec3(5.0f, 0.0f, 0.0f), 1.0f, 8, 4, 1);
  ASSERT_EQ(s.triangle_count(), 12u + 2u * 8u * 3u);
  EXPECT_EQ(s.materials.size(), 2u);
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    EXPECT_EQ(s.material_id[t], t < 12 ? 0u : 1u);
    EXPECT_EQ(s.source_triangle_id[t], t);
  }
  EXPECT_TRUE(topology(s, 12, s.triangle_count() - 12).closed);
}

TEST(UvSphere, RejectsBadArguments) {
  Scene s;
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(0.0f), 1.0f, 2, 4, 0), SceneError);
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(0.0f), 1.0f, 8, 1, 0), SceneError);
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(0.0f), 0.0f, 8, 4, 0), SceneError);
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(0.0f), -1.0f, 8, 4, 0), SceneError);
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(0.0f), std::nanf(""), 8, 4, 0), SceneError);
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(INFINITY, 0.0f, 0.0f), 1.0f, 8, 4, 0), SceneError);
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(0.0f), 1.0f, 8, 4, 1), SceneError) << "no material 1";
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(0.0f), 1.0f, 1 << 20, 1 << 20, 0), SceneError) << "too many";
  // A radius float cannot resolve at this position collapses triangles: refused whole.
  EXPECT_THROW(append_uv_sphere(s, glm::vec3(1e6f), 1e-4f, 32, 16, 0), SceneError);
  EXPECT_EQ(s.triangle_count(), 0u) << "nothing is added when the arguments are refused";
}

TEST(UvSphere, ErrorNamesTheScene) {
  Scene s;
  s.source = "bench-spheres";
  try {
    append_uv_sphere(s, glm::vec3(0.0f), 1.0f, 2, 4, 0);
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bench-spheres"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("slices"), std::string::npos) << e.what();
  }
}

class IcosphereTest : public ::testing::TestWithParam<int> {};

TEST_P(IcosphereTest, ClosedOutwardAndOnTheSphere) {
  const int level = GetParam();
  const glm::vec3 center(-0.5f, 0.25f, 4.0f);
  const float radius = 1.5f;
  Scene s;
  append_icosphere(s, center, radius, level, 0);

  const std::size_t faces = 20u << (2 * level);
  ASSERT_EQ(s.triangle_count(), faces);
  const MeshTopology topo = topology(s, 0, s.triangle_count());
  EXPECT_TRUE(topo.closed) << topo.problem;
  EXPECT_EQ(topo.vertices, (10u << (2 * level)) + 2);
  EXPECT_EQ(topo.edges, 30u << (2 * level));
  expect_sphere(s, center, radius, true);
}

INSTANTIATE_TEST_SUITE_P(Levels, IcosphereTest, ::testing::Values(0, 1, 2, 4));

TEST(Icosphere, LevelZeroIsARegularIcosahedron) {
  Scene s;
  append_icosphere(s, glm::vec3(0.0f), 1.0f, 0, 0);
  // Edge of the icosahedron inscribed in the unit sphere: 4 / sqrt(10 + 2 sqrt 5).
  const double edge = 4.0 / std::sqrt(10.0 + 2.0 * std::sqrt(5.0));
  for (std::size_t t = 0; t < s.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(glm::distance(glm::dvec3(s.triangles.vertex(t, k)), glm::dvec3(s.triangles.vertex(t, (k + 1) % 3))),
                  edge, 1e-6);
}

TEST(Icosphere, RejectsBadArguments) {
  Scene s;
  EXPECT_THROW(append_icosphere(s, glm::vec3(0.0f), 1.0f, -1, 0), SceneError);
  EXPECT_THROW(append_icosphere(s, glm::vec3(0.0f), 1.0f, 9, 0), SceneError);
  EXPECT_THROW(append_icosphere(s, glm::vec3(0.0f), 0.0f, 2, 0), SceneError);
  EXPECT_EQ(s.triangle_count(), 0u);
}

TEST(Box, ClosedOutwardTwelveTriangles) {
  Scene s;
  const Bounds3 box{glm::vec3(-1.0f, 0.5f, 2.0f), glm::vec3(3.0f, 0.75f, 2.5f)};
  append_box(s, box, 0);
  ASSERT_EQ(s.triangle_count(), 12u);
  const MeshTopology topo = topology(s, 0, 12);
  EXPECT_TRUE(topo.closed) << topo.problem;
  EXPECT_EQ(topo.vertices, 8u);
  for (std::size_t t = 0; t < 12; ++t) {
    const glm::vec3 n = glm::normalize(geometric_normal(s, t));
    EXPECT_GT(glm::dot(n, centroid(s, t) - box.center()), 0.0f) << "triangle " << t;
    // Axis aligned: exactly one non-zero component, +-1.
    EXPECT_FLOAT_EQ(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0f) << "triangle " << t;
  }
  const Bounds3 b = s.bounds();
  EXPECT_EQ(b.lo, box.lo);
  EXPECT_EQ(b.hi, box.hi);
  EXPECT_THROW(append_box(s, Bounds3{glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 1.0f)}, 0), SceneError);
}

TEST(Quad, TwoTrianglesFacingTheCounterClockwiseSide) {
  Scene s;
  append_quad(s, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0);
  ASSERT_EQ(s.triangle_count(), 2u);
  for (std::size_t t = 0; t < 2; ++t) EXPECT_GT(geometric_normal(s, t).z, 0.0f);
  EXPECT_THROW(append_quad(s, {0, 0, 0}, {1, 0, 0}, {NAN, 1, 0}, {0, 1, 0}, 0), SceneError);
}

bool same_triangles(const Scene& a, const Scene& b) {
  if (a.triangle_count() != b.triangle_count()) return false;
  for (std::size_t t = 0; t < a.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      if (key_of(a.triangles.vertex(t, k)) != key_of(b.triangles.vertex(t, k))) return false;
  return true;
}

TEST(TriangleSoup, SameSeedSameBitsOtherSeedOtherTriangles) {
  const Bounds3 box{glm::vec3(-2.0f, 0.0f, 1.0f), glm::vec3(3.0f, 1.0f, 9.0f)};
  const Scene a = make_random_triangle_soup(1000, 42, box, 0.5f);
  const Scene b = make_random_triangle_soup(1000, 42, box, 0.5f);
  const Scene c = make_random_triangle_soup(1000, 43, box, 0.5f);
  EXPECT_TRUE(same_triangles(a, b));
  EXPECT_FALSE(same_triangles(a, c));
  // A prefix is stable: more triangles from the same seed extend the same stream.
  const Scene shorter = make_random_triangle_soup(10, 42, box, 0.5f);
  for (std::size_t t = 0; t < shorter.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(key_of(shorter.triangles.vertex(t, k)), key_of(a.triangles.vertex(t, k)));
}

TEST(TriangleSoup, PinnedFirstVertexForSeedZero) {
  // Pins the stream itself (splitmix64, top 24 bits), so a change of generator or of
  // the order of draws shows up here rather than as silently different benchmarks.
  const Bounds3 box{glm::vec3(0.0f), glm::vec3(1.0f)};
  const Scene s = make_random_triangle_soup(1, 0, box, 1e-3f);
  // splitmix64(0) first output 0xE220A8397B1DCDAF; top 24 bits 0xE220A8 -> centre x.
  const float centre_x = float(0xE220A8) * 0x1p-24f;
  EXPECT_NEAR(s.triangles.vertex(0, 0).x, centre_x, 0.5e-3f);
}

TEST(TriangleSoup, CountEdgesBoxAndMaterials) {
  const Bounds3 box{glm::vec3(-1.0f, -1.0f, -1.0f), glm::vec3(1.0f, 1.0f, 0.5f)};
  const float max_edge = 0.8f;  // large against the box, so clamping happens often
  const Scene s = make_random_triangle_soup(5000, 7, box, max_edge);
  ASSERT_EQ(s.triangle_count(), 5000u);
  EXPECT_EQ(s.stats.degenerate_dropped, 0u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_NE(s.source.find("seed 7"), std::string::npos);
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    EXPECT_EQ(s.material_id[t], 0u);
    EXPECT_NE(geometric_normal(s, t), glm::vec3(0.0f)) << "triangle " << t;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = s.triangles.vertex(t, k);
      EXPECT_TRUE(p.x >= box.lo.x && p.y >= box.lo.y && p.z >= box.lo.z) << "triangle " << t;
      EXPECT_TRUE(p.x <= box.hi.x && p.y <= box.hi.y && p.z <= box.hi.z) << "triangle " << t;
      // Float rounding of the corner sums may add a few ulps of max_edge.
      EXPECT_LE(glm::distance(p, s.triangles.vertex(t, (k + 1) % 3)), max_edge * (1.0f + 1e-5f)) << "triangle " << t;
    }
  }
  // Triangles spread over the box: the soup's bounds reach close to every face.
  const Bounds3 b = s.bounds();
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT(b.lo[a] - box.lo[a], 0.05f);
    EXPECT_LT(box.hi[a] - b.hi[a], 0.05f);
  }
}

TEST(TriangleSoup, FlatBoxStillGivesTrianglesALineDoesNot) {
  const Scene flat = make_random_triangle_soup(100, 1, Bounds3{glm::vec3(0.0f), glm::vec3(1.0f, 1.0f, 0.0f)}, 0.3f);
  EXPECT_EQ(flat.triangle_count(), 100u);
  EXPECT_THROW(make_random_triangle_soup(1, 1, Bounds3{glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f)}, 0.3f),
               SceneError);
}

TEST(TriangleSoup, RejectsBadArguments) {
  const Bounds3 box{glm::vec3(0.0f), glm::vec3(1.0f)};
  EXPECT_THROW(make_random_triangle_soup(10, 1, Bounds3{}, 0.1f), SceneError) << "empty box";
  EXPECT_THROW(make_random_triangle_soup(10, 1, box, 0.0f), SceneError);
  EXPECT_THROW(make_random_triangle_soup(10, 1, box, INFINITY), SceneError);
  EXPECT_THROW(make_random_triangle_soup(std::size_t(1) << 40, 1, box, 0.1f), SceneError);
  EXPECT_EQ(make_random_triangle_soup(0, 1, box, 0.1f).triangle_count(), 0u);
}

}  // namespace
}  // namespace lancer
