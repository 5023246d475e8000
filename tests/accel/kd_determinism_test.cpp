// The kd-tree build gives bytewise identical arrays whatever the number of threads, and
// whether it runs as the lean one-thread build (KdBuildOptions::one_thread_below) or not.
#include <cstring>
#include <limits>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "accel/kd_tree.h"
#include "kd_test_support.h"
#include "scene/procedural.h"

namespace lancer::test {
namespace {

template <typename Vec>
bool same_bytes(const Vec& a, const Vec& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

void expect_identical(const KdTree& a, const KdTree& b, const std::string& what) {
  EXPECT_TRUE(same_bytes(a.nodes(), b.nodes())) << what << ": node arrays differ (" << a.nodes().size() << " vs "
                                                << b.nodes().size() << " nodes)";
  EXPECT_TRUE(same_bytes(a.leaf_prims(), b.leaf_prims())) << what << ": leaf index arrays differ";
  EXPECT_TRUE(same_bytes(a.blocks(), b.blocks())) << what << ": triangle blocks differ";
  EXPECT_EQ(a.references(), b.references()) << what;
}

// Large enough that the top levels split with parallel sweeps and build their subtrees as
// separate tasks (the parallel threshold is 4096 references).
TEST(KdDeterminism, SameTreeForOneAndSeveralThreads) {
  Scene s = make_random_triangle_soup(40000, 21, {{-4, -4, -4}, {4, 4, 4}}, 0.4f);
  append_icosphere(s, {0.0f, 0.0f, 0.0f}, 3.0f, 5, 0);  // 20480 triangles sharing edges
  // Axis-aligned quads in three stacks of planes: planar events on every axis, many refs
  // lying in one split plane, and cells that share their faces with triangles.
  for (int k = 0; k < 24; ++k) {
    const float c = -3.5f + 0.25f * float(k);
    append_quad(s, {c, -2, -2}, {c, 2, -2}, {c, 2, 2}, {c, -2, 2}, 0);
    append_quad(s, {-2, c, -2}, {2, c, -2}, {2, c, 2}, {-2, c, 2}, 0);
    append_box(s, {{c, c, c}, {c + 0.2f, c + 0.2f, c + 0.2f}}, 0);
  }
  const TriangleSoA& t = s.triangles;
  for (KdSplit split : {KdSplit::Sah, KdSplit::Middle, KdSplit::Median}) {
    KdBuildOptions o;
    o.split = split;
    o.one_thread_below = 0;  // never the lean build
    KdBuildOptions lean = o;
    lean.one_thread_below = std::numeric_limits<std::size_t>::max();
    tbb::task_arena one(1), several(4);
    std::unique_ptr<KdTree> a, b, c, d;
    one.execute([&] { a = std::make_unique<KdTree>(t, o); });
    several.execute([&] { b = std::make_unique<KdTree>(t, o); });
    c = std::make_unique<KdTree>(t, o);  // the default arena
    several.execute([&] { d = std::make_unique<KdTree>(t, lean); });
    ASSERT_GT(a->nodes().size(), 1000u);
    const std::string what = "split " + std::to_string(int(split));
    expect_identical(*a, *b, what + ", 1 vs 4 threads");
    expect_identical(*a, *c, what + ", 1 thread vs default arena");
    expect_identical(*a, *d, what + ", 1 thread vs the lean build");
  }
}

}  // namespace
}  // namespace lancer::test
