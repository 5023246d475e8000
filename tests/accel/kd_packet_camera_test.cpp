// Packet traversal at scale: well over a million camera rays per ISA, traced in 8x8 pixel
// packets, must give the same closest hit (triangle and bit-identical t, u, v) as the
// single-ray traversal, and on the scenes small enough for it, as the brute-force oracle.
// Scenes: the built-in Cornell boxes, a procedural one, and the shared meshes when present
// (the test says which were absent). Runs per ISA (AllIsas/KdPacketCamera.<Test>/<isa>).
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "accel/brute_force.h"
#include "accel/kd_tree.h"
#include "kd_test_support.h"
#include "scene/load_scene.h"
#include "scene/procedural.h"
#include "test_paths.h"

namespace lancer::test {
namespace {

struct ViewReport {
  std::size_t rays = 0, hits = 0, oracle_checked = 0;
  std::string first_mismatch;  // empty when every ray agreed
};

// Every tile of one view: packet against single ray (every ray), and against the oracle
// when given. Tiles run in parallel; the first disagreement is kept for the message.
ViewReport check_view(const KdTree& kd, const BruteForce* oracle, const Pinhole& cam, int size) {
  const std::vector<std::vector<Ray>> tiles = camera_tiles(cam, size, size);
  std::atomic<std::size_t> hits{0}, checked{0};
  std::mutex mutex;
  ViewReport report;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles.size(), 8), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<Hit> packet(64);
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      const std::vector<Ray>& rays = tiles[t];
      kd.intersect_packet(rays.data(), packet.data(), static_cast<int>(rays.size()));
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit single = kd.intersect(rays[i]);
        const Hit expected = oracle ? oracle->intersect(rays[i]) : single;
        if (!same_hit(packet[i], single) || !same_hit(single, expected)) {
          std::lock_guard<std::mutex> lock(mutex);
          if (report.first_mismatch.empty()) {
            std::ostringstream s;
            s << "tile " << t << " lane " << i << ", " << describe(rays[i]) << ": packet prim " << packet[i].prim
              << " t " << packet[i].t << ", single-ray prim " << single.prim << " t " << single.t
              << (oracle ? ", oracle prim " : "") << (oracle ? std::to_string(expected.prim) : "");
            report.first_mismatch = s.str();
          }
        }
        hits += packet[i].valid() ? 1 : 0;
      }
      if (oracle) checked += rays.size();
    }
  });
  report.rays = tiles.size() * 64;
  report.hits = hits.load();
  report.oracle_checked = checked.load();
  return report;
}

class KdPacketCamera : public KdIsaTest {
 protected:
  // Two views of `tris` (outside, from the front-right and the back-left) at size x size.
  void check_scene(const std::string& name, const TriangleSoA& tris, int size, bool with_oracle) {
    const KdTree kd(tris, {}, isa());
    const BruteForce oracle(tris);
    const Bounds3 b = tris.bounds();
    const glm::vec3 c = b.center(), e = b.extent();
    const float reach = std::fmax(e.x, std::fmax(e.y, e.z));
    const Pinhole views[] = {
        Pinhole::looking_at(c + glm::vec3(0.3f, 0.4f, 1.6f) * reach, c, {0, 1, 0}, 40.0f, size),
        Pinhole::looking_at(c + glm::vec3(-0.9f, 0.2f, -0.7f) * reach, c, {0, 1, 0}, 55.0f, size),
    };
    for (const Pinhole& v : views) {
      const ViewReport r = check_view(kd, with_oracle ? &oracle : nullptr, v, size);
      ASSERT_TRUE(r.first_mismatch.empty()) << name << ": " << r.first_mismatch;
      EXPECT_GT(r.hits, r.rays / 20) << name << ": the view should see the scene";
      rays_ += r.rays;
      oracle_rays_ += r.oracle_checked;
    }
  }

  std::size_t rays_ = 0, oracle_rays_ = 0;
};

TEST_P(KdPacketCamera, OverAMillionRaysAgreeWithSingleRaysAndTheOracle) {
  check_scene("cornell-box", load_scene(scenes_dir() / "cornell-box.gltf").triangles, 512, true);
  if (HasFatalFailure()) return;
  check_scene("cornell-box-spheres", load_scene(scenes_dir() / "cornell-box-spheres.gltf").triangles, 192, true);
  if (HasFatalFailure()) return;
  Scene spheres;
  append_icosphere(spheres, {0.0f, 0.0f, 0.0f}, 1.0f, 3, 0);
  append_uv_sphere(spheres, {1.8f, 0.3f, -0.4f}, 0.7f, 32, 16, 0);
  append_box(spheres, {{-3.0f, -1.2f, -3.0f}, {3.0f, -1.0f, 3.0f}}, 0);
  // 320 x 320: with the Cornell boxes, over 800,000 rays checked against the oracle even
  // where the shared meshes are absent.
  check_scene("spheres", spheres.triangles, 320, true);
  if (HasFatalFailure()) return;

  std::vector<std::string> absent;
  for (const char* mesh : {"suzanne.obj", "stanford-bunny.obj", "ogre.obj"}) {
    const std::filesystem::path path = models_dir() / mesh;
    if (!std::filesystem::exists(path)) {
      absent.push_back(mesh);
      continue;
    }
    const bool small = std::string(mesh) == "suzanne.obj";  // the oracle only where it is quick
    check_scene(mesh, load_scene(path).triangles, small ? 192 : 448, small);
    if (HasFatalFailure()) return;
  }
  EXPECT_GE(oracle_rays_, std::size_t{800'000}) << "camera rays checked against the oracle";
  if (absent.empty()) {
    EXPECT_GE(rays_, std::size_t{1'500'000}) << "camera rays in all";
  } else {
    std::cout << "[ note     ] shared meshes absent (" << models_dir() << "):";
    for (const std::string& a : absent) std::cout << " " << a;
    std::cout << "\n";
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, KdPacketCamera, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
