// The photon map's kd-tree (render/point_kd_tree.h): its k nearest neighbours are exactly
// those of a brute-force search under the same order (distance, then index), on random
// points, on points with many duplicates and on points that share coordinates (a plane, a
// line, one point repeated), with and without a filter; and the tree is balanced.
#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "render/point_kd_tree.h"

namespace lancer {
namespace {

using Neighbour = PointKdTree::Neighbour;

std::vector<Neighbour> brute_force(const std::vector<glm::vec3>& points, const glm::vec3& q, int k, float radius,
                                   std::uint32_t skip_mod) {
  std::vector<Neighbour> all;
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    if (skip_mod > 0 && i % skip_mod == 0) continue;
    const glm::vec3 d = points[i] - q;
    const float d2 = d.x * d.x + d.y * d.y + d.z * d.z;  // the tree's arithmetic, in its order
    if (d2 <= radius * radius) all.push_back({d2, i, 0});
  }
  std::sort(all.begin(), all.end(), [](const Neighbour& a, const Neighbour& b) { return a.before(b); });
  if (all.size() > static_cast<std::size_t>(k)) all.resize(static_cast<std::size_t>(k));
  return all;
}

// Queries the tree at `queries` and compares with brute force; skip_mod > 0 filters out
// every point whose index is a multiple of it.
void expect_brute_force(const std::vector<glm::vec3>& points, const std::vector<glm::vec3>& queries, int k,
                        float radius, std::uint32_t skip_mod = 0) {
  PointKdTree tree;
  tree.build(points);
  ASSERT_EQ(tree.size(), points.size());
  std::vector<Neighbour> heap(static_cast<std::size_t>(k));
  for (const glm::vec3& q : queries) {
    const int n = tree.nearest(q, k, radius, [&](std::uint32_t slot) {
      return skip_mod == 0 || tree.slot_index(slot) % skip_mod != 0;
    }, heap.data());
    // heap[0, n) is a max-heap: its root is the farthest.
    for (int i = 1; i < n; ++i) ASSERT_FALSE(heap[0].before(heap[i]));
    std::vector<Neighbour> got(heap.begin(), heap.begin() + n);
    for (const Neighbour& g : got) {
      ASSERT_EQ(tree.slot_index(g.slot), g.index);
      ASSERT_EQ(tree.slot_point(g.slot), points[g.index]);
    }
    std::sort(got.begin(), got.end(), [](const Neighbour& a, const Neighbour& b) { return a.before(b); });
    const std::vector<Neighbour> want = brute_force(points, q, k, radius, skip_mod);
    ASSERT_EQ(got.size(), want.size()) << "k " << k << " radius " << radius;
    for (std::size_t i = 0; i < want.size(); ++i) {
      ASSERT_EQ(got[i].index, want[i].index) << "neighbour " << i << " of k " << k << " radius " << radius;
      ASSERT_EQ(got[i].d2, want[i].d2);
    }
  }
}

std::vector<glm::vec3> random_points(std::mt19937& rng, int n, float lo, float hi) {
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<glm::vec3> p(static_cast<std::size_t>(n));
  for (glm::vec3& v : p) v = glm::vec3(u(rng), u(rng), u(rng));
  return p;
}

TEST(PointKdTree, NearestAreThoseOfBruteForceOnRandomPoints) {
  std::mt19937 rng(7);
  for (int n : {1, 2, 3, 7, 100, 1000, 5000}) {
    const std::vector<glm::vec3> points = random_points(rng, n, -1.0f, 1.0f);
    const std::vector<glm::vec3> queries = random_points(rng, 200, -1.2f, 1.2f);
    for (int k : {1, 2, 5, 50})
      for (float radius : {0.05f, 0.3f, 10.0f}) expect_brute_force(points, queries, k, radius);
  }
}

TEST(PointKdTree, NearestWithAFilter) {
  std::mt19937 rng(11);
  const std::vector<glm::vec3> points = random_points(rng, 3000, 0.0f, 1.0f);
  const std::vector<glm::vec3> queries = random_points(rng, 200, 0.0f, 1.0f);
  for (int k : {3, 40}) expect_brute_force(points, queries, k, 0.2f, 3);
}

// Points on a coarse grid, each repeated: many equal distances, decided by index.
TEST(PointKdTree, DuplicatesAndTiesAreBrokenByIndex) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> cell(0, 4);
  std::vector<glm::vec3> points;
  for (int i = 0; i < 2000; ++i) points.emplace_back(float(cell(rng)), float(cell(rng)), float(cell(rng)));
  std::vector<glm::vec3> queries = {glm::vec3(2.0f), glm::vec3(0.0f), glm::vec3(2.5f, 2.0f, 1.0f)};
  for (const glm::vec3& q : random_points(rng, 50, 0.0f, 4.0f)) queries.push_back(q);
  for (int k : {1, 7, 16, 100}) {
    expect_brute_force(points, queries, k, 1.0f);
    expect_brute_force(points, queries, k, 100.0f);
  }
}

