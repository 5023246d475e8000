// Node encoding, the invariants of the built arrays, and the statistics.
#include <bit>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_stats.h"
#include "accel/kd_tree.h"
#include "kd_test_support.h"
#include "scene/procedural.h"

namespace lancer::test {
namespace {

TEST(KdLayout, NodeEncodingRoundTrips) {
  static_assert(sizeof(KdNode) == 8);
  for (int axis = 0; axis < 3; ++axis) {
    const KdNode n = KdNode::inner(axis, -1.25e-7f, kKdMaxOffset);
    EXPECT_FALSE(n.is_leaf());
    EXPECT_EQ(n.axis(), axis);
    EXPECT_EQ(n.split(), -1.25e-7f);
    EXPECT_EQ(n.left_child(), kKdMaxOffset);
    EXPECT_EQ(n.right_child(), kKdMaxOffset + 1);
  }
  const KdNode l = KdNode::leaf(kKdMaxOffset, 0xFFFFFFFFu);
  EXPECT_TRUE(l.is_leaf());
  EXPECT_EQ(l.first_slot(), kKdMaxOffset);
  EXPECT_EQ(l.count(), 0xFFFFFFFFu);
  EXPECT_EQ(KdNode::inner(2, 1.0f, 7).relocated(5).left_child(), 12u);
  EXPECT_EQ(KdNode::leaf(3, 9).relocated(5).first_slot(), 8u);
  EXPECT_EQ(KdNode::leaf(3, 9).relocated(5).count(), 9u);
}

// Walks the tree: every node but the root is the child of exactly one inner node, splits
// lie strictly inside their cells, leaves start on a block boundary, hold ascending
// triangle indices, copies of the input vertices bit for bit, and NaN padding.
void check_invariants(const KdTree& kd, const TriangleSoA& t) {
  const auto& nodes = kd.nodes();
  std::vector<int> parents(nodes.size(), 0);
  std::vector<bool> referenced(t.size(), false);
  struct Item {
    std::uint32_t node;
    Bounds3 cell;
  };
  std::vector<Item> todo{{0, kd.bounds()}};
  while (!todo.empty()) {
    const Item it = todo.back();
    todo.pop_back();
    const KdNode& n = nodes[it.node];
    if (!n.is_leaf()) {
      ASSERT_LT(n.right_child(), nodes.size());
      ++parents[n.left_child()];
      ++parents[n.right_child()];
      EXPECT_LT(it.cell.lo[n.axis()], n.split());
      EXPECT_GT(it.cell.hi[n.axis()], n.split());
      Bounds3 l = it.cell, r = it.cell;
      l.hi[n.axis()] = n.split();
      r.lo[n.axis()] = n.split();
      todo.push_back({n.left_child(), l});
      todo.push_back({n.right_child(), r});
      continue;
    }
    const std::uint32_t w = static_cast<std::uint32_t>(kd.block_width());
    EXPECT_EQ(n.first_slot() % w, 0u);
    ASSERT_LE(n.first_slot() + n.count(), kd.leaf_prims().size());
    for (std::uint32_t i = 0; i < n.count(); ++i) {
      const std::uint32_t slot = n.first_slot() + i, tri = kd.leaf_prims()[slot];
      ASSERT_LT(tri, t.size());
      if (i > 0) {
        EXPECT_LT(kd.leaf_prims()[slot - 1], tri);
      }
      referenced[tri] = true;
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 v = kd.slot_vertex(slot, k);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(v.x), std::bit_cast<std::uint32_t>(t.x[k][tri]));
        EXPECT_EQ(std::bit_cast<std::uint32_t>(v.y), std::bit_cast<std::uint32_t>(t.y[k][tri]));
        EXPECT_EQ(std::bit_cast<std::uint32_t>(v.z), std::bit_cast<std::uint32_t>(t.z[k][tri]));
      }
    }
    for (std::uint32_t slot = n.first_slot() + n.count(); slot % w != 0; ++slot) {
      EXPECT_EQ(kd.leaf_prims()[slot], kNoHit);
      EXPECT_TRUE(std::isnan(kd.slot_vertex(slot, 0).x));
    }
  }
  EXPECT_EQ(parents[0], 0);
  for (std::size_t i = 1; i < nodes.size(); ++i) EXPECT_EQ(parents[i], 1) << "node " << i;
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_TRUE(referenced[i]) << "triangle " << i << " is in no leaf";
}

