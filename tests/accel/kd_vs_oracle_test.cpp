// The kd-tree against the brute-force oracle: same triangle, bit-identical t, u, v and the
// same any-hit answer, for every ray kind, on soups and procedural scenes, for SAH, middle
// and median trees.
#include <cstdio>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "kd_test_support.h"
#include "scene/procedural.h"

namespace lancer::test {
namespace {

const KdSplit kAllSplits[] = {KdSplit::Sah, KdSplit::Middle, KdSplit::Median};

const char* split_name(KdSplit s) {
  switch (s) {
    case KdSplit::Sah: return "sah";
    case KdSplit::Middle: return "middle";
    case KdSplit::Median: return "median";
  }
  return "?";
}

const RayKind kAllKinds[] = {RayKind::Random,       RayKind::Aimed,          RayKind::Inside, RayKind::AxisParallel,
                             RayKind::InSplitPlane, RayKind::FromSplitPlane, RayKind::Segment};

// Every ray kind, `per_kind` rays each (plus secondary rays from the hits), all splits,
// with the traversal kernels of `isa`.
void compare_all(const TriangleSoA& tris, std::size_t per_kind, std::uint64_t seed, const std::string& scene, Isa isa) {
  std::size_t rays = 0, hits = 0;
  for (KdSplit split : kAllSplits) {
    KdBuildOptions o;
    o.split = split;
    const KdTree kd(tris, o, isa);
    for (RayKind kind : kAllKinds) {
      OracleComparison cmp;
      compare_with_oracle(kd, tris, kind, per_kind, seed + static_cast<std::uint64_t>(kind), true, cmp);
      cmp.expect_no_mismatch(scene + " / " + split_name(split) + " / " + ray_kind_name(kind));
      EXPECT_GT(cmp.hits.load(), 0u) << "the rays should hit something";
      rays += cmp.rays;
      hits += cmp.hits;
    }
  }
  std::printf("[ info     ] %s, %s: %zu rays compared with the oracle, %zu hits\n", scene.c_str(),
              std::string(isa_name(isa)).c_str(), rays, hits);
}

class KdVsOracle : public KdIsaTest {};

// Many rays on a small scene, where the oracle is cheap: about a million rays per ISA.
TEST_P(KdVsOracle, TinySoupManyRays) {
  const Scene s = make_random_triangle_soup(100, 10, {{-1, -1, -1}, {1, 1, 1}}, 0.8f);
  compare_all(s.triangles, 25000, 50 + isa_seed(), "soup 100", isa());
}

TEST_P(KdVsOracle, SmallRandomSoup) {
  const Scene s = make_random_triangle_soup(300, 11, {{-1, -1, -1}, {1, 1, 1}}, 0.6f);
  compare_all(s.triangles, 2000, 100 + isa_seed(), "soup 300", isa());
}

TEST_P(KdVsOracle, DenseRandomSoup) {
  const Scene s = make_random_triangle_soup(2000, 12, {{-1, -1, -1}, {1, 1, 1}}, 0.15f);
  compare_all(s.triangles, 800, 200 + isa_seed(), "soup 2000", isa());
}

TEST_P(KdVsOracle, SoupOfLargeStraddlingTriangles) {
  const Scene s = make_random_triangle_soup(400, 13, {{-1, -1, -1}, {1, 1, 1}}, 2.5f);
  compare_all(s.triangles, 1500, 300 + isa_seed(), "large-triangle soup", isa());
}

// Closed meshes with shared edges and vertices, and boxes that touch along whole faces:
// coincident triangles give exact ties in t that must go to the lower index.
TEST_P(KdVsOracle, SpheresAndTouchingBoxes) {
  Scene s;
  append_icosphere(s, {0.0f, 0.0f, 0.0f}, 1.0f, 3, 0);
  append_uv_sphere(s, {2.5f, 0.5f, 0.0f}, 0.75f, 24, 12, 0);
  append_box(s, {{-2.0f, -2.0f, -2.0f}, {-1.0f, -1.0f, -1.0f}}, 0);
  append_box(s, {{-1.0f, -2.0f, -2.0f}, {0.0f, -1.0f, -1.0f}}, 0);  // shares the face x = -1
  append_box(s, {{-2.0f, -1.0f, -2.0f}, {-1.0f, 0.0f, -1.0f}}, 0);  // shares the face y = -1
  append_box(s, {{-3.0f, -3.0f, -3.0f}, {3.0f, 3.0f, -2.0f}}, 0);   // floor touching the boxes
  compare_all(s.triangles, 1200, 400 + isa_seed(), "spheres and boxes", isa());
}

INSTANTIATE_TEST_SUITE_P(AllIsas, KdVsOracle, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
