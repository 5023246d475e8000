// kd_setup_ray_float, the single-ray traversal's common-case setup: it takes every ordinary
// ray, its interval covers the whole stretch of the ray inside the scene box (computed
// here in double), it says Miss only for rays that never enter the box, and it declines
// (leaving the setup to the double-precision path) every ray outside its limits.
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>

#include "accel/kd_traverse_setup.h"
#include "accel/kd_tree.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

// A box-shaped scene (two triangles on opposite corners span it) of the given size.
KdTree box_scene(glm::vec3 lo, glm::vec3 hi) {
  TriangleSoA t;
  t.push_back(lo, {hi.x, lo.y, lo.z}, {lo.x, hi.y, lo.z});
  t.push_back(hi, {lo.x, hi.y, hi.z}, {hi.x, lo.y, hi.z});
  return KdTree(t, {}, Isa::Scalar);
}

// The exact stretch [enter, leave] of the ray inside the box, in double.
struct Stretch {
  double enter, leave;
};
Stretch inside(const Bounds3& b, const Ray& r) {
  double enter = r.tnear, leave = r.tfar;
  for (int a = 0; a < 3; ++a) {
    const double ta = (double(b.lo[a]) - r.org[a]) / r.dir[a], tb = (double(b.hi[a]) - r.org[a]) / r.dir[a];
    enter = std::max(enter, std::min(ta, tb));
    leave = std::min(leave, std::max(ta, tb));
  }
  return {enter, leave};
}

TEST(KdSetupFloat, CoversTheRayInsideTheSceneBox) {
  for (const float scale : {1e-3f, 1.0f, 1e4f}) {
    const KdTree kd = box_scene(glm::vec3(-1.0f, -2.0f, 0.5f) * scale, glm::vec3(3.0f, 1.0f, 4.0f) * scale);
    const KdTreeView v = view(kd);
    SplitMix64 rng(42);
    auto in = [&](float lo, float hi) { return lo + (hi - lo) * rng.uniform(); };
    int covered = 0, missed = 0;  // rays with a stretch inside the box, and misses
    for (int i = 0; i < 200000; ++i) {
      Ray r;
      r.org = glm::vec3(in(-6, 8), in(-7, 6), in(-4, 9)) * scale;
      if (i % 2 == 0) {  // aimed at a point of the box, else any direction
        r.dir = glm::vec3(in(-1, 3), in(-2, 1), in(0.5f, 4)) * scale - r.org;
      } else {
        r.dir = glm::vec3(in(-1, 1), in(-1, 1), in(-1, 1));
      }
      if (i % 3 == 0) r.dir *= 1e-3f;
      for (int a = 0; a < 3; ++a)
        if (std::fabs(r.dir[a]) < 1e-6f) r.dir[a] = 1e-6f;
      r.tnear = i % 4 == 0 ? in(0, 2) * scale : 0.0f;
      r.tfar = i % 5 == 0 ? in(0, 10) * scale : kInfinity;
      KdRaySetup s{};
      ASSERT_TRUE(kd_setup_ray_float(v, r, s)) << "ray " << i << " declined";
      const Stretch st = inside(kd.bounds(), r);
      if (s.plan == KdPlan::Miss) {
        ++missed;
        ASSERT_GT(st.enter, st.leave) << "ray " << i << " enters the box but was set up as a miss";
        continue;
      }
      ASSERT_EQ(s.plan, KdPlan::Traverse);
      ASSERT_TRUE(s.float_ok);
      if (st.enter <= st.leave) {
        ++covered;
        ASSERT_LE(double(s.t0_f), st.enter) << "ray " << i;
        ASSERT_GE(double(s.t1_f), st.leave) << "ray " << i;
      }
      for (int a = 0; a < 3; ++a) {
        ASSERT_EQ(s.inv_dir_f[a], 1.0f / r.dir[a]);
        ASSERT_EQ(s.negative[a], r.dir[a] < 0.0f);
        ASSERT_FALSE(s.parallel[a]);
      }
    }
    std::printf("scale %g: %d rays inside the box checked, %d misses\n", double(scale), covered, missed);
    EXPECT_GT(covered, 40000);
    EXPECT_GT(missed, 40000);
  }
}

TEST(KdSetupFloat, DeclinesRaysOutsideItsLimits) {
  const KdTree kd = box_scene({0, 0, 0}, {1, 1, 1});
  const KdTreeView v = view(kd);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Ray ordinary{{-1.0f, 0.3f, 0.4f}, 0.0f, {1.0f, 0.1f, 0.2f}, kInfinity};
  KdRaySetup ok{};
  ASSERT_TRUE(kd_setup_ray_float(v, ordinary, ok));
  EXPECT_EQ(ok.plan, KdPlan::Traverse);
  auto declined = [&](Ray r, const char* what) {
    KdRaySetup s{};
    s.plan = KdPlan::Scan;  // must stay untouched
    EXPECT_FALSE(kd_setup_ray_float(v, r, s)) << what;
    EXPECT_EQ(s.plan, KdPlan::Scan) << what;
    EXPECT_FALSE(s.float_ok) << what;
  };
  Ray r = ordinary;
  r.dir.y = 0.0f;
  declined(r, "axis-parallel");
  r = ordinary, r.dir.z = 1e-19f;
  declined(r, "direction component below 2^-60");
  r = ordinary, r.org.x = nan;
  declined(r, "NaN origin");
  r = ordinary, r.dir.x = kInfinity;
  declined(r, "infinite direction");
  r = ordinary, r.tnear = kInfinity;
  declined(r, "infinite tnear");
  r = ordinary, r.tfar = -kInfinity;
  declined(r, "tfar of -inf");
  r = ordinary, r.org.x = -1e30f;
  declined(r, "origin far beyond the box");
  r = ordinary, r.dir *= 1e30f;
  declined(r, "huge direction");
  r = ordinary, r.dir = glm::vec3(1e-18f);
  declined(r, "tiny direction (plane distances beyond 2^60)");
}

}  // namespace
}  // namespace lancer
