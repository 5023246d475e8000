// The lancer command line, in-process (run_cli) and as the real binary.
#include "app/cli.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "render/image_io.h"
#include "simd/isa.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

struct CliResult {
  int code;
  std::string out, err;
};

CliResult run(std::vector<std::string> args) {
  args.insert(args.begin(), "lancer");
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int code = run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {code, out.str(), err.str()};
}

// This process's folder, removed when it exits.
fs::path temp_dir() {
  static const test::TempDir dir("lancer_cli_test");
  return dir.path();
}

std::string cornell() { return (test::scenes_dir() / "cornell-box.gltf").string(); }

TEST(Cli, HelpListsEveryRenderOption) {
  const CliResult top = run({"--help"});
  EXPECT_EQ(top.code, 0);
  EXPECT_NE(top.out.find("render"), std::string::npos);
  EXPECT_NE(top.out.find("info"), std::string::npos);
  const CliResult r = run({"render", "--help"});
  EXPECT_EQ(r.code, 0);
  for (const char* opt : {"--output", "--width", "--height", "--spp", "--integrator", "--threads", "--seed", "--accel",
                          "--camera", "--eye", "--look-at", "--up", "--fov", "--max-depth", "--kd-split", "--isa",
                          "--mode"})
    EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
}

TEST(Cli, NoSubcommandIsAUsageError) { EXPECT_EQ(run({}).code, 2); }

TEST(Cli, AbsurdOptionsAreRefused) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"render", cornell(), "--spp", "0"},
        {"render", cornell(), "--width", "-1"},
        {"render", cornell(), "--width", "100000", "--height", "100000"},
        {"render", cornell(), "--threads", "-3"},
        {"render", cornell(), "--integrator", "magic"},
        {"render", cornell(), "--accel", "octree"},
        {"render", cornell(), "--kd-split", "sweep"},
        {"render", cornell(), "--isa", "avx3"},
        {"render", cornell(), "--mode", "foo"},
        {"render", cornell(), "--eye", "1,2"}}) {
    const CliResult r = run(args);
    EXPECT_EQ(r.code, 2) << args[2] << " " << args[3];
    EXPECT_FALSE(r.err.empty());
  }
}

