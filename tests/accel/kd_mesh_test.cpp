// The kd-tree against the oracle on the real meshes in models_dir() (skipped when absent).
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "accel/kd_stats.h"
#include "accel/kd_tree.h"
#include "kd_test_support.h"
#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer::test {
namespace {

// The oracle costs O(N) per ray, so the ray counts shrink as the meshes grow.
void compare_on_mesh(const char* file, std::initializer_list<KdSplit> splits, std::size_t per_kind, Isa isa) {
  const std::filesystem::path path = models_dir() / file;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent: the shared meshes are not installed";
  const Scene scene = load_scene(path);
  const TriangleSoA& t = scene.triangles;
  ASSERT_GT(t.size(), 0u);
  for (KdSplit split : splits) {
    KdBuildOptions o;
    o.split = split;
    const KdTree kd(t, o, isa);
    const KdStats st = compute_kd_stats(kd);
    std::printf("[ info     ] %s split %d: %zu triangles, %zu nodes, %.2f refs/tri, SAH cost %.2f, %.1f ms\n", file,
                int(split), st.triangles, st.nodes, double(st.references) / double(st.triangles), st.sah_cost,
                st.build_ms);
    for (RayKind kind : {RayKind::Aimed, RayKind::Inside, RayKind::AxisParallel, RayKind::InSplitPlane,
                         RayKind::FromSplitPlane, RayKind::Random}) {
      OracleComparison cmp;
      const std::uint64_t seed = 500 + 0x10001ull * std::uint64_t(isa) + std::uint64_t(kind);
      compare_with_oracle(kd, t, kind, per_kind, seed, true, cmp);
      cmp.expect_no_mismatch(std::string(file) + " / " + std::string(isa_name(isa)) + " / split " +
                             std::to_string(int(split)) + " / " + ray_kind_name(kind));
    }
  }
}

class KdMesh : public KdIsaTest {};

TEST_P(KdMesh, StanfordBunny) { compare_on_mesh("stanford-bunny.obj", {KdSplit::Sah}, 80, isa()); }

// A CAD model with flat faces, sharp edges and many vertices on common coordinates.
TEST_P(KdMesh, Fandisk) {
  compare_on_mesh("fandisk.obj", {KdSplit::Sah, KdSplit::Middle, KdSplit::Median}, 60, isa());
}

TEST_P(KdMesh, Teapot) { compare_on_mesh("teapot.obj", {KdSplit::Sah, KdSplit::Median}, 120, isa()); }

INSTANTIATE_TEST_SUITE_P(AllIsas, KdMesh, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
