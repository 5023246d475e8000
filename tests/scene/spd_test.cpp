// The SPD generators: documented triangle counts, no zero-area triangles, closed and
// outward-wound pieces, open surfaces facing the right way, the SPD layout, viewpoint
// and lights, determinism, and refusal of sizes out of range or over the cap.
#include "scene/spd.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <ostream>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include <glm/geometric.hpp>

#include "mesh_checks.h"

namespace lancer {
namespace {

using test::closed_mesh_problem;
using test::geometric_normal;
using test::signed_volume6;

std::uint64_t per_sphere(int s) { return 20ull << (2 * s); }
std::uint64_t pow_u(std::uint64_t b, int e) {
  std::uint64_t r = 1;
  for (int i = 0; i < e; ++i) r *= b;
  return r;
}

struct Piece {
  std::size_t first, count;
};

// Where a generator puts its pieces, written from spd.h independently of the code:
// open squares and terrain first, then the closed pieces in emission order.
struct Layout {
  std::vector<Piece> open;    // squares (2 triangles) and the mount terrain
  std::vector<Piece> closed;  // spheres, cylinders, tetrahedra, gears
  std::size_t total() const {
    std::size_t n = 0;
    for (const auto& p : open) n += p.count;
    for (const auto& p : closed) n += p.count;
    return n;
  }
};

Layout layout_of(const std::string& name, int n, const SpdOptions& o) {
  Layout l;
  std::size_t next = 0;
  const auto open = [&](std::size_t count) { l.open.push_back({next, count}), next += count; };
  const auto closed = [&](std::size_t count) { l.closed.push_back({next, count}), next += count; };
  const std::size_t sphere = per_sphere(o.sphere_subdivisions), cylinder = 4 * std::size_t(o.cylinder_sides);
  if (name == "balls") {
    open(2);
    for (std::uint64_t i = 0; i < (pow_u(9, n + 1) - 1) / 8; ++i) closed(sphere);
  } else if (name == "tetra") {
    for (std::uint64_t i = 0; i < pow_u(4, n - 1); ++i) closed(4);
  } else if (name == "mount") {
    open(2 * pow_u(4, n));
    for (int i = 0; i < 4; ++i) closed(sphere);
  } else if (name == "rings") {
    open(2);
    const std::size_t objects = std::size_t(n) * (n + 1) * (2 * n + 1) / 6;
    for (std::size_t i = 0; i < 6 * objects * 5; ++i) {
      closed(sphere);
      closed(cylinder);
    }
  } else if (name == "gears") {
    open(2);
    for (std::uint64_t i = 0; i < pow_u(std::uint64_t(n), 3); ++i) closed(576);
  }
  return l;
}

struct Case {
  const char* name;
  int size;
  SpdOptions options;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.name << " size " << c.size << ", sphere subdivisions " << c.options.sphere_subdivisions
      << ", cylinder sides " << c.options.cylinder_sides;
}

class SpdShapes : public ::testing::TestWithParam<Case> {};

TEST_P(SpdShapes, CountsClosednessAndOrientation) {
  const Case c = GetParam();
  const Scene s = make_spd(c.name, c.size, c.options);
  const Layout layout = layout_of(c.name, c.size, c.options);
  ASSERT_EQ(s.triangle_count(), layout.total()) << "the documented formula";
  EXPECT_EQ(spd_triangle_count(c.name, c.size, c.options), s.triangle_count());
  EXPECT_EQ(s.stats.degenerate_dropped, 0u) << "zero-area triangles were dropped";
  for (std::size_t t = 0; t < s.triangle_count(); ++t)
    ASSERT_GT(glm::length(geometric_normal(s, t)), 0.0) << "triangle " << t;

  for (const Piece& p : layout.closed) {
    const std::string problem = closed_mesh_problem(s, p.first, p.count);
    ASSERT_TRUE(problem.empty()) << problem;
    ASSERT_GT(signed_volume6(s, p.first, p.count), 0.0) << "piece at " << p.first << " winds inward";
  }
  // Open squares face the camera (the SPD's floors and walls are seen from the front).
  ASSERT_EQ(s.cameras.size(), 1u);
  const glm::dvec3 eye(s.cameras[0].camera_to_world[3]);
  for (const Piece& p : layout.open) {
    if (p.count != 2) continue;  // the terrain is checked in its own test
    for (std::size_t t = p.first; t < p.first + 2; ++t)
      EXPECT_GT(glm::dot(geometric_normal(s, t), eye - glm::dvec3(s.triangles.vertex(t, 0))), 0.0)
          << "square triangle " << t << " faces away from the camera";
  }
  EXPECT_GE(s.materials.size(), std::string(c.name) == "tetra" ? 1u : 2u);
  for (std::uint32_t id : s.material_id) ASSERT_LT(id, s.materials.size());
  for (const Material& m : s.materials) {  // SPD glass is solid: it must refract, not be a thin wall
    if (m.transmission > 0.0f) {
      EXPECT_GT(m.thickness, 0.0f) << m.name;
    }
  }
  EXPECT_FALSE(s.lights.empty());
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(info.param.name) + std::to_string(info.param.size) + "_s" +
         std::to_string(info.param.options.sphere_subdivisions) + "_k" +
         std::to_string(info.param.options.cylinder_sides);
}

INSTANTIATE_TEST_SUITE_P(SmallSizes, SpdShapes,
                         ::testing::Values(Case{"balls", 0, {1, 16}}, Case{"balls", 1, {0, 16}},
                                           Case{"balls", 2, {1, 16}}, Case{"tetra", 1, {}}, Case{"tetra", 2, {}},
                                           Case{"tetra", 4, {}}, Case{"mount", 0, {0, 16}}, Case{"mount", 2, {1, 16}},
                                           Case{"mount", 4, {2, 16}}, Case{"rings", 1, {0, 3}},
                                           Case{"rings", 2, {1, 8}}, Case{"rings", 1, {2, 16}}, Case{"gears", 1, {}},
                                           Case{"gears", 2, {}}, Case{"gears", 3, {}}),
                         case_name);

TEST(SpdCounts, MatchTheSpdTablesAndFormulas) {
  const SpdOptions coarse{0, 3};
  // Sphere counts 10, 91, 820, 7381 (SPD balls table), 20 triangles each, plus the floor.
  EXPECT_EQ(spd_triangle_count("balls", 1, coarse), 10u * 20 + 2);
  EXPECT_EQ(spd_triangle_count("balls", 2, coarse), 91u * 20 + 2);
  EXPECT_EQ(spd_triangle_count("balls", 3, coarse), 820u * 20 + 2);
  EXPECT_EQ(spd_triangle_count("balls", 4, coarse), 7381u * 20 + 2);
  EXPECT_EQ(spd_triangle_count("tetra", 6), 4096u);                          // SPD: 4096 triangles
  EXPECT_EQ(spd_triangle_count("mount", 6, coarse), 8192u + 80);             // SPD: 8192 triangles, 4 spheres
  EXPECT_EQ(spd_triangle_count("rings", 7, coarse), 4200u * (20 + 12) + 2);  // SPD: 4200 spheres and cylinders
  EXPECT_EQ(spd_triangle_count("gears", 4), 64u * 576 + 2);                  // SPD: 64 gears
  // Large sizes, without building anything.
  EXPECT_EQ(spd_triangle_count("balls", 5), 66430u * 320 + 2);
  EXPECT_EQ(spd_triangle_count("balls", 6, coarse), 597871u * 20 + 2);
  EXPECT_EQ(spd_triangle_count("tetra", 12), 16777216u);
  EXPECT_EQ(spd_triangle_count("mount", 12), 33554432u + 1280);
  EXPECT_EQ(spd_triangle_count("rings", 14), 30u * 1015 * (320 + 64) + 2);
  EXPECT_EQ(spd_triangle_count("gears", 44), 85184u * 576 + 2);
  EXPECT_GT(spd_triangle_count("balls", 6), kSpdMaxTriangles) << "past the cap, the count is still reported";
}

TEST(SpdCounts, NamesAndRanges) {
  EXPECT_EQ(spd_names(), (std::vector<std::string_view>{"balls", "gears", "mount", "rings", "tetra"}));
  EXPECT_EQ(spd_size_range("balls").min, 0);
  EXPECT_EQ(spd_size_range("balls").max, 6);
  EXPECT_EQ(spd_size_range("tetra").min, 1);
  EXPECT_EQ(spd_size_range("tetra").max, 12);
  EXPECT_EQ(spd_size_range("mount").max, 12);
  EXPECT_EQ(spd_size_range("rings").max, 50);
  EXPECT_EQ(spd_size_range("gears").max, 44);
  // At each top size, some tessellation stays under the cap: the ranges are usable.
  for (std::string_view name : spd_names())
    EXPECT_LE(spd_triangle_count(name, spd_size_range(name).max, {0, 3}), kSpdMaxTriangles) << name;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no std::invalid_argument thrown)";
}

TEST(SpdRefusals, UnknownNamesSizesAndOptions) {
  EXPECT_NE(message_of([] { make_spd("teapot", 1); }).find("unknown SPD scene 'teapot'"), std::string::npos);
  EXPECT_NE(message_of([] { spd_size_range("x"); }).find("unknown SPD scene"), std::string::npos);
  const std::string too_big = message_of([] { make_spd("balls", 7); });
  EXPECT_NE(too_big.find("spd balls"), std::string::npos) << too_big;
  EXPECT_NE(too_big.find("size 7"), std::string::npos) << too_big;
  EXPECT_NE(too_big.find("0..6"), std::string::npos) << too_big;
  EXPECT_NE(message_of([] { make_spd("tetra", 0); }).find("1..12"), std::string::npos);
  EXPECT_NE(message_of([] { spd_triangle_count("gears", -1); }).find("1..44"), std::string::npos);
  EXPECT_NE(message_of([] { make_spd("rings", 51); }).find("1..50"), std::string::npos);
  EXPECT_NE(message_of([] { make_spd("mount", 13); }).find("0..12"), std::string::npos);
  EXPECT_NE(message_of([] { make_spd("balls", 1, {9, 16}); }).find("sphere subdivisions 9"), std::string::npos);
  EXPECT_NE(message_of([] { make_spd("rings", 1, {1, 2}); }).find("cylinder sides 2"), std::string::npos);
  EXPECT_NE(message_of([] { make_spd("rings", 1, {1, 1025}); }).find("3..1024"), std::string::npos);
}

TEST(SpdRefusals, CountsOverTheCapBeforeAllocating) {
  // 191 million triangles (about 29 GB as a Scene): refused from the formula at once.
  const auto start = std::chrono::steady_clock::now();
  const std::string message = message_of([] { make_spd("balls", 6); });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(message.find("spd balls"), std::string::npos) << message;
  EXPECT_NE(message.find("191318722 triangles"), std::string::npos) << message;
  EXPECT_NE(message.find("limit of 50000000"), std::string::npos) << message;
  EXPECT_LT(seconds, 1.0) << "the cap must be checked before building";
  EXPECT_NE(message_of([] { make_spd("rings", 50); }).find("limit"), std::string::npos);
  EXPECT_NE(message_of([] { make_spd("balls", 5, {3, 16}); }).find("limit"), std::string::npos);
}

bool same_bits(const Scene& a, const Scene& b) {
  if (a.triangle_count() != b.triangle_count()) return false;
  for (int k = 0; k < 3; ++k) {
    const std::size_t bytes = a.triangle_count() * sizeof(float);
    if (std::memcmp(a.triangles.x[k].data(), b.triangles.x[k].data(), bytes) != 0 ||
        std::memcmp(a.triangles.y[k].data(), b.triangles.y[k].data(), bytes) != 0 ||
        std::memcmp(a.triangles.z[k].data(), b.triangles.z[k].data(), bytes) != 0)
      return false;
  }
  // Normals may be absent: an empty array, whose data() may be null (no memcmp then).
  const bool same_normals =
      a.normals.size() == b.normals.size() &&
      (a.normals.empty() || std::memcmp(a.normals.data(), b.normals.data(), a.normals.size() * sizeof(glm::vec3)) == 0);
  return a.material_id == b.material_id && a.attrib_flags == b.attrib_flags && same_normals &&
         a.materials.size() == b.materials.size() && a.lights.size() == b.lights.size();
}

TEST(SpdDeterminism, SameArgumentsSameBits) {
  for (std::string_view name : spd_names()) {
    const int size = spd_size_range(name).min + 1;
    EXPECT_TRUE(same_bits(make_spd(name, size, {1, 5}), make_spd(name, size, {1, 5}))) << name;
  }
}

TEST(SpdLayout, BallsSitOnTheFloorInsideTheUnitSphere) {
  const Scene s = make_spd("balls", 2, {1, 16});
  // The floor: y = -0.5 (SPD z), +-12 in x and z.
  for (std::size_t t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = s.triangles.vertex(t, k);
      EXPECT_EQ(p.y, -0.5f);
      EXPECT_EQ(std::abs(p.x), 12.0f);
      EXPECT_EQ(std::abs(p.z), 12.0f);
    }
  // The SPD sizes the flake to fit in a sphere of radius 1; tessellated spheres lie
  // inside their true spheres, so nothing goes below the floor.
  for (std::size_t t = 2; t < s.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = s.triangles.vertex(t, k);
      EXPECT_LE(glm::length(glm::dvec3(p)), 1.0 + 1e-6);
      EXPECT_GE(p.y, -0.5f - 1e-6f);
    }
  // The big sphere is first: its corners are 0.5 from the origin.
  EXPECT_NEAR(glm::length(glm::dvec3(s.triangles.vertex(2, 0))), 0.5, 1e-6);
}

TEST(SpdLayout, TetraFillsTheCubeCorners) {
  for (int size : {1, 3, 5}) {
    const Bounds3 b = make_spd("tetra", size).bounds();
    EXPECT_EQ(b.lo, glm::vec3(-1.0f)) << size;
    EXPECT_EQ(b.hi, glm::vec3(1.0f)) << size;
  }
}

TEST(SpdLayout, MountTerrainFacesUpWithItsBoundaryOnTheBorder) {
  const int size = 4;
  const Scene s = make_spd("mount", size, {1, 16});
  const std::size_t terrain = 2u << (2 * size);
  for (std::size_t t = 0; t < terrain; ++t) ASSERT_GT(geometric_normal(s, t).y, 0.0) << "terrain triangle " << t;
  const test::EdgeUse e(s, 0, terrain);
  std::size_t boundary = 0;
  for (const auto& [key, n] : e.directed) {
    const auto a = std::uint32_t(key >> 32), b = std::uint32_t(key);
    ASSERT_EQ(n, 1) << "directed edge used twice";
    if (e.uses(b, a) == 1) continue;  // interior edge
    ++boundary;
    for (std::uint32_t v : {a, b}) {
      const glm::vec3 p = e.position[v];
      EXPECT_TRUE(std::abs(p.x) == 1.0f || std::abs(p.z) == 1.0f) << "boundary edge inside the terrain";
    }
  }
  EXPECT_EQ(boundary, 4u << size) << "the border is 4 * 2^n edges";
  // The four outer corners stay at height 0; the terrain spans [-1, 1] in x and z.
  std::size_t corners = 0;
  for (const glm::vec3& p : e.position) {
    EXPECT_LE(std::abs(p.x), 1.0f);
    EXPECT_LE(std::abs(p.z), 1.0f);
    if (std::abs(p.x) == 1.0f && std::abs(p.z) == 1.0f) {
      EXPECT_EQ(p.y, 0.0f);
      ++corners;
    }
  }
  EXPECT_EQ(corners, 4u);
}

TEST(SpdLayout, MountOfSizeNIsMountOfSizeNPlusOneSampled) {
  const auto terrain_points = [](int size) {
    const Scene s = make_spd("mount", size, {0, 16});
    return test::EdgeUse(s, 0, 2u << (2 * size)).position;
  };
  const std::vector<glm::vec3> coarse = terrain_points(3), fine = terrain_points(4);
  std::unordered_set<glm::vec3, test::BitsHash, test::BitsEqual> fine_set(fine.begin(), fine.end());
  EXPECT_EQ(coarse.size(), 81u);
  for (const glm::vec3& p : coarse) EXPECT_TRUE(fine_set.count(p)) << p.x << " " << p.y << " " << p.z;
  // And the mountain is not flat.
  float top = 0.0f;
  for (const glm::vec3& p : fine) top = std::max(top, std::abs(p.y));
  EXPECT_GT(top, 0.05f);
}

TEST(SpdLayout, GearsStandOnTheGroundInTheUnitBlock) {
  const int size = 3;
  const Scene s = make_spd("gears", size);
  for (std::size_t t = 2; t < s.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = s.triangles.vertex(t, k);
      ASSERT_LE(std::abs(p.x), 1.0f);
      ASSERT_LE(std::abs(p.z), 1.0f);
      ASSERT_GT(p.y, 0.0f);
      ASSERT_LE(p.y, 1.0f);
    }
  // Each gear face is a fan of 144 triangles around its axis; the top of gear 0 is
  // at y = 1 (the first layer) or below.
  EXPECT_GT(s.materials.size(), 2u) << "gears get several colours";
}

TEST(SpdView, CameraAndLightsFollowTheSpd) {
  const Scene s = make_spd("balls", 0, {0, 16});
  ASSERT_EQ(s.cameras.size(), 1u);
  const CameraDesc& c = s.cameras[0];
  EXPECT_FLOAT_EQ(c.yfov, float(45.0 * std::numbers::pi / 180.0));
  ASSERT_TRUE(c.aspect_ratio.has_value());
  EXPECT_EQ(*c.aspect_ratio, 1.0f);
  // SPD eye (2.1, 1.3, 1.7) looking at the origin, z up; the scene swaps y and z.
  const glm::vec3 eye(c.camera_to_world[3]);
  EXPECT_EQ(eye, glm::vec3(2.1f, 1.7f, 1.3f));
  const glm::vec3 forward = -glm::vec3(c.camera_to_world[2]);
  EXPECT_NEAR(glm::dot(forward, glm::normalize(-eye)), 1.0f, 1e-6f);
  const glm::vec3 up(c.camera_to_world[1]), right(c.camera_to_world[0]);
  EXPECT_GT(up.y, 0.0f) << "the image is upright";
  EXPECT_NEAR(glm::dot(glm::cross(right, up), -forward), 1.0f, 1e-6f) << "right-handed camera frame";

  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].position, glm::vec3(4.0f, 2.0f, 3.0f));
  EXPECT_EQ(s.lights[1].position, glm::vec3(1.0f, 4.0f, -4.0f));
  EXPECT_EQ(s.lights[2].position, glm::vec3(-3.0f, 5.0f, 1.0f));
  // Relative intensity sqrt(3) / 6 at the look-at point, for a white diffuse surface.
  EXPECT_NEAR(s.lights[0].intensity, std::sqrt(3.0) / 6.0 * std::numbers::pi * 29.0, 1e-3);
  for (const PunctualLight& l : s.lights) EXPECT_EQ(l.type, LightType::Point);

  const std::size_t light_counts[] = {3, 5, 1, 3, 1};  // balls, gears, mount, rings, tetra
  for (std::size_t i = 0; i < spd_names().size(); ++i) {
    const std::string_view name = spd_names()[i];
    EXPECT_EQ(make_spd(name, spd_size_range(name).min, {0, 3}).lights.size(), light_counts[i]) << name;
  }
}

TEST(SpdLarge, TetraOfAMillionTriangles) {
  const auto start = std::chrono::steady_clock::now();
  const Scene s = make_spd("tetra", 10);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(s.triangle_count(), 1048576u);
  EXPECT_EQ(s.stats.degenerate_dropped, 0u);
  EXPECT_EQ(s.bounds().lo, glm::vec3(-1.0f));
  EXPECT_EQ(s.bounds().hi, glm::vec3(1.0f));
  // Spot-check a few of the 262144 tetrahedra.
  for (std::size_t first : {std::size_t(0), std::size_t(4 * 1000), s.triangle_count() - 4}) {
    EXPECT_TRUE(closed_mesh_problem(s, first, 4).empty());
    EXPECT_GT(signed_volume6(s, first, 4), 0.0);
  }
  ::testing::Test::RecordProperty("seconds", std::to_string(seconds));
}

}  // namespace
}  // namespace lancer
