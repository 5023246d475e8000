// Pieces of the build: perfect-split clipping, the SAH sweep, splitting decisions.
#include <gtest/gtest.h>

#include "accel/kd_build_clip.h"
#include "accel/kd_build_events.h"
#include "accel/kd_tree.h"

namespace lancer::kd {
namespace {

TEST(KdClip, TriangleInsideTheCellKeepsItsBounds) {
  TriangleSoA t;
  t.push_back({0.1f, 0.2f, 0.3f}, {0.9f, 0.2f, 0.3f}, {0.5f, 0.8f, 0.6f});
  const Bounds3 b = clipped_triangle_bounds(t, 0, {{0, 0, 0}, {1, 1, 1}});
  EXPECT_EQ(b.lo, glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(b.hi, glm::vec3(0.9f, 0.8f, 0.6f));
}

// The triangle (0,0,0) (2,0,0) (0,2,0) clipped to the cell y >= 1.5: only its corner near
// (0, 2) remains, so x shrinks to [0, 0.5] where the triangle's box clamped to the cell
// would give [0, 1].
TEST(KdClip, PerfectSplitShrinksTheOtherAxes) {
  TriangleSoA t;
  t.push_back({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const Bounds3 b = clipped_triangle_bounds(t, 0, {{0.0f, 1.5f, -1.0f}, {1.0f, 3.0f, 1.0f}});
  EXPECT_EQ(b.lo.x, 0.0f);
  EXPECT_NEAR(b.hi.x, 0.5f, 1e-6f);
  EXPECT_GE(b.hi.x, 0.5f) << "conservative: rounded outward";
  EXPECT_EQ(b.lo.y, 1.5f);
  EXPECT_EQ(b.hi.y, 2.0f);
  EXPECT_EQ(b.lo.z, 0.0f);
  EXPECT_EQ(b.hi.z, 0.0f) << "planar stays planar";
}

TEST(KdClip, TriangleMissingTheCellIsEmpty) {
  TriangleSoA t;
  t.push_back({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  // The triangle's box overlaps the cell near (1.5, 1.5), but the triangle (x + y <= 2) does not.
  EXPECT_TRUE(clipped_triangle_bounds(t, 0, {{1.2f, 1.2f, -1.0f}, {2.0f, 2.0f, 1.0f}}).empty());
  // Touching at one point counts as meeting.
  EXPECT_FALSE(clipped_triangle_bounds(t, 0, {{1.0f, 1.0f, -1.0f}, {2.0f, 2.0f, 1.0f}}).empty());
}

TEST(KdClip, FlatCellKeepsTrianglesInItsPlane) {
  TriangleSoA t;
  t.push_back({0, 0, 0.5f}, {1, 0, 0.5f}, {0, 1, 0.5f});
  const Bounds3 b = clipped_triangle_bounds(t, 0, {{0.25f, 0.0f, 0.5f}, {1.0f, 1.0f, 0.5f}});
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(b.lo.x, 0.25f);
  EXPECT_EQ(b.lo.z, 0.5f);
  EXPECT_EQ(b.hi.z, 0.5f);
}

RefVector refs_of(const std::vector<Bounds3>& boxes) {
  RefVector refs;
  for (std::size_t i = 0; i < boxes.size(); ++i) refs.push_back({static_cast<std::uint32_t>(i), boxes[i]});
  return refs;
}

// Two clusters far apart on x: the best plane separates them, in the empty gap.
TEST(KdSweep, SeparatesTwoClusters) {
  std::vector<Bounds3> boxes;
  for (int i = 0; i < 10; ++i) boxes.push_back({{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}});
  for (int i = 0; i < 10; ++i) boxes.push_back({{9.0f, 0.0f, 0.0f}, {10.0f, 1.0f, 1.0f}});
  const auto refs = refs_of(boxes);
  const EventLists ev = make_sorted_events(refs);
  const Bounds3 cell{{0, 0, 0}, {10, 1, 1}};
  const SplitChoice c = find_sah_split(ev, refs.size(), cell, {1.0, 1.5, 0.8}, false);
  ASSERT_TRUE(c.found);
  EXPECT_EQ(c.axis, 0);
  EXPECT_TRUE(c.pos == 1.0f || c.pos == 9.0f) << c.pos;
  EXPECT_LT(c.cost, 1.5 * 20);
}

// Events at one position sort end, planar, start; the sweep never proposes a plane on
// the cell boundary, and a cell with no extent on an axis is not swept on it.
TEST(KdSweep, EventOrderAndBoundaryPlanes) {
  std::vector<Bounds3> boxes = {{{0, 0, 0}, {1, 1, 0}}, {{1, 0, 0}, {2, 1, 0}}, {{1, 0, 0}, {1, 1, 0}}};
  const auto refs = refs_of(boxes);
  const EventLists ev = make_sorted_events(refs);
  ASSERT_EQ(ev.axis[0].size(), 5u);
  EXPECT_EQ(ev.axis[0][1].pos, 1.0f);
  EXPECT_EQ(ev.axis[0][1].type(), kEnd);
  EXPECT_EQ(ev.axis[0][2].type(), kPlanar);
  EXPECT_EQ(ev.axis[0][3].type(), kStart);
  EXPECT_EQ(ev.axis[2].size(), 3u);  // all planar on z
  const SplitChoice c = find_sah_split(ev, refs.size(), {{0, 0, 0}, {2, 1, 0}}, {1.0, 1.5, 0.8}, false);
  if (c.found) {
    EXPECT_NE(c.axis, 2);
    EXPECT_GT(c.pos, 0.0f);
    EXPECT_LT(c.pos, c.axis == 0 ? 2.0f : 1.0f);
  }
}

// Two small triangles at opposite corners of a large cell: when intersections are dear
// the SAH cuts the empty space away (with the empty-space bonus) rather than keep one leaf;
// when they are cheap (leaf cost 2 * 0.5 = 1 = C_trav) no split can pay for itself.
TEST(KdSweep, CutsEmptySpaceOnlyWhenItPays) {
  TriangleSoA t;
  t.push_back({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  t.push_back({9, 9, 9}, {9.01f, 9, 9}, {9, 9.01f, 9});
  KdBuildOptions o;
  o.traversal_cost = 1.0f;
  o.intersection_cost = 4.0f;
  EXPECT_GT(KdTree(t, o).nodes().size(), 3u);
  o.intersection_cost = 0.5f;
  EXPECT_EQ(KdTree(t, o).nodes().size(), 1u);
}

// The default intersection cost is the one measured for the tree's ISA (kd_build_cost.h):
// each ISA's tree is built for its own leaf kernels. build_kd_tree itself refuses 0.
TEST(KdCost, DefaultIntersectionCostFollowsTheIsa) {
  TriangleSoA t;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      const float x = float(i), y = float(j), z = float((i * 7 + j * 13) % 5);
      t.push_back({x, y, z}, {x + 0.9f, y, z}, {x, y + 0.9f, z + 0.5f});
    }
  for (Isa isa : supported_isas()) {
    SCOPED_TRACE(std::string(isa_name(isa)));
    const KdTree automatic(t, {}, isa);
    EXPECT_EQ(automatic.options().intersection_cost, kd_intersection_cost(isa));
    KdBuildOptions o;
    o.intersection_cost = kd_intersection_cost(isa);
    EXPECT_EQ(KdTree(t, o, isa).nodes().size(), automatic.nodes().size());
    o.intersection_cost = 0.5f;  // an explicit cost is kept
    const KdTree explicit_cost(t, o, isa);
    EXPECT_EQ(explicit_cost.options().intersection_cost, 0.5f);
    EXPECT_NE(explicit_cost.nodes().size(), automatic.nodes().size());
  }
  EXPECT_LT(kd_intersection_cost(Isa::Avx512), kd_intersection_cost(Isa::Avx2));
  EXPECT_THROW(build_kd_tree(t, KdBuildOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace lancer::kd
