// The top level's cheap first test (two_level::segment_misses): it may answer "misses" only
// where setup_top_ray answers Miss, and must answer it for most rays that end far from the
// root box (else it saves nothing). Rays ending just short of the box, within the slack
// setup_top_ray adds, are where a margin too small would fail.
#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "accel/two_level_ray.h"
#include "kd_test_support.h"

namespace lancer::test {
namespace {

using two_level::segment_misses;
using two_level::setup_top_ray;
using two_level::TopPlan;

// A random box, a point on (or just beside) it, and a ray ending at a parameter placed a
// tiny relative distance before or after that point: the grazing cases.
TEST(TopLevelRay, SegmentMissesOnlyWhereTheSetupMisses) {
  TestRng rng(1234);
  std::size_t rejected = 0, far_misses = 0, rejected_far = 0, grazing_traverse = 0;
  for (int i = 0; i < 200000; ++i) {
    const float scale = std::ldexp(1.0f, int(rng.below(24)) - 12);
    Bounds3 root;
    root.extend(rng.in_box({{-scale, -scale, -scale}, {scale, scale, scale}}));
    root.extend(rng.in_box({{-scale, -scale, -scale}, {scale, scale, scale}}));
    const double beta = rng.below(2) ? 0.0 : std::ldexp(1.0, -18 - int(rng.below(8)));
    const double extent = rng.below(2) ? 0.0 : double(scale) * rng.uniform();
    Ray r;
    r.dir = rng.direction();
    if (rng.below(4) == 0) r.dir[int(rng.below(3))] = 0.0f;  // parallel to an axis
    r.dir *= std::ldexp(1.0f, int(rng.below(16)) - 8);
    // A target on the box's surface (a face, edge or corner), the ray ending near it.
    glm::vec3 target = rng.in_box(root);
    for (int a = 0; a < 3; ++a)
      if (rng.below(2)) target[a] = rng.below(2) ? root.lo[a] : root.hi[a];
    const float back = scale * rng.uniform(0.01f, 4.0f);
    r.org = target - back * r.dir;
    r.tnear = rng.below(3) == 0 ? 0.0f : back * rng.uniform(0.0f, 0.5f);
    const float rel = std::ldexp(1.0f, -int(rng.below(24)));
    const bool far_short = rng.below(4) == 0;
    r.tfar = far_short ? back * rng.uniform(0.0f, 0.3f) : back * (1.0f + (rng.below(2) ? rel : -rel));
    if (r.tfar < r.tnear) r.tfar = r.tnear;
    const bool misses = segment_misses(r, root, beta, extent);
    const TopPlan plan = setup_top_ray(r, root, beta, extent).plan;
    if (misses) {
      ASSERT_EQ(plan, TopPlan::Miss) << "segment_misses but setup_top_ray traverses: org (" << r.org.x << ", "
                                     << r.org.y << ", " << r.org.z << ") dir (" << r.dir.x << ", " << r.dir.y
                                     << ", " << r.dir.z << ") t [" << r.tnear << ", " << r.tfar << "]";
    }
    rejected += misses ? 1 : 0;
    if (!far_short && plan == TopPlan::Traverse && r.tfar < back) ++grazing_traverse;
    if (far_short && plan == TopPlan::Miss) {
      ++far_misses;
      rejected_far += misses ? 1 : 0;
    }
  }
  EXPECT_GT(grazing_traverse, 1000u) << "too few rays end just short of the box yet reach it through the slack";
  EXPECT_GT(far_misses, 10000u);
  EXPECT_GT(rejected_far, far_misses * 9 / 10) << "the first test should catch most rays ending far from the box";
  EXPECT_GT(rejected, 0u);
}

// Rays setup_top_ray scans (not finite, huge origins, tiny or huge directions) and rays
// with an infinite tfar are never answered by the first test.
TEST(TopLevelRay, SegmentMissesLeavesScanRaysAndOpenRaysAlone) {
  const Bounds3 root{{0, 0, 0}, {1, 1, 1}};
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto ray = [](glm::vec3 org, glm::vec3 dir, float tnear, float tfar) {
    Ray r;
    r.org = org;
    r.dir = dir;
    r.tnear = tnear;
    r.tfar = tfar;
    return r;
  };
  EXPECT_TRUE(segment_misses(ray({5, 5, 5}, {1, 0, 0}, 0, 1), root, 0, 0));  // the control
  EXPECT_FALSE(segment_misses(ray({5, 5, 5}, {1, 0, 0}, 0, inf), root, 0, 0));
  EXPECT_FALSE(segment_misses(ray({5, 5, 5}, {1, 0, 0}, 0, nan), root, 0, 0));
  EXPECT_FALSE(segment_misses(ray({5, nan, 5}, {1, 0, 0}, 0, 1), root, 0, 0));
  EXPECT_FALSE(segment_misses(ray({5, 5, 5}, {inf, 0, 0}, 0, 1), root, 0, 0));
  EXPECT_FALSE(segment_misses(ray({0x1p62f, 5, 5}, {1, 0, 0}, 0, 1), root, 0, 0));
  EXPECT_FALSE(segment_misses(ray({5, 5, 5}, {0x1p-62f, 0, 0}, 0, 1), root, 0, 0));
  EXPECT_FALSE(segment_misses(ray({5, 5, 5}, {0x1p62f, 0, 0}, 0, 1), root, 0, 0));
  EXPECT_EQ(setup_top_ray(ray({0x1p62f, 5, 5}, {1, 0, 0}, 0, 1), root, 0, 0).plan, TopPlan::Scan);
}

}  // namespace
}  // namespace lancer::test
