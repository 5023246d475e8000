// The scalar watertight kernel (Woop et al. 2013) on hand-checked cases.
#include "accel/watertight.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace lancer {
namespace {

const glm::vec3 kA(0, 0, 0), kB(1, 0, 0), kC(0, 1, 0);

bool hit(const Ray& r, TriangleHit& h, glm::vec3 a = kA, glm::vec3 b = kB, glm::vec3 c = kC) {
  return intersect_watertight(WatertightRay(r), a, b, c, r.tfar, h);
}

TEST(Watertight, HitsInteriorWithBarycentrics) {
  Ray r;
  r.org = {0.25f, 0.5f, 2.0f};
  r.dir = {0, 0, -1};
  TriangleHit h;
  ASSERT_TRUE(hit(r, h));
  EXPECT_FLOAT_EQ(h.t, 2.0f);
  EXPECT_FLOAT_EQ(h.u, 0.25f);  // weight of b = (1,0,0)
  EXPECT_FLOAT_EQ(h.v, 0.5f);   // weight of c = (0,1,0)
}

TEST(Watertight, BothSidesAndUnnormalisedDirection) {
  Ray r;
  r.org = {0.2f, 0.2f, -3.0f};
  r.dir = {0, 0, 2};
  TriangleHit h;
  ASSERT_TRUE(hit(r, h));
  EXPECT_FLOAT_EQ(h.t, 1.5f);  // t in units of |dir|
}

TEST(Watertight, MissesOutsideAndBehind) {
  TriangleHit h;
  Ray r;
  r.org = {0.6f, 0.6f, 1.0f};
  r.dir = {0, 0, -1};
  EXPECT_FALSE(hit(r, h));
  r.org = {0.2f, 0.2f, 1.0f};
  r.dir = {0, 0, 1};
  EXPECT_FALSE(hit(r, h));  // triangle behind the origin
}

TEST(Watertight, RespectsTnearAndTfar) {
  TriangleHit h;
  Ray r;
  r.org = {0.2f, 0.2f, 1.0f};
  r.dir = {0, 0, -1};
  r.tfar = 1.0f;  // a hit exactly at tfar does not count
  EXPECT_FALSE(hit(r, h));
  r.tfar = std::nextafter(1.0f, 2.0f);
  EXPECT_TRUE(hit(r, h));
  r.tnear = std::nextafter(1.0f, 2.0f);
  EXPECT_FALSE(hit(r, h));
}

TEST(Watertight, DegenerateTriangleNeverHits) {
  TriangleHit h;
  Ray r;
  r.org = {0.5f, 0.0f, 1.0f};
  r.dir = {0, 0, -1};
  EXPECT_FALSE(hit(r, h, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}));
  EXPECT_FALSE(hit(r, h, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}));
}

TEST(Watertight, RayInTrianglePlaneDoesNotHit) {
  TriangleHit h;
  Ray r;
  r.org = {-1.0f, 0.25f, 0.0f};
  r.dir = {1, 0, 0};
  EXPECT_FALSE(hit(r, h));
}

// A ray through the shared edge of two triangles hits at least one of them, whatever
// the direction: the edge function is exactly zero on both sides.
TEST(Watertight, SharedEdgeIsClosed) {
  const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(1, 1, 0);  // triangles abc and bdc share bc
  int misses = 0;
  for (int i = 1; i < 1000; ++i) {
    const float s = static_cast<float>(i) / 1000.0f;
    const glm::vec3 p = b + s * (c - b);
    for (const glm::vec3 dir : {glm::vec3(0.1f, 0.3f, -1.0f), glm::vec3(-0.7f, 0.2f, -0.3f), glm::vec3(0, 0, -1)}) {
      Ray r;
      r.dir = dir;
      r.org = p - 3.0f * dir;
      TriangleHit h;
      const bool h1 = intersect_watertight(WatertightRay(r), a, b, c, kInfinity, h);
      const bool h2 = intersect_watertight(WatertightRay(r), b, d, c, kInfinity, h);
      misses += (h1 || h2) ? 0 : 1;
    }
  }
  EXPECT_EQ(misses, 0);
}

// A triangle of subnormal size 0.48 away from the ray's line: after the shear its three
// corners share x and differ in y by subnormals, so the edge functions are of mixed sign
// or zero exactly, but rounded back to float (as in the paper) they read {0, 0, +tiny}
// and the kernel reported a hit at t = -0. Found by KdRobustness.DenormalCoordinates.
TEST(Watertight, SubnormalTriangleOffTheRayNeverHits) {
  const float d = std::numeric_limits<float>::denorm_min();
  Ray r;
  r.org = {9.47025528e-41f, -1.00000022e-39f, 0.479814291f};
  r.dir = {0.218123734f, 0.875024021f, -0.812284112f};
  TriangleHit h;
  EXPECT_FALSE(hit(r, h, {0.0f, 0.0f, 0.0f}, {d, 0.0f, 0.0f}, {0.0f, d, d})) << "t " << h.t;
  // The same triangle scaled up 2^100 (exact) is hit by a ray aimed at it, and missed by this one.
  const float s = std::ldexp(1.0f, 100);
  EXPECT_FALSE(hit(r, h, {0.0f, 0.0f, 0.0f}, {d * s, 0.0f, 0.0f}, {0.0f, d * s, d * s}));
  Ray aimed;
  aimed.org = glm::vec3(d * s * 0.25f, d * s * 0.25f, 1.0f);
  aimed.dir = {0.0f, 0.0f, -1.0f};
  EXPECT_TRUE(hit(aimed, h, {0.0f, 0.0f, 0.0f}, {d * s, 0.0f, 0.0f}, {0.0f, d * s, d * s}));
}

TEST(Watertight, NanRayNeverHits) {
  TriangleHit h;
  Ray r;
  r.org = {0.2f, 0.2f, 1.0f};
  r.dir = {NAN, 0, -1};
  EXPECT_FALSE(hit(r, h));
}

}  // namespace
}  // namespace lancer
