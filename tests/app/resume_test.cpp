// `lancer render --resume FILE.exr`: a render continued from a shorter one's EXR ends with
// the same file, byte for byte, as the render done in one go, whatever the threads, trace
// mode or accelerator of either; anything that would change the image is refused with a
// message naming it, and so are files that cannot be resumed.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/cli.h"
#include "app/resume.h"
#include "render/checkpoint_file.h"
#include "render/camera.h"
#include "render/image_io.h"
#include "scene/load_scene.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

class Resume : public ::testing::Test {
 protected:
  struct Run {
    int code = -1;
    std::string out, err;
  };

  // `lancer render SCENE -o DIR/output --no-progress` plus `extra`, and `--width 24` unless
  // `extra` gives a width.
  Run render(const std::string& output, const std::vector<std::string>& extra,
             const std::string& scene = "cornell-box-spheres.gltf") const {
    std::vector<std::string> args = {"lancer", "render", (test::scenes_dir() / scene).string(), "-o",
                                     (dir_ / output).string(), "--no-progress"};
    if (std::find(extra.begin(), extra.end(), "--width") == extra.end()) args.insert(args.end(), {"--width", "24"});
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<const char*> argv;
    for (const std::string& a : args) argv.push_back(a.c_str());
    std::ostringstream o, e;
    Run r;
    r.code = run_cli(static_cast<int>(argv.size()), argv.data(), o, e);
    r.out = o.str(), r.err = e.str();
    return r;
  }

  std::string bytes(const std::string& name) const {
    std::ifstream in(dir_ / name, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // A 3-sample render to resume from.
  void make_checkpoint() const { ASSERT_EQ(render("short.exr", {"--spp", "3", "--seed", "7"}).code, 0); }

  // Expects `lancer render ... --resume short.exr` with `extra` to fail with exit 1 and a
  // message holding `says`.
  void expect_refused(const std::vector<std::string>& extra, const std::string& says,
                      const std::string& scene = "cornell-box-spheres.gltf") const {
    std::vector<std::string> args = {"--resume", path("short.exr")};
    if (std::find(extra.begin(), extra.end(), "--spp") == extra.end()) args.insert(args.end(), {"--spp", "6"});
    args.insert(args.end(), extra.begin(), extra.end());
    const Run r = render("resumed.exr", args, scene);
    std::string what = "resume with";
    for (const std::string& a : extra) what += " " + a;
    EXPECT_EQ(r.code, 1) << what << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << what << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "resumed.exr")) << what;
  }

  test::TempDir temp_{"lancer_resume"};
  const fs::path& dir_ = temp_.path();
};

