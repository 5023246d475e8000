// `lancer gen` in-process: the summary line, the file it writes, and its errors.
#include "app/gen_command.h"
#include "app/cli.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "scene/load_scene.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

class GenCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lancer_gen_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  struct Result {
    int code;
    std::string out, err;
  };
  static Result gen(const GenOptions& options) {
    std::ostringstream out, err;
    const int code = run_gen(options, out, err);
    return {code, out.str(), err.str()};
  }
  GenOptions options(const char* name, int size, const std::string& file) const {
    GenOptions o;
    o.name = name;
    o.size = size;
    o.output = (dir_ / file).string();
    return o;
  }
  fs::path dir_;
};

TEST_F(GenCommandTest, WritesTheSceneAndSaysSo) {
  const GenOptions o = options("tetra", 3, "tetra.glb");
  const Result r = gen(o);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "wrote " + o.output + ": 64 triangles (spd tetra, size 3)\n");
  EXPECT_EQ(r.err, "");
  const Scene back = load_scene(o.output);
  EXPECT_EQ(back.triangle_count(), 64u);
  EXPECT_EQ(back.cameras.size(), 1u);
  EXPECT_EQ(back.lights.size(), 1u);
}

TEST_F(GenCommandTest, TessellationOptionsReachTheGenerator) {
  GenOptions o = options("rings", 1, "rings.glb");
  o.tessellation = {0, 3};
  const Result r = gen(o);
  ASSERT_EQ(r.code, 0) << r.err;
  // 30 spheres of 20 triangles and 30 cylinders of 12, plus the wall.
  EXPECT_NE(r.out.find(": 962 triangles (spd rings, size 1)"), std::string::npos) << r.out;
  EXPECT_EQ(load_scene(o.output).triangle_count(), 962u);
}

TEST_F(GenCommandTest, ErrorsAreReportedWithExitCodeOne) {
  const auto expect_error = [&](const GenOptions& o, const std::string& needle) {
    const Result r = gen(o);
    EXPECT_EQ(r.code, 1) << needle;
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find("lancer: error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(o.output)) << o.output;
  };
  expect_error(options("teapot", 1, "a.glb"), "unknown SPD scene 'teapot'");
  expect_error(options("balls", 9, "b.glb"), "valid sizes: 0..6");
  expect_error(options("balls", 6, "c.glb"), "more than the limit");
  GenOptions kind = options("balls", 1, "d.glb");
  kind.kind = "lsystem";
  expect_error(kind, "unknown generator kind 'lsystem'");
  expect_error(options("balls", 1, "e.obj"), "must end in .glb");
  expect_error(options("balls", 1, "missing/dir/f.glb"), "does not exist");
  GenOptions no_output = options("balls", 1, "");
  no_output.output.clear();
  expect_error(no_output, "no output file");
}

// The same through the command line: `lancer gen spd NAME -s N -o FILE`, its options and
// its exit codes (2 for a malformed command line, 1 for a size the generator refuses).
TEST_F(GenCommandTest, CommandLineWritesTheFileAndRefusesBadArguments) {
  auto cli = [](std::vector<std::string> args) {
    args.insert(args.begin(), "lancer");
    std::vector<const char*> argv;
    for (const std::string& a : args) argv.push_back(a.c_str());
    std::ostringstream out, err;
    const int code = run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
    return Result{code, out.str(), err.str()};
  };
  const std::string file = (dir_ / "balls.glb").string();
  Result r = cli({"gen", "spd", "balls", "-s", "1", "--sphere-subdivisions", "0", "-o", file});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("wrote " + file + ": ", 0), 0u) << r.out;
  EXPECT_EQ(load_scene(file).triangle_count(), spd_triangle_count("balls", 1, SpdOptions{0, 16}));

  r = cli({"gen", "spd", "teapot", "-s", "1", "-o", file});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("teapot"), std::string::npos) << r.err;
  r = cli({"gen", "spd", "balls", "-o", file});
  EXPECT_EQ(r.code, 2) << "--size is required";
  r = cli({"gen", "spd", "balls", "-s", "9", "-o", file});
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("0..6"), std::string::npos) << r.err;
  r = cli({"gen", "spd", "tetra", "-s", "2", "--sphere-subdivisions", "9", "-o", file});
  EXPECT_EQ(r.code, 2);
}

}  // namespace
}  // namespace lancer
