// The kd-tree on awkward input: no triangles, one, zero-area and duplicate triangles, flat
// scenes, triangles all straddling one plane, huge and tiny coordinates, non-finite
// triangles and rays. Each case: the build terminates within its bounds and every ray
// gives exactly the oracle's answer.
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "kd_test_support.h"

namespace lancer::test {
namespace {

const KdSplit kAllSplits[] = {KdSplit::Sah, KdSplit::Middle, KdSplit::Median};
const RayKind kKinds[] = {RayKind::Random,       RayKind::Aimed,          RayKind::Inside,
                          RayKind::AxisParallel, RayKind::InSplitPlane, RayKind::FromSplitPlane};

// Builds all three kinds of tree for `isa` and compares `per_kind` rays of every kind with
// the oracle. Returns the number of oracle hits (some cases must have hits for the test to
// mean much).
std::size_t expect_matches_oracle(const TriangleSoA& tris, std::size_t per_kind, const std::string& what, Isa isa) {
  std::size_t hits = 0;
  for (KdSplit split : kAllSplits) {
    KdBuildOptions o;
    o.split = split;
    const KdTree kd(tris, o, isa);
    EXPECT_LE(kd.references(), kd.reference_budget()) << what;
    if (tris.empty()) continue;
    for (RayKind kind : kKinds) {
      OracleComparison cmp;
      const std::uint64_t seed = 77 + 0x10001ull * std::uint64_t(isa) + std::uint64_t(kind);
      compare_with_oracle(kd, tris, kind, per_kind, seed, true, cmp);
      cmp.expect_no_mismatch(what + " / " + std::string(isa_name(isa)) + " / split " + std::to_string(int(split)) +
                             " / " + ray_kind_name(kind));
      hits += cmp.hits;
    }
  }
  return hits;
}

class KdRobustness : public KdIsaTest {};

TEST_P(KdRobustness, ZeroTriangles) {
  const TriangleSoA none;
  const KdTree kd(none, {}, isa());
  ASSERT_EQ(kd.nodes().size(), 1u);
  EXPECT_TRUE(kd.nodes()[0].is_leaf());
  EXPECT_EQ(kd.nodes()[0].count(), 0u);
  Ray r;
  r.org = {0.0f, 0.0f, -1.0f};
  EXPECT_FALSE(kd.intersect(r).valid());
  EXPECT_EQ(kd.intersect(r).t, kInfinity);
  EXPECT_FALSE(kd.occluded(r));
}

TEST_P(KdRobustness, OneTriangle) {
  TriangleSoA t;
  t.push_back({0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
  EXPECT_GT(expect_matches_oracle(t, 1000, "one triangle", isa()), 0u);
  const KdTree kd(t, {}, isa());
  Ray r;
  r.org = {0.25f, 0.25f, 1.0f};
  r.dir = {0.0f, 0.0f, -1.0f};
  const Hit h = kd.intersect(r);
  EXPECT_EQ(h.prim, 0u);
  EXPECT_EQ(h.t, 1.0f);
}

// Every triangle three times over (exact ties in t: the lowest index must win), plus
// zero-area triangles: collinear corners, two equal corners, all three equal.
TEST_P(KdRobustness, DuplicateAndZeroAreaTriangles) {
  const TriangleSoA base = random_soup(150, 3, {{-1, -1, -1}, {1, 1, 1}}, 0.7f);
  TriangleSoA t;
  TestRng rng(5);
  for (std::size_t i = 0; i < base.size(); ++i) {
    const glm::vec3 a = base.vertex(i, 0), b = base.vertex(i, 1), c = base.vertex(i, 2);
    t.push_back(a, b, c);
    t.push_back(a, b, c);
    t.push_back(b, c, a);  // same triangle, other corner order: t may differ in the last bit
    t.push_back(a, 0.5f * (a + b), b);  // collinear
    t.push_back(a, a, c);
    t.push_back(c, c, c);
    if (rng.below(4) == 0) t.push_back(a, b, c);  // a later duplicate
  }
  EXPECT_GT(expect_matches_oracle(t, 1000, "duplicates and zero-area", isa()), 0u);
}

// All triangles in the plane z = 0.5: the scene box has no extent on z (zero volume, and
// zero area for the cells of a line-like subset).
TEST_P(KdRobustness, FlatScene) {
  const TriangleSoA t = random_soup(600, 4, {{-1.0f, -1.0f, 0.5f}, {1.0f, 1.0f, 0.5f}}, 0.3f);
  const KdTree kd(t, {}, isa());
  EXPECT_EQ(kd.bounds().lo.z, kd.bounds().hi.z);
  EXPECT_GT(kd.nodes().size(), 1u) << "a flat scene still splits on x and y";
  EXPECT_GT(expect_matches_oracle(t, 1000, "flat scene", isa()), 0u);
}

// Triangles in an axis-aligned plane inside a 3D scene, and a scene that is a line.
TEST_P(KdRobustness, PlanarTrianglesAndLineScene) {
  TriangleSoA t = random_soup(300, 6, {{-1.0f, -1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}}, 0.4f);
  const TriangleSoA above = random_soup(300, 7, {{-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}}, 0.4f);
  for (std::size_t i = 0; i < above.size(); ++i) t.push_back(above.vertex(i, 0), above.vertex(i, 1), above.vertex(i, 2));
  EXPECT_GT(expect_matches_oracle(t, 750, "planar triangles in a 3D scene", isa()), 0u);

  TriangleSoA line;
  for (int i = 0; i < 50; ++i) line.push_back({float(i), 0.0f, 0.0f}, {float(i) + 0.5f, 0.0f, 0.0f}, {float(i) + 1.0f, 0.0f, 0.0f});
  const KdTree kd(line, {}, isa());
  EXPECT_EQ(kd.nodes().size(), 1u) << "a scene of zero area is one leaf";
  expect_matches_oracle(line, 500, "line scene", isa());
}

// 3000 long thin triangles all crossing the plane x = 0 (and each other): every split
// near the middle duplicates references, which the reference budget must bound.
TEST_P(KdRobustness, ThousandsStraddlingOnePlane) {
  TriangleSoA t;
  TestRng rng(8);
  for (int i = 0; i < 3000; ++i) {
    const float y = rng.uniform(-1, 1), z = rng.uniform(-1, 1);
    t.push_back({-1.0f, y, z}, {1.0f, y + rng.uniform(-0.01f, 0.01f), z}, {rng.uniform(-1, 1), y, z + 0.02f});
  }
  for (KdSplit split : kAllSplits) {
    KdBuildOptions o;
    o.split = split;
    const KdTree kd(t, o, isa());
    EXPECT_LE(kd.references(), kd.reference_budget());
    EXPECT_LE(kd.reference_budget(), static_cast<std::size_t>(std::ceil(4.0 * 3000)) + 1);
  }
  EXPECT_GT(expect_matches_oracle(t, 300, "straddling one plane", isa()), 0u);
}

TriangleSoA scaled(const TriangleSoA& in, float s) {
  TriangleSoA t;
  for (std::size_t i = 0; i < in.size(); ++i) t.push_back(in.vertex(i, 0) * s, in.vertex(i, 1) * s, in.vertex(i, 2) * s);
  return t;
}

std::string scale_name(float s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "scale %g", double(s));
  return buf;
}

// At 1e30 and 1e-30 the watertight kernel's products overflow or underflow in float, so
// the oracle rarely hits; at 1e-15 it returns t = 0 for triangles anywhere on the ray's
// line (T underflows); at 1e-6 .. 1e6 it works. The tree must agree on every ray in all
// of these (the traversal scans where the kernel breaks down), build in bounded time,
// and keep finite bounds.
TEST_P(KdRobustness, HugeAndTinyCoordinates) {
  const TriangleSoA base = random_soup(300, 9, {{-1, -1, -1}, {1, 1, 1}}, 0.5f);
  for (float s : {1e30f, 1e-30f}) {
    const TriangleSoA t = scaled(base, s);
    const KdTree kd(t, {}, isa());
    EXPECT_TRUE(std::isfinite(kd.bounds().lo.x) && std::isfinite(kd.bounds().hi.x));
    expect_matches_oracle(t, 400, scale_name(s), isa());
  }
  for (float s : {1e15f, 1e-15f, 1e6f, 1e-6f})
    EXPECT_GT(expect_matches_oracle(scaled(base, s), 400, scale_name(s), isa()), 0u);

  // Ordinary triangles plus one at 1e30: a root cell of enormous extent.
  TriangleSoA far = base;
  far.push_back({1e30f, 1e30f, 1e30f}, {1.1e30f, 1e30f, 1e30f}, {1e30f, 1.1e30f, 1e30f});
  far.push_back({-1e30f, 0.0f, 0.0f}, {-1e30f, 1.0f, 0.0f}, {-1e30f, 0.0f, 1.0f});
  EXPECT_GT(expect_matches_oracle(far, 500, "ordinary scene with far triangles", isa()), 0u);
}

// Denormal (subnormal) coordinates: an ordinary scene whose coordinates near zero are
// replaced by subnormals down to the smallest (about 1.4e-45), so that triangles crossing
// the axis planes, split planes at subnormal positions and cells of subnormal width all
// occur; and a scene of subnormal size (degenerate for the kernel, but never a crash or a
// disagreement). Readers keep such positions (they are finite), so the tree must take them.
TEST_P(KdRobustness, DenormalCoordinates) {
  const TriangleSoA base = random_soup(400, 15, {{-1, -1, -1}, {1, 1, 1}}, 0.5f);
  const float subnormals[] = {1e-39f, 3e-41f, 1e-42f, std::numeric_limits<float>::denorm_min()};
  ASSERT_EQ(std::fpclassify(subnormals[0]), FP_SUBNORMAL);
  TriangleSoA snapped;
  TestRng rng(16);
  std::size_t replaced = 0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    glm::vec3 v[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = base.vertex(i, k);
      for (int axis = 0; axis < 3; ++axis)
        if (std::fabs(v[k][axis]) < 0.15f) {
          v[k][axis] = std::copysign(subnormals[rng.below(4)], v[k][axis]);
          ++replaced;
        }
    }
    snapped.push_back(v[0], v[1], v[2]);
  }
  // A few triangles of subnormal size at the origin, inside the ordinary scene.
  for (float s : subnormals) snapped.push_back({0.0f, 0.0f, 0.0f}, {s, 0.0f, 0.0f}, {0.0f, s, s});
  ASSERT_GT(replaced, 100u);
  EXPECT_GT(expect_matches_oracle(snapped, 600, "subnormal coordinates", isa()), 0u);

  const TriangleSoA tiny = scaled(base, 1e-40f);
  const KdTree kd(tiny, {}, isa());
  EXPECT_TRUE(std::isfinite(kd.bounds().lo.x) && std::isfinite(kd.bounds().hi.x));
  expect_matches_oracle(tiny, 300, "scale 1e-40", isa());
}

// Triangles with NaN or infinite corners are left out of the tree; the oracle never hits
// them either.
TEST_P(KdRobustness, NonFiniteTriangles) {
  TriangleSoA t = random_soup(200, 10, {{-1, -1, -1}, {1, 1, 1}}, 0.5f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
  t.push_back({nan, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
  t.push_back({0.0f, 0.0f, 0.0f}, {inf, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
  t.push_back({-inf, -inf, 0.0f}, {inf, -inf, 0.0f}, {0.0f, inf, 0.0f});
  const KdTree kd(t, {}, isa());
  EXPECT_TRUE(std::isfinite(kd.bounds().lo.x) && std::isfinite(kd.bounds().hi.x));
  EXPECT_GT(expect_matches_oracle(t, 500, "non-finite triangles", isa()), 0u);
}

// Degenerate rays: zero direction, NaN or infinite origin, NaN direction, empty or NaN
// ranges, negative tnear (hits behind the origin count when tnear allows them).
TEST_P(KdRobustness, DegenerateRays) {
  const TriangleSoA t = random_soup(200, 11, {{-1, -1, -1}, {1, 1, 1}}, 0.5f);
  const KdTree kd(t, {}, isa());
  const BruteForce oracle(t);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Ray> rays;
  TestRng rng(12);
  for (int i = 0; i < 200; ++i) {
    Ray r;
    r.org = rng.in_box({{-1, -1, -1}, {1, 1, 1}});
    r.dir = rng.direction();
    Ray z = r;
    z.dir = glm::vec3(0.0f);
    rays.push_back(z);
    z = r;
    z.dir[i % 3] = (i & 4) ? kInfinity : -kInfinity;  // the kernel reports t = 0 "hits" here
    rays.push_back(z);
    Ray n = r;
    n.org[i % 3] = nan;
    rays.push_back(n);
    n = r;
    n.dir[i % 3] = nan;
    rays.push_back(n);
    n = r;
    n.org[i % 3] = kInfinity;
    rays.push_back(n);
    n = r;
    n.tnear = 2.0f;
    n.tfar = 1.0f;
    rays.push_back(n);
    n = r;
    n.tnear = nan;
    rays.push_back(n);
    n = r;
    n.tfar = nan;
    rays.push_back(n);
    n = r;
    n.tnear = -1.5f;  // the segment starts behind the origin
    rays.push_back(n);
    n.tnear = -kInfinity;
    rays.push_back(n);
  }
  std::size_t hits = 0;
  for (const Ray& r : rays) {
    const Hit a = kd.intersect(r), b = oracle.intersect(r);
    EXPECT_TRUE(same_hit(a, b)) << describe(r) << ": kd prim " << a.prim << ", oracle prim " << b.prim;
    EXPECT_EQ(kd.occluded(r), oracle.occluded(r)) << describe(r);
    hits += b.valid();
  }
  EXPECT_GT(hits, 0u);
}

// Directions with components far smaller than the others (down to float denormals): the
// traversal computes their plane distances in double instead of float.
TEST_P(KdRobustness, TinyDirectionComponents) {
  const TriangleSoA t = random_soup(400, 13, {{-1, -1, -1}, {1, 1, 1}}, 0.4f);
  const KdTree kd(t, {}, isa());
  const BruteForce oracle(t);
  TestRng rng(14 + isa_seed());
  const float tiny[] = {1e-12f, 1e-20f, 1e-30f, 1e-38f, 1e-42f, 1e-45f};
  std::size_t hits = 0;
  for (int i = 0; i < 3000; ++i) {
    Ray r;
    r.org = rng.in_box({{-1.5f, -1.5f, -1.5f}, {1.5f, 1.5f, 1.5f}});
    r.dir = rng.direction();
    r.dir[i % 3] = (i & 8 ? -1.0f : 1.0f) * tiny[rng.below(6)];
    if (i % 5 == 0) r.dir[(i + 1) % 3] = tiny[rng.below(6)];
    const Hit a = kd.intersect(r), b = oracle.intersect(r);
    EXPECT_TRUE(same_hit(a, b)) << describe(r) << ": kd prim " << a.prim << ", oracle prim " << b.prim;
    EXPECT_EQ(kd.occluded(r), oracle.occluded(r)) << describe(r);
    hits += b.valid();
  }
  EXPECT_GT(hits, 300u);
}

INSTANTIATE_TEST_SUITE_P(AllIsas, KdRobustness, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