// Issue 7's absurd values: each refused before anything is loaded or allocated, with a
// message naming the option and the allowed range (CLI11's check text).
TEST(Cli, AbsurdValuesNameTheOptionAndItsRange) {
  struct Case {
    std::vector<std::string> args;
    const char* option;
  };
  const Case cases[] = {
      {{"--spp", "0"}, "--spp"},
      {{"--spp", "-5"}, "--spp"},
      {{"--width", "-1"}, "--width"},
      {{"--width", "0"}, "--width"},
      {{"--width", "100000", "--height", "100000"}, "--width"},
      {{"--width", "100000"}, "--width"},  // the height would follow the camera: 100000 too
      {{"--width", "16", "--height", "100000"}, "--height"},
      {{"--width", "99999999999999999999"}, "--width"},
      {{"--spp", "many"}, "--spp"},
      {{"--time", "0"}, "--time"},
      {{"--checkpoint", "-1"}, "--checkpoint"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"render", cornell(), "--no-progress", "-o", (temp_dir() / "absurd.png").string()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CliResult r = run(args);
    std::string joined;
    for (const std::string& a : c.args) joined += a + " ";
    EXPECT_EQ(r.code, 2) << joined << r.err;
    EXPECT_NE(r.err.find(c.option), std::string::npos) << joined << ": " << r.err;
    EXPECT_FALSE(fs::exists(temp_dir() / "absurd.png")) << joined;
  }
}

// A scene with nothing that emits light renders (status 0), black, and says why.
TEST(Cli, SceneWithoutLightRendersBlackWithAWarning) {
  const fs::path dir = temp_dir();
  const fs::path obj = dir / "unlit.obj", exr = dir / "unlit.exr";
  std::ofstream(obj) << "v -1 -1 -3\nv 1 -1 -3\nv 0 1 -3\nf 1 2 3\n";
  for (const std::string integrator : {"path", "whitted"}) {
    const CliResult r = run({"render", obj.string(), "--width", "16", "--spp", "2", "--no-progress", "--integrator",
                             integrator, "-o", exr.string()});
    ASSERT_EQ(r.code, 0) << integrator << ": " << r.err;
    EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("unlit.obj"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("no lights"), std::string::npos) << r.err;
    // It says what to do, with options this integrator takes.
    EXPECT_NE(r.err.find(integrator == "path" ? "--env-color" : "--integrator path --env-color"), std::string::npos)
        << r.err;
    const ImageRGB image = read_image(exr);
    ASSERT_EQ(image.width, 16);
    for (float v : image.rgb) ASSERT_EQ(v, 0.0f) << integrator << ": the unlit scene is not black";
  }
  // The same triangle under an emissive material: no warning, and not black (the test can fail).
  const fs::path lit = dir / "lit.obj", mtl = dir / "lit.mtl";
  std::ofstream(mtl) << "newmtl glow\nKd 0 0 0\nKe 1 1 1\n";
  std::ofstream(lit) << "mtllib lit.mtl\nusemtl glow\nv -1 -1 -3\nv 1 -1 -3\nv 0 1 -3\nf 1 2 3\n";
  const CliResult r = run({"render", lit.string(), "--width", "16", "--spp", "2", "--no-progress", "-o", exr.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("no lights"), std::string::npos) << r.err;
  double sum = 0.0;
  for (float v : read_image(exr).rgb) sum += v;
  EXPECT_GT(sum, 0.0);
}

TEST(Cli, MissingSceneNamesTheFile) {
  const CliResult r = run({"render", "/nonexistent/scene.gltf", "-o", (temp_dir() / "x.png").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("/nonexistent/scene.gltf"), std::string::npos) << r.err;
}

TEST(Cli, UnknownOutputTypeIsRefusedBeforeRendering) {
  const CliResult r = run({"render", cornell(), "-o", (temp_dir() / "x.bmp").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(".bmp"), std::string::npos) << r.err;
}

TEST(Cli, CameraIndexOutOfRangeIsRefused) {
  const CliResult r = run({"render", cornell(), "--camera", "7", "-o", (temp_dir() / "x.png").string()});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--camera"), std::string::npos) << r.err;
}

TEST(Cli, RendersExrAndPngWithSummary) {
  const fs::path dir = temp_dir();
  const fs::path exr = dir / "c.exr", png = dir / "sub" / "c.png";
  const CliResult r = run({"render", cornell(), "--width", "24", "--height", "16", "--spp", "2", "--no-progress", "-o",
                           exr.string(), "-o", png.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Mrays/s"), std::string::npos) << r.out;
  const ImageRGB a = read_image(exr), b = read_image(png);
  EXPECT_EQ(a.width, 24);
  EXPECT_EQ(a.height, 16);
  EXPECT_EQ(b.width, 24);
  EXPECT_EQ(b.height, 16);
  double sum = 0.0;
  for (float v : a.rgb) sum += v;
  EXPECT_GT(sum, 0.0) << "the lit Cornell box rendered black";
}

TEST(Cli, SummaryNamesTheIsaAndEveryIsaRenders) {
  for (Isa isa : supported_isas()) {
    const std::string name(isa_name(isa));
    const CliResult r = run({"render", cornell(), "--width", "8", "--height", "8", "--spp", "1", "--no-progress",
                             "--isa", name, "-o", (temp_dir() / ("i_" + name + ".png")).string()});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("isa " + name), std::string::npos) << r.out;
  }
}

TEST(Cli, UnknownModeNamesTheOption) {
  const CliResult r = run({"render", cornell(), "--mode", "foo", "-o", (temp_dir() / "m.png").string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--mode"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("foo"), std::string::npos) << r.err;
}

// Both modes render, the summary names the mode and the primary-ray rate, and the images
// are the same bit for bit (the EXR holds the linear floats).
TEST(Cli, PacketAndSingleModesRenderTheSameImage) {
  std::vector<ImageRGB> images;
  for (const std::string mode : {"packet", "single"}) {
    const fs::path exr = temp_dir() / ("mode_" + mode + ".exr");
    const CliResult r = run({"render", cornell(), "--width", "21", "--height", "13", "--spp", "2", "--no-progress",
                             "--mode", mode, "-o", exr.string()});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("mode " + mode), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("primary "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" Mrays/s/thread"), std::string::npos) << r.out;
    images.push_back(read_image(exr));
  }
  ASSERT_EQ(images[0].rgb.size(), images[1].rgb.size());
  EXPECT_EQ(std::memcmp(images[0].rgb.data(), images[1].rgb.data(), images[0].rgb.size() * sizeof(float)), 0);
}

TEST(Cli, SummaryNamesTheDefaultModePacket) {
  const CliResult r = run({"render", cornell(), "--width", "8", "--height", "8", "--spp", "1", "--no-progress", "-o",
                           (temp_dir() / "default_mode.png").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("mode packet"), std::string::npos) << r.out;
}

// Without --height the image is square, unless a glTF camera gives its aspect ratio.
TEST(Cli, HeightFollowsWidthOrTheCameraAspect) {
  const fs::path dir = temp_dir();
  const fs::path obj = dir / "tri.obj";
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const fs::path png = dir / "square.png";
  ASSERT_EQ(run({"render", obj.string(), "--width", "24", "--spp", "1", "--no-progress", "-o", png.string()}).code, 0);
  EXPECT_EQ(read_image(png).height, 24);
  ASSERT_EQ(run({"render", obj.string(), "--width", "24", "--height", "10", "--spp", "1", "--no-progress", "-o",
                 png.string()}).code, 0);
  EXPECT_EQ(read_image(png).height, 10);
}

TEST(Cli, InfoDescribesTheScene) {
  const CliResult r = run({"info", cornell()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("triangles:"), std::string::npos);
  EXPECT_NE(r.out.find("bounds:"), std::string::npos);
  for (const char* stat : {"nodes:", "leaves:", "empty leaves:", "max leaf depth:", "mean leaf depth:",
                           "triangles / leaf:", "SAH cost:", "bytes / triangle:", "build time:",
                           "peak memory:"})
    EXPECT_NE(r.out.find(stat), std::string::npos) << stat;
}

// A triangle drawn by two nodes: shared with --instancing on, copied with off; the render
// summary counts the triangles drawn either way.
TEST(Cli, InstancingOptionSharesMeshesDrawnTwice) {
  const fs::path file = temp_dir() / "twice.gltf";
  {
    std::ofstream f(file);
    f << R"({"asset": {"version": "2.0"},
      "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [2, 0, 0]}],
      "scenes": [{"nodes": [0, 1]}], "scene": 0})";
  }
  const CliResult on = run({"info", file.string(), "--instancing", "on"});
  ASSERT_EQ(on.code, 0) << on.err;
  EXPECT_NE(on.out.find("triangles:  1 "), std::string::npos) << on.out;
  EXPECT_NE(on.out.find("instances:  2 of 1 meshes, 2 triangles drawn"), std::string::npos) << on.out;
  const CliResult off = run({"info", file.string(), "--instancing", "off"});
  ASSERT_EQ(off.code, 0) << off.err;
  EXPECT_NE(off.out.find("triangles:  2 "), std::string::npos) << off.out;
  EXPECT_EQ(off.out.find("instances:"), std::string::npos) << off.out;
  // Auto: two drawings of one triangle are cheaper copied.
  EXPECT_EQ(run({"info", file.string()}).out.find("instances:"), std::string::npos);
  const CliResult render = run({"render", file.string(), "-o", (temp_dir() / "twice.exr").string(), "--width", "16",
                                "--spp", "1", "--no-progress", "--instancing", "on", "--integrator", "albedo"});
  ASSERT_EQ(render.code, 0) << render.err;
  EXPECT_NE(render.out.find("(2 triangles drawn)"), std::string::npos) << render.out;
  const CliResult bad = run({"render", file.string(), "-o", "x.exr", "--instancing", "sometimes"});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--instancing"), std::string::npos) << bad.err;
}

TEST(Cli, InfoListsWhatTheReaderIgnored) {
  const fs::path obj = temp_dir() / "odd.obj";
  {
    std::ofstream f(obj);
    f << "v 0 0 0\nv 1 0 0\nv 0 1 0\nfrobnicate 1 2 3\nf 1 2 3\n";
  }
  const CliResult r = run({"info", obj.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("warnings:   1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  - ignored 1"), std::string::npos) << r.out;
  const CliResult clean = run({"info", cornell()});
  EXPECT_NE(clean.out.find("warnings:   0"), std::string::npos) << clean.out;
}

TEST(Cli, ExposureAndToneCurveShapeThePngNotTheExr) {
  const fs::path dir = temp_dir();
  auto render_to = [&](const std::vector<std::string>& extra, const std::string& stem) {
    std::vector<std::string> args = {"render", cornell(), "--width", "16", "--spp", "4", "--no-progress",
                                     "-o", (dir / (stem + ".exr")).string(), "-o", (dir / (stem + ".png")).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliResult r = run(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return std::pair{read_image(dir / (stem + ".exr")), read_image(dir / (stem + ".png"))};
  };
  const auto [exr, png] = render_to({"--exposure", "1", "--tone", "clamp"}, "clamp");
  const auto [exr_neutral, png_neutral] = render_to({}, "neutral");
  EXPECT_EQ(exr.rgb, exr_neutral.rgb) << "EXR output is linear radiance whatever the display settings";
  double brightest = 0.0;
  for (std::size_t i = 0; i < exr.rgb.size(); i += 3) {
    const glm::vec3 linear(exr.rgb[i], exr.rgb[i + 1], exr.rgb[i + 2]);
    brightest = std::max(brightest, double(linear.r));
    const glm::vec3 clamped = display_map(linear, {1.0f, ToneCurve::Clamp});
    const glm::vec3 neutral = display_map(linear, {0.0f, ToneCurve::Neutral});
    for (int c = 0; c < 3; ++c) {
      // 8-bit sRGB codes: within half a code step, a relative 1/255 at worst near white.
      EXPECT_NEAR(png.rgb[i + std::size_t(c)], clamped[c], 0.01f + 0.02f * clamped[c]) << i;
      EXPECT_NEAR(png_neutral.rgb[i + std::size_t(c)], neutral[c], 0.01f + 0.02f * neutral[c]) << i;
    }
  }
  EXPECT_GT(brightest, 1.0) << "the light is in view: the curves differ there";
  EXPECT_EQ(run({"render", cornell(), "--tone", "filmic", "-o", (dir / "x.png").string()}).code, 2);
}

// The real binary: exit codes reach the shell and output goes to the right streams.
TEST(CliBinary, ExitCodesAndStreams) {
  const fs::path dir = temp_dir();
  const std::string bin = LANCER_BINARY;
  const std::string bad = bin + " render " + (dir / "missing.obj").string() + " >" + (dir / "o.txt").string() + " 2>" +
                          (dir / "e.txt").string();
  const int status = std::system(bad.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  std::ifstream e(dir / "e.txt");
  const std::string err((std::istreambuf_iterator<char>(e)), std::istreambuf_iterator<char>());
  EXPECT_NE(err.find("missing.obj"), std::string::npos) << err;
}

}  // namespace
}  // namespace lancer
