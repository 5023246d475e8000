// Every render option either changes the image or is refused, for every integrator: no
// option is silently ignored. And the options that choose how rays are traced (mode,
// threads, accelerator, ISA) never change a bit of it.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/cli.h"
#include "render/image_io.h"
#include "simd/isa.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

const char* const kIntegrators[] = {"path", "sppm", "photon", "whitted", "normals", "albedo", "depth", "ao", "primid"};

class RenderOptions : public ::testing::Test {
 protected:
  struct Run {
    int code = -1;
    std::string err;
    ImageRGB image;
  };

  // `lancer render` of the mirror/glass Cornell box (or `scene` of scenes/), 24x24, 2 spp,
  // plus `extra`.
  Run render(const std::string& integrator, const std::vector<std::string>& extra,
             const std::string& scene = "cornell-box-spheres.gltf") const {
    const fs::path out = dir_ / "image.exr";
    fs::remove(out);
    std::vector<std::string> args = {"lancer", "render", (test::scenes_dir() / scene).string(),
                                     "-o", out.string(), "--width", "24", "--no-progress", "--integrator", integrator};
    if (std::find(extra.begin(), extra.end(), "--spp") == extra.end()) args.insert(args.end(), {"--spp", "2"});
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<const char*> argv;
    for (const std::string& a : args) argv.push_back(a.c_str());
    std::ostringstream o, e;
    Run r;
    r.code = run_cli(static_cast<int>(argv.size()), argv.data(), o, e);
    r.err = e.str();
    if (r.code == 0) r.image = read_image(out);
    return r;
  }

  test::TempDir temp_{"lancer_render_options"};
  const fs::path& dir_ = temp_.path();
};

bool same(const ImageRGB& a, const ImageRGB& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

TEST_F(RenderOptions, EveryOptionChangesTheImageOrIsRefused) {
  const std::vector<std::vector<std::string>> changes = {
      {"--spp", "3"},          {"--seed", "5"},         {"--max-depth", "1"},       {"--light-samples", "2"},
      {"--filter", "gaussian"}, {"--aperture", "0.03", "--focus-distance", "0.6"}, {"--fov", "30"},
      {"--eye", "0.3,0.3,-0.7", "--look-at", "0.278,0.273,0.28"}, {"--env-color", "1,1,1"}, {"--env-color", "1,1,1", "--env-scale", "3"},
      {"--photons", "100"},    {"--sppm-radius", "0.05"}, {"--caustic-k", "5"},     {"--caustic-radius", "0.01"}};
  for (const char* integrator : kIntegrators) {
    const Run base = render(integrator, {});
    ASSERT_EQ(base.code, 0) << integrator << ": " << base.err;
    for (const auto& change : changes) {
      std::string what = std::string(integrator) + " with";
      for (const std::string& a : change) what += " " + a;
      const Run r = render(integrator, change);
      if (r.code != 0) {
        EXPECT_EQ(r.code, 1) << what;
        EXPECT_NE(r.err.find("integrator does not use it"), std::string::npos) << what << ": " << r.err;
        continue;
      }
      // --env-scale is compared with the plain environment: the scale must matter too.
      const Run& against = change.size() > 2 && change[2] == "--env-scale" ? render(integrator, {"--env-color", "1,1,1"})
                                                                          : base;
      EXPECT_FALSE(same(r.image, against.image)) << what << ": the image did not change";
    }
  }
}

// What each integrator refuses, spelled out: the debug views and ao read neither the
// depth nor the light samples, only the path tracer and the photon mappers are lit by an
// environment, only the photon mappers read --photons, and each its own other options.
TEST_F(RenderOptions, RefusalsAreThoseOfTheIntegratorsThatIgnoreTheOption) {
  for (const char* integrator : kIntegrators) {
    const std::string name = integrator;
    const bool paths = name == "path" || name == "sppm" || name == "photon";
    const bool lit = paths || name == "whitted";
    EXPECT_EQ(render(integrator, {"--max-depth", "3"}).code == 0, lit) << name;
    EXPECT_EQ(render(integrator, {"--light-samples", "3"}).code == 0, lit) << name;
    EXPECT_EQ(render(integrator, {"--env-color", "1,1,1"}).code == 0, paths) << name;
    EXPECT_EQ(render(integrator, {"--photons", "50"}).code == 0, name == "sppm" || name == "photon") << name;
    EXPECT_EQ(render(integrator, {"--sppm-radius", "0.1"}).code == 0, name == "sppm") << name;
    EXPECT_EQ(render(integrator, {"--caustic-k", "10"}).code == 0, name == "photon") << name;
    EXPECT_EQ(render(integrator, {"--caustic-radius", "0.1"}).code == 0, name == "photon") << name;
  }
}

// The motion options (issue 19) on the shipped animated scene, for every integrator:
// --frame-time poses the scene (the ball thrown, the block turned) in every one, and an
// open --shutter blurs the image of those that trace rays at times, or is refused by name
// (the photon mappers, whose photons have no time).
TEST_F(RenderOptions, MotionOptionsChangeTheImageOrAreRefused) {
  const std::string scene = "cornell-box-motion.gltf";
  for (const char* integrator : kIntegrators) {
    const std::string name = integrator;
    const Run start = render(integrator, {"--frame-time", "0"}, scene);
    ASSERT_EQ(start.code, 0) << name << ": " << start.err;
    const Run later = render(integrator, {"--frame-time", "1"}, scene);
    ASSERT_EQ(later.code, 0) << name << ": " << later.err;
    EXPECT_FALSE(same(later.image, start.image)) << name << " --frame-time 1: the image did not change";
    const Run blurred = render(integrator, {"--shutter", "0,1"}, scene);
    if (name == "sppm" || name == "photon") {
      EXPECT_EQ(blurred.code, 1) << name;
      EXPECT_NE(blurred.err.find("not " + name), std::string::npos) << name << ": " << blurred.err;
      continue;
    }
    ASSERT_EQ(blurred.code, 0) << name << ": " << blurred.err;
    EXPECT_FALSE(same(blurred.image, start.image)) << name << " --shutter 0,1: the image did not change";
    EXPECT_FALSE(same(blurred.image, later.image)) << name << " --shutter 0,1: the image is the closing pose's";
  }
}

// --photons for the photon integrator counts caustic photons in all: at most 2^24.
TEST_F(RenderOptions, CausticPhotonsAreBounded) {
  const Run r = render("photon", {"--photons", std::to_string((1 << 24) + 1)});
  EXPECT_EQ(r.code, 2);  // a command-line error
  EXPECT_NE(r.err.find("--photons"), std::string::npos) << r.err;
  EXPECT_EQ(render("photon", {"--caustic-k", "1"}).code, 2);
}

TEST_F(RenderOptions, HowRaysAreTracedNeverChangesTheImage) {
  std::vector<std::vector<std::string>> same_image = {
      {"--mode", "single"}, {"--threads", "1"}, {"--threads", "3"}, {"--accel", "brute"}};
  for (Isa isa : {Isa::Scalar, Isa::Sse4, Isa::Avx2, Isa::Avx512})
    if (cpu_supports(isa)) same_image.push_back({"--isa", std::string(isa_name(isa))});
  for (const char* integrator : kIntegrators) {
    const Run base = render(integrator, {"--threads", "2"});
    ASSERT_EQ(base.code, 0) << base.err;
    for (const auto& option : same_image) {
      const Run r = render(integrator, option);
      ASSERT_EQ(r.code, 0) << r.err;
      EXPECT_TRUE(same(r.image, base.image)) << integrator << " " << option[0] << " " << option[1];
    }
  }
}

}  // namespace
}  // namespace lancer