TEST_F(Resume, ContinuesAShorterRenderToTheSameBytes) {
  ASSERT_EQ(render("straight.exr", {"--spp", "6", "--seed", "7", "--threads", "2"}).code, 0);
  make_checkpoint();
  const Run r = render("resumed.exr", {"--resume", path("short.exr"), "--spp", "6", "--seed", "7", "--threads", "1"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(bytes("resumed.exr"), bytes("straight.exr")) << "the whole file: picture, state and facts";
  // The picture of the PNG beside it too.
  ASSERT_EQ(render("resumed.png", {"--resume", path("short.exr"), "--spp", "6", "--seed", "7"}).code, 0);
  ASSERT_EQ(render("straight.png", {"--spp", "6", "--seed", "7"}).code, 0);
  EXPECT_EQ(bytes("resumed.png"), bytes("straight.png"));
}

// How rays are traced never changes the image, so it may change between the two runs.
TEST_F(Resume, TheWayRaysAreTracedMayDiffer) {
  ASSERT_EQ(render("straight.exr", {"--spp", "5", "--seed", "7"}).code, 0);
  make_checkpoint();
  const Run r = render("resumed.exr", {"--resume", path("short.exr"), "--spp", "5", "--seed", "7", "--mode", "single",
                                       "--accel", "brute", "--threads", "3", "--isa", "scalar"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(bytes("resumed.exr"), bytes("straight.exr"));
}

// A resume of a finished render, without --spp (on to the target the checkpoint's render was
// given) and writing over its own input, rewrites it as it was. (interrupt_test.cpp resumes
// an interrupted one.)
TEST_F(Resume, WithoutSppKeepsTheCheckpointsTarget) {
  make_checkpoint();
  const std::string before = bytes("short.exr");
  const Run r = render("short.exr", {"--resume", path("short.exr"), "--seed", "7"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(" 3 spp"), std::string::npos) << r.out;
  EXPECT_EQ(bytes("short.exr"), before);
}

TEST_F(Resume, RefusesAnotherRender) {
  make_checkpoint();
  expect_refused({}, "--seed 7, this render has --seed 0");  // the seed is not taken from the file
  expect_refused({"--seed", "8"}, "--seed 7, this render has --seed 8");
  expect_refused({"--seed", "7"}, "another scene", "cornell-box.gltf");
  expect_refused({"--seed", "7", "--width", "32"}, "--width 24, this render has --width 32");
  expect_refused({"--seed", "7", "--height", "20"}, "--height 24, this render has --height 20");
  expect_refused({"--seed", "7", "--integrator", "whitted"}, "--integrator path, this render has --integrator whitted");
  expect_refused({"--seed", "7", "--max-depth", "3"}, "--max-depth 8, this render has --max-depth 3");
  expect_refused({"--seed", "7", "--light-samples", "2"}, "--light-samples 1, this render has --light-samples 2");
  expect_refused({"--seed", "7", "--filter", "gaussian"}, "--filter box, this render has --filter gaussian");
  expect_refused({"--seed", "7", "--fov", "30"}, "another camera");
  expect_refused({"--seed", "7", "--aperture", "0.03", "--focus-distance", "0.6"}, "another camera");
  expect_refused({"--seed", "7", "--eye", "0.3,0.3,-0.7", "--look-at", "0.278,0.273,0.28"}, "another camera");
  expect_refused({"--seed", "7", "--env-color", "1,1,1"}, "another environment");
  expect_refused({"--seed", "7", "--frame-time", "0.5"}, "--frame-time none, this render has --frame-time 0x1p-1");
  expect_refused({"--seed", "7", "--spp", "2"}, "it already has 3 samples per pixel, more than --spp 2");
  expect_refused({"--seed", "7", "--integrator", "sppm"}, "the sppm integrator cannot resume");
}

// Every option that changes the image (the list of render_options_test.cpp) is either
// checked on resume or, for --spp, allowed to grow.
TEST_F(Resume, EveryOptionThatChangesTheImageIsChecked) {
  make_checkpoint();
  const std::vector<std::vector<std::string>> changes = {
      {"--seed", "5"}, {"--max-depth", "1"}, {"--light-samples", "2"}, {"--filter", "gaussian"},
      {"--aperture", "0.03", "--focus-distance", "0.6"}, {"--fov", "30"},
      {"--eye", "0.3,0.3,-0.7", "--look-at", "0.278,0.273,0.28"}, {"--env-color", "1,1,1"},
      {"--env-color", "1,1,1", "--env-scale", "3"}, {"--width", "25"}, {"--height", "23"},
      {"--integrator", "ao"}, {"--camera", "0"}, {"--shutter", "0,1"}};
  for (const auto& change : changes) {
    std::vector<std::string> args = {"--seed", "7"};
    args.insert(args.end(), change.begin(), change.end());
    if (change.front() == "--seed") args.erase(args.begin(), args.begin() + 2);
    const Run r = render("resumed.exr", [&] {
      std::vector<std::string> a = {"--resume", path("short.exr"), "--spp", "4"};
      a.insert(a.end(), args.begin(), args.end());
      return a;
    }());
    std::string what;
    for (const std::string& a : change) what += " " + a;
    if (change.front() == "--camera") {  // the scene's own camera, chosen by name: the same image
      EXPECT_EQ(r.code, 0) << what << ": " << r.err;
      continue;
    }
    EXPECT_EQ(r.code, 1) << what << " was not refused";
    EXPECT_NE(r.err.find("--resume"), std::string::npos) << what << ": " << r.err;
  }
}

// The caustic photon map is rebuilt the same from the same options, so the photon
// integrator resumes to the same bytes, and its own options are checked like the others.
TEST_F(Resume, ThePhotonIntegratorResumesAndItsOptionsAreChecked) {
  const std::vector<std::string> photon = {"--integrator", "photon", "--photons", "20000", "--seed", "7"};
  auto with = [&](std::vector<std::string> a, const std::vector<std::string>& more) {
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  ASSERT_EQ(render("straight.exr", with(photon, {"--spp", "4"})).code, 0);
  ASSERT_EQ(render("short.exr", with(photon, {"--spp", "2"})).code, 0);
  const Run r = render("resumed.exr", with(photon, {"--resume", path("short.exr"), "--spp", "4"}));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(bytes("resumed.exr"), bytes("straight.exr"));
  fs::remove(dir_ / "resumed.exr");  // the refusals below must not write one
  expect_refused({"--integrator", "photon", "--photons", "30000", "--seed", "7"}, "--photons");
  expect_refused(with(photon, {"--caustic-k", "10"}), "--caustic-k");
  expect_refused(with(photon, {"--caustic-radius", "0.01"}), "--caustic-radius");
}

// A checkpoint whose digest holds but whose spp fact is no number (a file written by hand)
// gets a message, not a bare parse error.
TEST_F(Resume, ADamagedSppFactIsNamed) {
  RenderState state;
  state.reset(24, 24);
  write_checkpoint(state, {{"spp", "abc"}, {"seed", "7"}}, dir_ / "hand.exr");
  const Run r = render("resumed.exr", {"--resume", path("hand.exr"), "--seed", "7"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("spp fact 'abc'"), std::string::npos) << r.err;
}

TEST_F(Resume, RefusesFilesItCannotResume) {
  // sppm writes a plain EXR; so do other programs.
  ASSERT_EQ(render("sppm.exr", {"--spp", "2", "--integrator", "sppm"}).code, 0);
  ExrExtras none;
  read_exr(path("sppm.exr"), none, "lancer.");
  EXPECT_TRUE(none.uint_channels.empty() && none.strings.empty() && none.ints.empty());
  Run r = render("resumed.exr", {"--resume", path("sppm.exr"), "--spp", "4"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("has no resume data"), std::string::npos) << r.err;

  ASSERT_EQ(render("short.png", {"--spp", "3"}).code, 0);
  r = render("resumed.exr", {"--resume", path("short.png"), "--spp", "4"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("short.png"), std::string::npos) << r.err;

  r = render("resumed.exr", {"--resume", path("missing.exr"), "--spp", "4"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("missing.exr"), std::string::npos) << r.err;

  // One character of the seed attribute changed: the digest no longer matches.
  make_checkpoint();
  std::string damaged = bytes("short.exr");
  const std::string key = std::string("lancer.seed") + '\0' + "string" + '\0';
  const std::size_t at = damaged.find(key);
  ASSERT_NE(at, std::string::npos);
  damaged[at + key.size() + 4] = '8';  // after the 4-byte size: the value "7"
  std::ofstream(dir_ / "short.exr", std::ios::binary | std::ios::trunc) << damaged;
  r = render("resumed.exr", {"--resume", path("short.exr"), "--spp", "4", "--seed", "8"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("damaged resume data"), std::string::npos) << r.err;
  // Cut short.
  std::ofstream(dir_ / "short.exr", std::ios::binary | std::ios::trunc) << damaged.substr(0, damaged.size() - 100);
  r = render("resumed.exr", {"--resume", path("short.exr"), "--spp", "4", "--seed", "7"});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("short.exr"), std::string::npos) << r.err;
}

// A checkpoint written before the emission seen directly had camera rays of its own
// (render/camera_emission.h), or with another count of them, holds samples of another
// estimator: refused, with a message that says what differs.
TEST(ResumeFacts, ACheckpointWithoutTheEmissionEstimateIsRefused) {
  Checkpoint old;
  old.facts = {{"seed", "7"}};
  const CheckpointFacts now = {{"seed", "7"}, {"emitterSamples", "4"}};
  try {
    check_resumable(old, now, "old.exr");
    ADD_FAILURE() << "resumed a checkpoint that does not record emitterSamples";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("camera rays per sample on visible lights"), std::string::npos) << e.what();
  }
  old.facts = {{"emitterSamples", "2"}, {"seed", "7"}};
  EXPECT_THROW(check_resumable(old, now, "old.exr"), std::invalid_argument);
  old.facts = {{"emitterSamples", "4"}, {"seed", "7"}};
  EXPECT_NO_THROW(check_resumable(old, now, "old.exr"));
}

// Nor one written before the path tracer traced light paths of its own
// (render/light_tracer.h): its samples counted the caustics seen directly at full weight.
TEST(ResumeFacts, ACheckpointWithoutLightTracedCausticsIsRefused) {
  RenderOptions options;
  options.scene = (test::scenes_dir() / "cornell-box-spheres.gltf").string();
  const Scene scene = load_scene(options.scene);
  RenderSettings settings;
  settings.width = settings.height = 16;
  const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), 16, 16);
  const CheckpointFacts now = render_facts(options, settings, scene, camera);
  const auto fact = std::find_if(now.begin(), now.end(), [](const auto& f) { return f.first == "lightTracedCaustics"; });
  ASSERT_NE(fact, now.end());
  EXPECT_EQ(fact->second, "1");
  Checkpoint old;
  for (const auto& f : now)
    if (f.first != "lightTracedCaustics") old.facts.push_back(f);
  try {
    check_resumable(old, now, "old.exr");
    ADD_FAILURE() << "resumed a checkpoint that does not record lightTracedCaustics";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("light-traced caustics"), std::string::npos) << e.what();
  }
  old.facts = now;
  EXPECT_NO_THROW(check_resumable(old, now, "old.exr"));
}

}  // namespace
}  // namespace lancer
