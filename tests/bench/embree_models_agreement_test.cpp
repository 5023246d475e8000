// Embree 3 as a second oracle on every mesh of ../shared/scenes/models, with the rays
// lancer-bench times (its camera, primary, diffuse and shadow sets) and the comparison it
// makes before timing: the same triangle at the same t, ties (another triangle at the same
// t: a shared edge or vertex) counted, and disagreements bounded. tests/accel's
// EmbreeOracle makes a stricter comparison (watertight Embree, grazing-angle bounds) on
// four of these meshes; this one covers them all, so lancer-bench's check cannot fail on
// any shared mesh. Skipped without Embree or without the meshes.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "accel/kd_tree.h"
#include "bench_checks.h"
#include "bench_suite.h"
#include "bench_trace.h"
#include "embree_tracer.h"
#include "render/ray_sets.h"
#include "test_paths.h"

namespace lancer::bench {
namespace {

namespace fs = std::filesystem;

// Image side of the ray sets: 4096 rays per set, every scene's silhouette well covered.
constexpr int kImage = 64;

std::vector<fs::path> model_files() {
  std::vector<fs::path> files;
  if (!fs::is_directory(test::models_dir())) return files;
  for (const fs::directory_entry& e : fs::directory_iterator(test::models_dir())) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (e.is_regular_file() && (ext == ".obj" || ext == ".gltf" || ext == ".glb")) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(EmbreeModelsAgreement, EveryModelEverySetAgreesUpToTies) {
  if (!embree_available()) GTEST_SKIP() << "built without Embree 3";
  const std::vector<fs::path> files = model_files();
  if (files.empty()) GTEST_SKIP() << test::models_dir() << " holds no meshes: the shared models are not installed";
  tbb::task_arena arena(1);
  std::size_t total_rays = 0, total_ties = 0;
  for (const fs::path& file : files) {
    SuiteScene entry;
    entry.name = file.stem().string();
    entry.file = file;
    const BenchScene bench = load_bench_scene(entry, kImage);
    const Isa isa = best_supported_isa();
    const KdTree kd(bench.scene.triangles, KdBuildOptions{}, isa);
    const EmbreeScene embree(bench.scene.triangles, isa, 1);
    for (RaySet set : {RaySet::Primary, RaySet::Diffuse, RaySet::Shadow}) {
      const std::vector<Ray> rays = make_ray_set(bench.scene, kd, bench.camera, set, 0);
      ASSERT_GT(rays.size(), std::size_t(kImage * kImage) / 20) << file << ": the camera misses the mesh";
      const bool occlusion = set == RaySet::Shadow;
      Answers lancer, theirs;
      trace_lancer(kd, Mode::Single, occlusion, rays, arena, lancer);
      trace_embree(embree, occlusion ? EmbreeCall::Occluded1 : EmbreeCall::Intersect1, rays, arena, theirs);
      embree.check_errors();
      const Agreement a = occlusion ? compare_occlusion(lancer.occluded, theirs.occluded)
                                    : compare_closest(rays, lancer.hits, theirs.hits, kd.max_extent_up());
      EXPECT_EQ(a.compared, rays.size());
      std::printf("[ info     ] %-16s %-7s %5zu rays, %zu ties, %zu disagreements\n", entry.name.c_str(),
                  std::string(ray_set_name(set)).c_str(), rays.size(), a.ties, a.disagreements);
      EXPECT_TRUE(a.acceptable()) << file << " " << ray_set_name(set) << ": " << a.disagreements << " of "
                                  << rays.size() << " rays disagree, first ray " << a.first_disagreement;
      EXPECT_LE(a.ties * 100, rays.size()) << file << " " << ray_set_name(set) << ": ties on over 1% of the rays";
      total_rays += rays.size();
      total_ties += a.ties;
    }
  }
  // Over all meshes, ties (rays through a shared edge or vertex) stay rare.
  EXPECT_LE(total_ties * 1000, total_rays) << total_ties << " ties in " << total_rays << " rays";
}

}  // namespace
}  // namespace lancer::bench