// For every split and every ISA's block width.
TEST(KdLayout, BuiltTreeInvariants) {
  Scene s = make_random_triangle_soup(3000, 41, {{-1, -1, -1}, {1, 1, 1}}, 0.2f);
  append_icosphere(s, {0.0f, 0.0f, 0.0f}, 0.5f, 3, 0);
  for (Isa isa : supported_isas())
    for (KdSplit split : {KdSplit::Sah, KdSplit::Middle, KdSplit::Median}) {
      KdBuildOptions o;
      o.split = split;
      const KdTree kd(s.triangles, o, isa);
      SCOPED_TRACE(std::string(isa_name(isa)));
      EXPECT_GT(kd.nodes().size(), 100u);
      check_invariants(kd, s.triangles);
    }
}

TEST(KdLayout, StatisticsAreConsistent) {
  const Scene s = make_random_triangle_soup(2000, 42, {{-1, -1, -1}, {1, 1, 1}}, 0.2f);
  // Fixed costs, not the tuned defaults: the bound on the SAH cost below compares the tree
  // with a single leaf, which only says much when a test costs no less than half a step.
  KdBuildOptions options;
  options.traversal_cost = 1.0f;
  options.intersection_cost = 0.5f;
  const KdTree kd(s.triangles, options);
  const KdStats st = compute_kd_stats(kd);
  EXPECT_EQ(st.triangles, 2000u);
  EXPECT_EQ(st.nodes, kd.nodes().size());
  EXPECT_EQ(st.inner_nodes + st.leaves, st.nodes);
  EXPECT_EQ(st.leaves, st.inner_nodes + 1);
  std::size_t refs = 0, empty = 0;
  for (const KdNode& n : kd.nodes())
    if (n.is_leaf()) refs += n.count(), empty += n.count() == 0;
  EXPECT_EQ(st.references, refs);
  EXPECT_EQ(st.empty_leaves, empty);
  EXPECT_GE(st.references, st.triangles);
  EXPECT_GT(st.max_leaf_depth, 5);
  EXPECT_LE(st.mean_leaf_depth, st.max_leaf_depth);
  EXPECT_NEAR(st.mean_triangles_per_leaf, double(refs) / double(st.leaves - empty), 1e-9);
  // The root alone costs C_trav; a single leaf would cost C_isect * N. A good tree is far
  // below that.
  EXPECT_GT(st.sah_cost, kd.options().traversal_cost);
  EXPECT_LT(st.sah_cost, 0.1 * kd.options().intersection_cost * 2000.0);
  EXPECT_GT(st.bytes_per_triangle, 8.0);
  EXPECT_GE(st.build_ms, 0.0);

  std::ostringstream os;
  print_kd_stats(os, st);
  EXPECT_NE(os.str().find("SAH cost"), std::string::npos);
  EXPECT_NE(os.str().find("empty leaves"), std::string::npos);
  EXPECT_NE(os.str().find("bytes / triangle"), std::string::npos);

  // A one-leaf tree costs exactly C_isect * N.
  TriangleSoA one;
  one.push_back({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const KdTree single(one);
  const KdStats st1 = compute_kd_stats(single);
  EXPECT_EQ(st1.nodes, 1u);
  EXPECT_DOUBLE_EQ(st1.sah_cost, single.options().intersection_cost);
}

// On a clustered scene the SAH tree has the lowest SAH cost of the three strategies.
TEST(KdLayout, SahTreeHasTheLowestSahCost) {
  Scene s;
  append_icosphere(s, {-5.0f, 0.0f, 0.0f}, 1.0f, 3, 0);
  append_icosphere(s, {5.0f, 3.0f, 0.0f}, 0.3f, 3, 0);
  append_uv_sphere(s, {0.0f, -4.0f, 2.0f}, 0.5f, 32, 16, 0);
  double cost[3];
  for (int i = 0; i < 3; ++i) {
    KdBuildOptions o;
    o.split = static_cast<KdSplit>(i);
    cost[i] = compute_kd_stats(KdTree(s.triangles, o)).sah_cost;
  }
  EXPECT_LT(cost[0], cost[1]);
  EXPECT_LT(cost[0], cost[2]);
}

}  // namespace
}  // namespace lancer::test
