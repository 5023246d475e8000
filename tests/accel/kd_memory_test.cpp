// The build's memory bound: references at most ceil(reference_factor * N) + 1, nodes at
// most 2 * budget * depth_bound + 1, leaves no deeper than the depth bound (which the
// traversal stack holds), on inputs that make every split duplicate references.
#include <cmath>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "accel/kd_stats.h"
#include "accel/kd_tree.h"
#include "kd_test_support.h"
#include "scene/spd.h"

namespace lancer::test {
namespace {

// `n` large triangles that all overlap each other across the whole box.
TriangleSoA overlapping_triangles(std::size_t n, std::uint64_t seed) {
  TestRng rng(seed);
  TriangleSoA t;
  for (std::size_t i = 0; i < n; ++i) {
    const float z = rng.uniform(-1, 1);
    t.push_back({-1.0f, -1.0f, z}, {1.0f, rng.uniform(-1, 1), rng.uniform(-1, 1)}, {rng.uniform(-1, 1), 1.0f, -z});
  }
  return t;
}

void expect_within_bounds(const KdTree& kd, std::size_t n, float factor, const std::string& what) {
  const KdStats s = compute_kd_stats(kd);
  const auto budget = static_cast<std::size_t>(std::ceil(double(factor) * double(n))) + 1;
  EXPECT_EQ(kd.reference_budget(), budget) << what;
  EXPECT_LE(s.references, budget) << what;
  EXPECT_LE(s.nodes, 2 * budget * std::size_t(kd.depth_bound()) + 1) << what;
  EXPECT_LE(s.max_leaf_depth, kd.depth_bound()) << what;
  EXPECT_LE(kd.depth_bound(), kKdMaxDepth) << what;
  EXPECT_EQ(kd.depth_bound(), kd_depth_bound(n, kd.options().max_depth)) << what;
  // Memory: nodes, plus one padded slot range per leaf of 36 bytes of vertices + 4 of index.
  const std::size_t slots = s.references + s.leaves * std::size_t(kd.block_width() - 1);
  EXPECT_LE(kd.leaf_prims().size(), slots) << what;
  EXPECT_LE(kd.memory_bytes(), 2 * (s.nodes * sizeof(KdNode) + slots * 40)) << what;
}

TEST(KdMemory, ReferencesNodesAndDepthStayBounded) {
  const std::size_t n = 1500;
  const TriangleSoA t = overlapping_triangles(n, 31);
  for (KdSplit split : {KdSplit::Sah, KdSplit::Middle, KdSplit::Median}) {
    for (float factor : {1.0f, 2.0f, 4.0f}) {
      KdBuildOptions o;
      o.split = split;
      o.reference_factor = factor;
      o.naive_leaf_size = 1;  // the naive splits would go on until the bounds stop them
      o.intersection_cost = 50.0f;  // and so would a SAH that finds intersections costly
      const KdTree kd(t, o);
      const std::string what = "split " + std::to_string(int(split)) + " factor " + std::to_string(factor);
      expect_within_bounds(kd, n, factor, what);
      if (split != KdSplit::Sah) {
        EXPECT_GT(kd.references(), n * factor / 2) << what << ": the budget should be what stops it";
      }
    }
  }
}

// Issue 7's memory bound, on the largest procedural scene lancer-bench measures (SPD
// rings-5, 633,602 triangles; bench_suite.h lists balls-3, gears-4, mount-7, rings-5 and
// tetra-8): at most kMaxBytesPerTriangle bytes of accelerator per input triangle, with
// every ISA's leaf layout (the widest blocks pad the most). The build's own bounds hold too.
// Today: 1.8 references per triangle at 40 bytes each (9 floats and an index), plus leaf
// padding to the block width and 8-byte nodes: 75 B (scalar, SSE4) to 84 B (AVX-512). The
// bound leaves a fifth on top of the widest; *Heavy (a 600,000-triangle build per ISA):
// not in the sanitizer run.
TEST(KdMemoryHeavy, BytesPerTriangleOnTheLargestBenchScene) {
  for (const auto& [name, size] : {std::pair{"balls", 3}, {"gears", 4}, {"mount", 7}, {"tetra", 8}})
    ASSERT_LT(spd_triangle_count(name, size), spd_triangle_count("rings", 5)) << name << " is larger";
  constexpr double kMaxBytesPerTriangle = 100.0;
  const TriangleSoA t = make_spd("rings", 5).triangles;
  for (Isa isa : supported_isas()) {
    const KdTree kd(t, {}, isa);
    const double per_triangle = double(kd.memory_bytes()) / double(t.size());
    EXPECT_LE(per_triangle, kMaxBytesPerTriangle) << isa_name(isa);
    expect_within_bounds(kd, t.size(), kd.options().reference_factor, std::string(isa_name(isa)));
  }
}

TEST(KdMemory, DepthBoundFormula) {
  EXPECT_EQ(kd_depth_bound(0, 0), 8);
  EXPECT_EQ(kd_depth_bound(1, 0), 8);
  EXPECT_EQ(kd_depth_bound(1024, 0), 21);              // 8 + 1.3 * 10
  EXPECT_EQ(kd_depth_bound(1u << 20, 0), 34);          // 8 + 1.3 * 20 = 34
  EXPECT_EQ(kd_depth_bound(std::size_t(1) << 28, 0), 44);  // round(8 + 36.4)
  EXPECT_EQ(kd_depth_bound(100, 5), 5);
  EXPECT_EQ(kd_depth_bound(100, 1000), kKdMaxDepth);
}

// A requested depth bound holds, and the tree still answers exactly.
TEST(KdMemory, ShallowDepthBoundStillExact) {
  const TriangleSoA t = random_soup(500, 32, {{-1, -1, -1}, {1, 1, 1}}, 0.3f);
  KdBuildOptions o;
  o.max_depth = 3;
  const KdTree kd(t, o);
  EXPECT_LE(compute_kd_stats(kd).max_leaf_depth, 3);
  OracleComparison cmp;
  compare_with_oracle(kd, t, RayKind::Aimed, 2000, 33, true, cmp);
  cmp.expect_no_mismatch("depth bound 3");
}

TEST(KdMemory, RejectsBadOptions) {
  const TriangleSoA t = random_soup(10, 34, {{-1, -1, -1}, {1, 1, 1}}, 0.3f);
  KdBuildOptions o;
  o.reference_factor = 0.5f;
  EXPECT_THROW(KdTree(t, o), std::invalid_argument);
  o = {};
  o.intersection_cost = -1.0f;
  EXPECT_THROW(KdTree(t, o), std::invalid_argument);
  o = {};
  o.max_depth = -2;
  EXPECT_THROW(KdTree(t, o), std::invalid_argument);
}

}  // namespace
}  // namespace lancer::test
