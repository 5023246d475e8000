// The counted single-ray kernels (intersect_counted, occluded_counted), which the benchmarks
// use to report node steps, leaves and triangle tests per ray: on every ISA they give the
// plain kernels' answers, and what they count follows from how the traversal works.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "kd_test_support.h"

namespace lancer::test {
namespace {

class KdCounts : public KdIsaTest {};

bool operator==(const KdTraversalCounts& a, const KdTraversalCounts& b) {
  return a.inner_steps == b.inner_steps && a.leaves == b.leaves && a.triangle_tests == b.triangle_tests;
}

KdTraversalCounts minus(const KdTraversalCounts& a, const KdTraversalCounts& b) {
  return {a.inner_steps - b.inner_steps, a.leaves - b.leaves, a.triangle_tests - b.triangle_tests};
}

// Any-hit and closest-hit visit nodes in the same front-to-back order, and closest-hit
// culls nothing before its first hit, which lies in the leaf where any-hit stops. So per
// ray any-hit never counts more than closest-hit, and exactly as much when nothing is hit.
TEST_P(KdCounts, SameAnswersAndAnyHitNeverCountsMoreThanClosestHit) {
  const TriangleSoA tris = random_soup(3000, 7, {{-1, -1, -1}, {1, 1, 1}}, 0.3f);
  const KdTree kd(tris, {}, isa());
  const std::vector<SplitPlane> planes = split_planes(kd);
  const RayKind kinds[] = {RayKind::Random, RayKind::Aimed, RayKind::Inside, RayKind::AxisParallel,
                           RayKind::FromSplitPlane, RayKind::Segment};
  std::size_t rays = 0, hits = 0, with_work = 0;
  KdTraversalCounts all_closest, all_any;
  for (RayKind kind : kinds)
    for (std::uint64_t i = 0; i < 2000; ++i) {
      TestRng rng(0xC0FFEEull * (static_cast<std::uint64_t>(kind) + 1) + i + isa_seed());
      const Ray r = make_ray(kind, tris, kd.bounds(), planes, rng);
      const KdTraversalCounts closest_before = all_closest, any_before = all_any;
      const Hit h = kd.intersect_counted(r, all_closest);
      const bool occluded = kd.occluded_counted(r, all_any);
      const KdTraversalCounts c = minus(all_closest, closest_before), a = minus(all_any, any_before);
      ++rays;
      ASSERT_TRUE(same_hit(h, kd.intersect(r))) << ray_kind_name(kind) << " ray " << i;
      ASSERT_EQ(occluded, kd.occluded(r)) << ray_kind_name(kind) << " ray " << i;
      SCOPED_TRACE(std::string(ray_kind_name(kind)) + " ray " + std::to_string(i));
      EXPECT_LE(a.inner_steps, c.inner_steps);
      EXPECT_LE(a.leaves, c.leaves);
      EXPECT_LE(a.triangle_tests, c.triangle_tests);
      if (!h.valid()) {
        EXPECT_FALSE(occluded);
        EXPECT_TRUE(a == c) << "a ray that hits nothing does the same work in both kernels";
      } else {
        ++hits;
        EXPECT_TRUE(occluded);
        EXPECT_GE(c.leaves, 1u) << "a hit is found in a leaf";
        EXPECT_GE(c.triangle_tests, 1u) << "a hit needs a triangle test";
      }
      if (c.inner_steps > 0) ++with_work;
    }
  EXPECT_GT(hits, rays / 10) << "the rays should hit something";
  EXPECT_GT(with_work, rays / 2) << "most rays should step through inner nodes of a 3000-triangle tree";
  EXPECT_LT(all_any.triangle_tests, all_closest.triangle_tests) << "any-hit should stop early on some ray";
  std::printf("[ info     ] %s: %zu rays, closest-hit %.1f steps / %.1f leaves / %.1f tests per ray\n",
              std::string(isa_name(isa())).c_str(), rays, double(all_closest.inner_steps) / double(rays),
              double(all_closest.leaves) / double(rays), double(all_closest.triangle_tests) / double(rays));
}

// A ray that misses the scene box does no traversal work at all.
TEST_P(KdCounts, RayMissingTheSceneBoxCountsNothing) {
  const TriangleSoA tris = random_soup(500, 8, {{-1, -1, -1}, {1, 1, 1}}, 0.3f);
  const KdTree kd(tris, {}, isa());
  Ray r;
  r.org = {5.0f, 5.0f, 5.0f};
  r.dir = {1.0f, 0.0f, 0.0f};
  KdTraversalCounts c;
  EXPECT_FALSE(kd.intersect_counted(r, c).valid());
  EXPECT_FALSE(kd.occluded_counted(r, c));
  EXPECT_TRUE(c == KdTraversalCounts{});
}

INSTANTIATE_TEST_SUITE_P(AllIsas, KdCounts, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
