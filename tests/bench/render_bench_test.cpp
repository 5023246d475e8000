// lancer bench --render: the ray recorder captures every ray a render traces and replays
// the same calls; the program end to end prints its table and JSON, refuses bad options,
// and reports a Cycles that cannot run instead of failing silently. (Speed itself is never
// asserted: these runs are tiny.)
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "accel/kd_tree.h"
#include "program_run.h"
#include "ray_recorder.h"
#include "render/renderer.h"
#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;
using bench::RecordedCall;
using bench::RecordingAccelerator;

RenderSettings tiny_path_settings(int threads) {
  RenderSettings s;
  s.width = s.height = 24;
  s.spp = 3;
  s.integrator = IntegratorKind::Path;
  s.max_depth = 16;
  s.threads = threads;
  return s;
}

// Every ray of a render passes through the recorder: as many recorded rays as the render
// counts, camera rays as packets, and the image is the same as without it.
TEST(RayRecorder, RecordsEveryRayTheRenderTraces) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  const KdTree kd(scene.triangles);
  for (const int threads : {1, 2}) {
    const RenderSettings s = tiny_path_settings(threads);
    const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), s.width, s.height);
    const RecordingAccelerator recorder(kd, 1u << 20);
    RenderStats recorded, plain;
    const ImageRGB a = render_image(scene, recorder, camera, s, recorded);
    const ImageRGB b = render_image(scene, kd, camera, s, plain);
    EXPECT_EQ(a.rgb, b.rgb);
    EXPECT_FALSE(recorder.truncated());
    const std::vector<RecordedCall> calls = recorder.calls();
    EXPECT_EQ(calls.size(), recorded.rays);
    std::uint64_t packet_rays = 0, any_packet_rays = 0, closest = 0, any = 0;
    bool in_any_packet = false;  // what the PacketRay records continue
    for (const RecordedCall& c : calls) {
      if (c.kind == RecordedCall::Kind::Packet || c.kind == RecordedCall::Kind::AnyPacket)
        in_any_packet = c.kind == RecordedCall::Kind::AnyPacket;
      const bool in_packet = c.kind == RecordedCall::Kind::Packet || c.kind == RecordedCall::Kind::AnyPacket ||
                             c.kind == RecordedCall::Kind::PacketRay;
      (in_any_packet ? any_packet_rays : packet_rays) += in_packet;
      closest += c.kind == RecordedCall::Kind::Closest;
      any += c.kind == RecordedCall::Kind::Any;
    }
    // Camera rays, the coherent continuation batches, and the emission estimate's camera
    // rays with the lattice that found its blocks (render/camera_emission.h: the light
    // shows in this image; a path render has no other setup rays).
    EXPECT_GT(recorded.path_batches.emission_rays, 0u);
    EXPECT_GT(recorded.setup_rays, 0u);
    EXPECT_EQ(packet_rays, recorded.primary_rays + recorded.path_batches.packet_rays +
                               recorded.path_batches.emission_rays + recorded.setup_rays);
    EXPECT_EQ(any_packet_rays, recorded.path_batches.shadow_packet_rays);
    EXPECT_GT(any_packet_rays, 0u);
    EXPECT_GT(closest, 0u);
    EXPECT_GT(any, 0u);
    // The replay makes the same calls: one per recorded ray, by kind.
    const bench::ReplayTime t = bench::replay(kd, calls, 1);
    EXPECT_EQ(t.packet_rays, packet_rays);
    EXPECT_EQ(t.any_packet_rays, any_packet_rays);
    EXPECT_EQ(t.closest, closest);
    EXPECT_EQ(t.any, any);
  }
}

TEST(RayRecorder, StopsRecordingAtItsLimit) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box.gltf");
  const KdTree kd(scene.triangles);
  const RenderSettings s = tiny_path_settings(2);
  const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), s.width, s.height);
  const RecordingAccelerator recorder(kd, 1000);
  RenderStats stats;
  render_image(scene, recorder, camera, s, stats);
  EXPECT_TRUE(recorder.truncated());
  EXPECT_LE(recorder.calls().size(), 1000u);
  EXPECT_GT(stats.rays, 1000u);
}

using Result = test::ProgramResult;
using test::file_text;

class RenderBenchProgram : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lancer_render_bench_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result bench(const std::string& args) const {
    return test::run_program(std::string(LANCER_BINARY) + " bench --render " + args, dir_);
  }

  std::string tiny() const {
    return "--scenes cornell-box,balls-1 --size 16 --spp 2 --reps 1 --threads 1 --trace-passes 1 --cache " +
           (dir_ / "cache").string();
  }

  fs::path dir_;
};

TEST_F(RenderBenchProgram, TinyRunPrintsTheTableAndJson) {
  const fs::path json = dir_ / "r.json";
  const Result r = bench(tiny() + " --cycles off --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| scene | triangles | Lancer s | paths/s | Mrays/s | rays/path | traversal share |"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("| cornell-box | 32 | "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| balls-1 | "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("Beside Blender Cycles"), std::string::npos) << "--cycles off, yet: " << r.out;
  const nlohmann::json j = nlohmann::json::parse(file_text(json));
  ASSERT_EQ(j["scenes"].size(), 2u);
  for (const auto& s : j["scenes"]) {
    EXPECT_GT(s["paths_per_s"].get<double>(), 0.0) << s;
    EXPECT_GT(s["rays_per_path"].get<double>(), 1.0) << s;  // camera rays and more
    const double share = s["traversal_share"].get<double>();
    EXPECT_GT(share, 0.0) << s;
    EXPECT_FALSE(s["replay"]["truncated"].get<bool>());
    EXPECT_GT(s["replay"]["closest"].get<std::uint64_t>(), 0u);
  }
}

TEST_F(RenderBenchProgram, BadOptionsExit2WithAMessage) {
  for (const char* args : {"--spp 0", "--max-depth 0", "--scenes no-such-scene --cycles off", "--cycles maybe"}) {
    const Result r = bench(std::string(args) + " --size 16");
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out << r.err;
    EXPECT_NE(r.err.find("lancer bench --render"), std::string::npos) << args << ": " << r.err;
  }
}

TEST_F(RenderBenchProgram, CyclesOnWithoutBlenderIsRefused) {
  const Result r = bench(tiny() + " --cycles on --blender /nonexistent/blender");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/blender cannot be run"), std::string::npos) << r.err;
}

// A Blender that runs but renders nothing (here `false`): the comparison fails with a
// message and exit status 1, and Lancer's own numbers are still printed.
TEST_F(RenderBenchProgram, AFailingCyclesIsReported) {
  const Result r = bench("--scenes cornell-box --size 16 --spp 2 --reps 1 --threads 1 --trace-passes 1 --cycles on "
                         "--blender false --reference lancer --reference-spp 4 --cache " +
                         (dir_ / "cache").string());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("Cycles failed on"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("| cornell-box | 32 | "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Cycles failed"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace lancer