TEST(PointKdTree, DegenerateCoordinates) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<glm::vec3> plane, line, same(500, glm::vec3(0.25f, -1.0f, 3.0f));
  for (int i = 0; i < 1000; ++i) {
    plane.emplace_back(u(rng), 0.5f, u(rng));
    line.emplace_back(1.0f, u(rng), 2.0f);
  }
  const std::vector<glm::vec3> queries = random_points(rng, 100, -0.5f, 1.5f);
  for (int k : {1, 10, 60}) {
    expect_brute_force(plane, queries, k, 0.2f);
    expect_brute_force(line, queries, k, 2.0f);
    expect_brute_force(same, {glm::vec3(0.25f, -1.0f, 3.0f), glm::vec3(0.0f)}, k, 100.0f);
    expect_brute_force(same, {glm::vec3(0.25f, -1.0f, 3.0f)}, k, 0.0f);  // radius 0: the point itself
  }
}

TEST(PointKdTree, EmptyTreeAndRebuild) {
  PointKdTree tree;
  Neighbour heap[4];
  EXPECT_EQ(tree.nearest(glm::vec3(0.0f), 4, 1.0f, [](std::uint32_t) { return true; }, heap), 0);
  std::mt19937 rng(1);
  tree.build(random_points(rng, 100, 0.0f, 1.0f));
  tree.build({});
  EXPECT_TRUE(tree.empty());
  EXPECT_EQ(tree.nearest(glm::vec3(0.0f), 4, 1.0f, [](std::uint32_t) { return true; }, heap), 0);
}

// The implicit layout: the middle slot of every subtree splits it, the points before it on
// one side of its plane and those after it on the other (so the tree is balanced).
TEST(PointKdTree, SubtreesAreMedianSplits) {
  std::mt19937 rng(9);
  const std::vector<glm::vec3> points = random_points(rng, 4097, 0.0f, 1.0f);
  PointKdTree tree;
  tree.build(points);
  struct Range {
    std::uint32_t lo, hi;
  };
  std::vector<Range> todo = {{0, static_cast<std::uint32_t>(tree.size())}};
  int checked = 0;
  while (!todo.empty()) {
    const Range r = todo.back();
    todo.pop_back();
    if (r.hi - r.lo < 2) continue;
    const std::uint32_t mid = r.lo + (r.hi - r.lo) / 2;
    const glm::vec3 split = tree.slot_point(mid);
    // Some axis separates the halves (the tree's own axis is private: any of the three).
    bool separated = false;
    for (int axis = 0; axis < 3 && !separated; ++axis) {
      bool ok = true;
      for (std::uint32_t i = r.lo; i < mid && ok; ++i) ok = tree.slot_point(i)[axis] <= split[axis];
      for (std::uint32_t i = mid + 1; i < r.hi && ok; ++i) ok = tree.slot_point(i)[axis] >= split[axis];
      separated = ok;
    }
    ASSERT_TRUE(separated) << "slots " << r.lo << ".." << r.hi;
    ++checked;
    todo.push_back({r.lo, mid});
    todo.push_back({mid + 1, r.hi});
  }
  EXPECT_GT(checked, 2000);
}

}  // namespace
}  // namespace lancer
