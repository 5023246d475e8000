// The top-level kd-tree over boxes (top_level_tree.h): structure, degenerate inputs,
// determinism, and that every point of every box lies in a leaf that lists the box.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "accel/top_level_tree.h"
#include "kd_test_support.h"

namespace lancer::test {
namespace {

std::vector<Bounds3> random_boxes(std::size_t n, std::uint64_t seed, float world, float max_size, bool flat_z = false) {
  TestRng rng(seed);
  std::vector<Bounds3> boxes;
  for (std::size_t i = 0; i < n; ++i) {
    const float z = flat_z ? 0.0f : rng.uniform(-world, world);
    const glm::vec3 lo(rng.uniform(-world, world), rng.uniform(-world, world), z);
    const float depth = flat_z ? 0.0f : rng.uniform(0.0f, max_size);
    const glm::vec3 size(rng.uniform(0.0f, max_size), rng.uniform(0.0f, max_size), depth);
    boxes.push_back({lo, lo + size});
  }
  return boxes;
}

// Leaves whose closed cell holds p (both sides where p lies on a plane).
void leaves_at(const TopLevelTree& t, std::uint32_t node, const glm::vec3& p, std::vector<std::uint32_t>& out) {
  const KdNode n = t.nodes()[node];
  if (n.is_leaf()) return out.push_back(node);
  if (p[n.axis()] <= n.split()) leaves_at(t, n.left_child(), p, out);
  if (p[n.axis()] >= n.split()) leaves_at(t, n.right_child(), p, out);
}

bool listed(const TopLevelTree& t, std::uint32_t leaf, std::uint32_t box) {
  const KdNode n = t.nodes()[leaf];
  const auto first = t.items().begin() + n.first_slot();
  return std::binary_search(first, first + n.count(), box);
}

// The layout's invariants, and that corners, centres and random points of each of the
// first `checked` boxes (all by default) lie in some leaf listing the box.
void check_tree(const TopLevelTree& t, const std::vector<Bounds3>& boxes, std::uint64_t seed,
                std::size_t checked = std::size_t(-1)) {
  ASSERT_FALSE(t.nodes().empty());
  for (const KdNode& n : t.nodes()) {
    if (!n.is_leaf()) {
      ASSERT_LT(n.right_child(), t.nodes().size());
      continue;
    }
    ASSERT_LE(std::size_t(n.first_slot()) + n.count(), t.items().size());
    const auto first = t.items().begin() + n.first_slot();
    ASSERT_TRUE(std::is_sorted(first, first + n.count()));
    ASSERT_EQ(std::adjacent_find(first, first + n.count()), first + n.count());
    for (std::uint32_t k = 0; k < n.count(); ++k) ASSERT_LT(first[k], boxes.size());
  }
  TestRng rng(seed);
  for (std::uint32_t i = 0; i < std::min(checked, boxes.size()); ++i) {
    const Bounds3& b = boxes[i];
    for (int k = 0; k < 10; ++k) {
      glm::vec3 p = k < 8 ? glm::vec3((k & 1 ? b.hi : b.lo).x, (k & 2 ? b.hi : b.lo).y, (k & 4 ? b.hi : b.lo).z)
                          : (k == 8 ? b.center() : rng.in_box(b));
      std::vector<std::uint32_t> leaves;
      leaves_at(t, 0, p, leaves);
      bool found = false;
      for (std::uint32_t l : leaves) found = found || listed(t, l, i);
      ASSERT_TRUE(found) << "box " << i << " is missing at point " << k;
    }
  }
}

int depth(const TopLevelTree& t, std::uint32_t node) {
  const KdNode n = t.nodes()[node];
  return n.is_leaf() ? 0 : 1 + std::max(depth(t, n.left_child()), depth(t, n.right_child()));
}

TEST(TopLevelTree, NoBoxesOneBoxAndEqualBoxes) {
  const TopLevelTree none(std::vector<Bounds3>{});
  ASSERT_EQ(none.nodes().size(), 1u);
  EXPECT_TRUE(none.nodes()[0].is_leaf());
  EXPECT_EQ(none.nodes()[0].count(), 0u);
  EXPECT_TRUE(none.bounds().empty());

  const std::vector<Bounds3> one{{{0, 0, 0}, {1, 2, 3}}};
  const TopLevelTree single(one);
  ASSERT_EQ(single.nodes().size(), 1u);
  EXPECT_EQ(single.items(), std::vector<std::uint32_t>{0});

  const std::vector<Bounds3> equal(100, Bounds3{{0, 0, 0}, {1, 1, 1}});
  const TopLevelTree same(equal);
  ASSERT_EQ(same.nodes().size(), 1u) << "no plane inside the cell can separate equal boxes";
  EXPECT_EQ(same.items().size(), 100u);
}

TEST(TopLevelTree, RandomBoxesAreAllReachable) {
  const std::vector<Bounds3> boxes = random_boxes(3000, 1, 10.0f, 1.0f);
  const TopLevelTree t(boxes);
  check_tree(t, boxes, 2);
  EXPECT_GT(t.nodes().size(), 100u);
  EXPECT_LE(depth(t, 0), t.depth_bound());
  EXPECT_LT(t.items().size(), 4 * boxes.size()) << "straddling boxes should not multiply without bound";
}

TEST(TopLevelTree, FlatBoxesPointsAndOverlaps) {
  const std::vector<Bounds3> flat = random_boxes(1000, 3, 10.0f, 1.0f, /*flat_z=*/true);
  const TopLevelTree t_flat(flat);
  check_tree(t_flat, flat, 4);
  EXPECT_GT(t_flat.nodes().size(), 10u) << "a flat scene still splits";

  std::vector<Bounds3> points = random_boxes(500, 5, 10.0f, 0.0f);
  const TopLevelTree t_points(points);
  check_tree(t_points, points, 6);
  EXPECT_GT(t_points.nodes().size(), 10u);

  // Large boxes overlapping many small ones, and a line of boxes along x.
  std::vector<Bounds3> mixed = random_boxes(800, 7, 10.0f, 0.5f);
  for (int i = 0; i < 20; ++i) mixed.push_back(random_boxes(1, 100 + i, 10.0f, 12.0f)[0]);
  for (int i = 0; i < 50; ++i) mixed.push_back({{float(i), 0, 0}, {float(i) + 0.5f, 0, 0}});
  const TopLevelTree t_mixed(mixed);
  check_tree(t_mixed, mixed, 8);
}

TEST(TopLevelTree, NonFiniteAndEmptyBoxesAreLeftOut) {
  std::vector<Bounds3> boxes = random_boxes(50, 9, 5.0f, 1.0f);
  boxes.push_back({{std::numeric_limits<float>::quiet_NaN(), 0, 0}, {1, 1, 1}});
  boxes.push_back({{0, 0, 0}, {kInfinity, 1, 1}});
  boxes.push_back(Bounds3{});  // empty
  const TopLevelTree t(boxes);
  for (std::uint32_t i : t.items()) EXPECT_LT(i, 50u) << "only the 50 finite boxes are listed";
  check_tree(t, boxes, 10, 50);
}

TEST(TopLevelTree, SameTreeEveryBuild) {
  const std::vector<Bounds3> boxes = random_boxes(2000, 11, 10.0f, 2.0f);
  const TopLevelTree a(boxes), b(boxes);
  ASSERT_EQ(a.nodes().size(), b.nodes().size());
  EXPECT_EQ(std::memcmp(a.nodes().data(), b.nodes().data(), a.nodes().size() * sizeof(KdNode)), 0);
  EXPECT_EQ(a.items(), b.items());
}

// 100,000 boxes (the upper size) build with the O(N log N) sweep; the check covers
// a sample of them.
TEST(TopLevelTree, HundredThousandBoxes) {
  const std::vector<Bounds3> boxes = random_boxes(100000, 12, 100.0f, 1.0f);
  const TopLevelTree t(boxes);
  EXPECT_LE(depth(t, 0), t.depth_bound());
  EXPECT_LT(t.items().size(), 4 * boxes.size());
  check_tree(t, boxes, 13, 2000);
}

}  // namespace
}  // namespace lancer::test
