// The two-level accelerator (two_level.h) on random instanced scenes: bit for bit the
// definition (every instance scanned) with kd-tree and brute-force bottoms on every ISA,
// the flattened world-space scene within stated tolerances, and its input checks.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/accel_factory.h"
#include "accel/kd_tree.h"
#include "accel/two_level.h"
#include "two_level_test_support.h"

namespace lancer::test {
namespace {

std::string describe_hit(const Hit& h) {
  std::ostringstream s;
  s.precision(9);
  s << "instance " << h.instance << " prim " << h.prim << " t " << h.t << " u " << h.u << " v " << h.v;
  return s.str();
}

class TwoLevel : public KdIsaTest {};

// (a) kd-tree bottoms, brute-force bottoms and the definition agree bit for bit, for
// closest hit and occlusion, on every ray kind; each ISA gets its own scene and rays.
TEST_P(TwoLevel, KdBottomsMatchBruteBottomsAndTheDefinition) {
  const InstancedScene s = random_instanced_scene(isa_seed() + 11);
  const TwoLevelAccelerator kd(s.tris, s.geometry, "kdtree", {}, isa());
  const TwoLevelAccelerator brute(s.tris, s.geometry, "brute");
  const InstanceScan scan(s);
  const FlatScene flat = flatten(s);
  const Bounds3 box = flat.tris.bounds();
  std::size_t hits = 0, ties = 0, occluded = 0;
  constexpr std::size_t kRays = 4000;
  for (std::size_t i = 0; i < kRays; ++i) {
    const Ray r = instanced_scene_ray(s, flat, box, isa_seed() + 3, i);
    const Hit expected = scan.intersect(r);
    const Hit a = kd.intersect(r), b = brute.intersect(r);
    ASSERT_TRUE(same_bits(a, expected)) << describe(r) << "\n kd bottoms: " << describe_hit(a)
                                        << "\n definition: " << describe_hit(expected);
    ASSERT_TRUE(same_bits(b, expected)) << describe(r) << "\n brute bottoms: " << describe_hit(b)
                                        << "\n definition: " << describe_hit(expected);
    const bool blocked = scan.occluded(r);
    ASSERT_EQ(kd.occluded(r), blocked) << describe(r);
    ASSERT_EQ(brute.occluded(r), blocked) << describe(r);
    ASSERT_EQ(blocked, expected.valid()) << describe(r);
    hits += expected.valid() ? 1 : 0;
    ties += expected.instance == 5 ? 1 : 0;  // instance 6 coincides with 5 and must lose every tie
    occluded += blocked ? 1 : 0;
    ASSERT_NE(expected.instance, 6u) << describe(r);
  }
  EXPECT_GT(hits, kRays / 4) << "most ray kinds should mostly hit";
  EXPECT_GT(ties, 0u) << "some rays should hit the coincident instances";
}

// (b) Against the scene flattened into world space in double (a different rounding of the
// same geometry). The two agree up to the rounding of the transforms: a few float ulps of
// the coordinates, times the transforms' condition (< 10 here), i.e. about 1e-6 of the
// scene's size. So, for each ray:
//  - t agrees within 1e-4 relative (plus 1e-4 of the scene size over |dir|), far above
//    that rounding, far below any error a wrong transform or a skipped instance makes;
//    the (instance, triangle) may then differ only in a near tie (coincident instances,
//    shared edges, crossing triangles);
//  - otherwise (a hit against a miss, or against a farther hit) the nearer hit must lie
//    within 1e-3 of its triangle's edge (barycentric): rounding can move a ray across
//    that silhouette, and the other answer then sees what lies behind.
// Such excused rays must stay rare: under 1% of all rays, and under half of those aimed
// exactly at a vertex (one kind in eight, all on edges).
TEST(TwoLevelWorld, MatchesTheFlattenedSceneWithinTolerance) {
  const InstancedScene s = random_instanced_scene(77, 24);
  const TwoLevelAccelerator accel(s.tris, s.geometry, "kdtree");
  const FlatScene flat = flatten(s);
  const BruteForce oracle(flat.tris);
  const Bounds3 box = flat.tris.bounds();
  const glm::vec3 e = box.extent();
  const double size = std::fmax(e.x, std::fmax(e.y, e.z));
  constexpr std::size_t kRays = 6000;
  std::size_t hits = 0, excused = 0, excused_at_vertices = 0, instances_hit = 0;
  std::vector<bool> seen(s.geometry.instances.size(), false);
  auto near_edge = [](const Hit& h) { return std::fmin(std::fmin(h.u, h.v), 1.0f - h.u - h.v) < 1e-3f; };
  for (std::size_t i = 0; i < kRays; ++i) {
    const Ray r = instanced_scene_ray(s, flat, box, 99, i);
    const Hit a = accel.intersect(r);
    Hit b = oracle.intersect(r);
    if (b.valid()) {
      const std::uint32_t k = b.prim;
      b.instance = flat.instance[k];
      b.prim = flat.prim[k];
    }
    if (a.valid() != b.valid()) {
      const Hit& h = a.valid() ? a : b;
      ASSERT_TRUE(near_edge(h)) << describe(r) << ": only one hits, away from an edge\n two-level: " << describe_hit(a)
                                << "\n flattened: " << describe_hit(b);
      ++(i % 8 == 2 ? excused_at_vertices : excused);
      continue;
    }
    if (!a.valid()) continue;
    ++hits;
    if (!seen[a.instance]) seen[a.instance] = true, ++instances_hit;
    const double dir_len = std::sqrt(double(r.dir.x) * r.dir.x + double(r.dir.y) * r.dir.y + double(r.dir.z) * r.dir.z);
    const double tol = 1e-4 * std::fabs(double(b.t)) + 1e-4 * size / dir_len;
    if (std::fabs(double(a.t) - double(b.t)) > tol) {
      // Only the nearer hit's silhouette can explain it: the other answer missed it.
      ASSERT_TRUE(near_edge(a.t < b.t ? a : b))
          << describe(r) << "\n two-level: " << describe_hit(a) << "\n flattened: " << describe_hit(b);
      ++(i % 8 == 2 ? excused_at_vertices : excused);
    } else if (a.instance != b.instance || a.prim != b.prim) {
      ++(i % 8 == 2 ? excused_at_vertices : excused);  // a near tie
    }
  }
  EXPECT_LT(excused, kRays / 100) << "too many rays excused by the tolerances";
  EXPECT_LT(excused_at_vertices, kRays / 8 / 2) << "too many rays aimed at vertices excused";
  EXPECT_GT(hits, kRays / 4);
  EXPECT_EQ(instances_hit, s.geometry.instances.size() - 1) << "every instance but the losing twin should be hit";
}

// (e) Invalid input is refused with std::invalid_argument.
TEST(TwoLevelInput, InvalidInputThrows) {
  const InstancedScene good = random_instanced_scene(5, 0);
  auto expect_throw = [&](const InstancedScene& s, const char* what) {
    EXPECT_THROW(TwoLevelAccelerator(s.tris, s.geometry, "kdtree"), std::invalid_argument) << what;
    EXPECT_THROW(TwoLevelAccelerator(s.tris, s.geometry, "brute"), std::invalid_argument) << what;
  };
  {
    InstancedScene s = good;
    s.geometry.meshes[1].count += 1;  // runs past the end of the triangles
    expect_throw(s, "mesh range past the end");
  }
  {
    InstancedScene s = good;
    s.geometry.meshes[0] = {0xFFFFFFFFu, 2};  // first + count overflows 32 bits
    expect_throw(s, "mesh range overflowing");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[2].mesh = 3;
    expect_throw(s, "instance of a missing mesh");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[1].to_world.linear[1][2] = std::numeric_limits<float>::quiet_NaN();
    expect_throw(s, "NaN in to_world");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[3].to_object.offset.y = kInfinity;
    expect_throw(s, "infinite to_object");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[0].to_world.linear = glm::mat3(0.0f);
    expect_throw(s, "singular to_world");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[0] = make_instance(0, glm::dmat3(1e20), {0, 0, 0});
    expect_throw(s, "scale beyond 2^40");
  }
  EXPECT_THROW(TwoLevelAccelerator(good.tris, good.geometry, "bvh"), std::invalid_argument);
  EXPECT_THROW(make_accelerator("bvh", good.tris, good.geometry), std::invalid_argument);
  const TwoLevelAccelerator accel(good.tris, good.geometry, "kdtree");
  Ray r;
  Hit h;
  bool b = false;
  EXPECT_THROW(accel.intersect_packet(&r, &h, -1), std::invalid_argument);
  EXPECT_THROW(accel.occluded_packet(&r, &b, -1), std::invalid_argument);
  EXPECT_NO_THROW(accel.intersect_packet(&r, &h, 0));
}

// The factory: empty geometry gives today's one-level accelerator, otherwise a two-level
// one over the named bottom; meshes no instance draws get no tree.
TEST(TwoLevelFactory, PicksOneOrTwoLevels) {
  const InstancedScene s = random_instanced_scene(6, 2);
  EXPECT_EQ(make_accelerator("kdtree", s.tris, InstancedGeometry{})->name(), "kdtree");
  EXPECT_EQ(make_accelerator("brute", s.tris, InstancedGeometry{})->name(), "brute");
  for (const char* bottom : {"kdtree", "brute"}) {
    const auto accel = make_accelerator(bottom, s.tris, s.geometry);
    ASSERT_EQ(accel->name(), "twolevel");
    const auto& two = dynamic_cast<const TwoLevelAccelerator&>(*accel);
    EXPECT_EQ(two.bottom_name(), bottom);
    EXPECT_EQ(two.instance_count(), s.geometry.instances.size());
    EXPECT_EQ(two.mesh_count(), 3u);
    EXPECT_EQ(two.bottom_count(), 2u) << "mesh 2 is drawn by no instance";
    EXPECT_GT(two.top_level().nodes().size(), 1u);
  }
}

// Edge cases of the input: no instances, an instance of an empty mesh, non-finite rays
// (the scan path) and a zero direction give the definition's answers.
TEST(TwoLevelInput, EmptyAndDegenerateCases) {
  InstancedScene s = random_instanced_scene(8, 0);
  {
    InstancedScene none = s;
    none.geometry.instances.clear();
    const TwoLevelAccelerator accel(none.tris, none.geometry, "kdtree");
    EXPECT_FALSE(accel.intersect(Ray{}).valid());
    EXPECT_FALSE(accel.occluded(Ray{}));
  }
  s.geometry.meshes.push_back({5, 0});  // an empty mesh, drawn
  s.geometry.instances.push_back(make_instance(3, glm::dmat3(1.0), {0, 0, 0}));
  const TwoLevelAccelerator accel(s.tris, s.geometry, "kdtree");
  const InstanceScan scan(s);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Ray rays[] = {
      Ray{{-10.0f, 0.1f, 0.2f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInfinity},
      Ray{{nan, 0.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInfinity},
      Ray{{-10.0f, 0.0f, 0.0f}, 0.0f, {kInfinity, 0.0f, 0.0f}, kInfinity},
      Ray{{-10.0f, 0.1f, 0.2f}, 0.0f, {0.0f, 0.0f, 0.0f}, kInfinity},
      Ray{{-10.0f, 0.1f, 0.2f}, 0.0f, {1e-30f, 1e-31f, 0.0f}, kInfinity},
      Ray{{1e25f, 0.1f, 0.2f}, 0.0f, {-1.0f, 0.0f, 0.0f}, kInfinity},
  };
  for (const Ray& r : rays) {
    EXPECT_TRUE(same_bits(accel.intersect(r), scan.intersect(r))) << describe(r);
    EXPECT_EQ(accel.occluded(r), scan.occluded(r)) << describe(r);
  }
  EXPECT_TRUE(accel.intersect(rays[0]).valid());
}

INSTANTIATE_TEST_SUITE_P(AllIsas, TwoLevel, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
