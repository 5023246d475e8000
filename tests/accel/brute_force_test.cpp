#include "accel/brute_force.h"

#include <gtest/gtest.h>

namespace lancer {
namespace {

TriangleSoA two_parallel_triangles() {
  TriangleSoA t;
  t.push_back({0, 0, 0}, {1, 0, 0}, {0, 1, 0});  // z = 0
  t.push_back({0, 0, 1}, {1, 0, 1}, {0, 1, 1});  // z = 1
  return t;
}

TEST(BruteForce, ClosestHitWins) {
  const TriangleSoA t = two_parallel_triangles();
  const BruteForce bf(t);
  Ray r;
  r.org = {0.2f, 0.2f, 5.0f};
  r.dir = {0, 0, -1};
  const Hit h = bf.intersect(r);
  ASSERT_TRUE(h.valid());
  EXPECT_EQ(h.prim, 1u);
  EXPECT_FLOAT_EQ(h.t, 4.0f);
  r.org.z = -5.0f;
  r.dir.z = 1.0f;
  EXPECT_EQ(bf.intersect(r).prim, 0u);
}

TEST(BruteForce, MissHasNoPrimAndInfiniteT) {
  const TriangleSoA t = two_parallel_triangles();
  const BruteForce bf(t);
  Ray r;
  r.org = {5, 5, 5};
  r.dir = {0, 0, -1};
  const Hit h = bf.intersect(r);
  EXPECT_FALSE(h.valid());
  EXPECT_EQ(h.prim, kNoHit);
  EXPECT_EQ(h.t, kInfinity);
  EXPECT_FALSE(bf.occluded(r));
}

TEST(BruteForce, TiesGoToTheLowestIndex) {
  TriangleSoA t;
  t.push_back({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  t.push_back({0, 0, 0}, {1, 0, 0}, {0, 1, 0});  // exact duplicate
  const BruteForce bf(t);
  Ray r;
  r.org = {0.2f, 0.2f, 1.0f};
  r.dir = {0, 0, -1};
  EXPECT_EQ(bf.intersect(r).prim, 0u);
}

TEST(BruteForce, OcclusionRespectsTfar) {
  const TriangleSoA t = two_parallel_triangles();
  const BruteForce bf(t);
  Ray r;
  r.org = {0.2f, 0.2f, 2.0f};
  r.dir = {0, 0, -1};
  r.tfar = 0.5f;
  EXPECT_FALSE(bf.occluded(r));
  r.tfar = 1.5f;
  EXPECT_TRUE(bf.occluded(r));
  EXPECT_EQ(bf.intersect(r).prim, 1u);
}

TEST(BruteForce, EmptySceneNeverHits) {
  const TriangleSoA t;
  const BruteForce bf(t);
  EXPECT_FALSE(bf.intersect(Ray{}).valid());
  EXPECT_FALSE(bf.occluded(Ray{}));
}

}  // namespace
}  // namespace lancer
