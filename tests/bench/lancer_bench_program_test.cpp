// lancer-bench end to end, as users run it (directly and as `lancer bench`): a tiny run
// prints the markdown tables and writes JSON and SVG that hold its numbers; embree rows
// appear exactly when the program was built with Embree; bad options exit 2 with a
// message naming the problem.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "program_run.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

#ifdef LANCER_HAVE_EMBREE
constexpr bool kWithEmbree = true;
#else
constexpr bool kWithEmbree = false;
#endif

using Result = test::ProgramResult;
using test::file_text;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

class LancerBenchProgram : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lancer_bench_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result run(const std::string& program, const std::string& args) const {
    return test::run_program(program + " " + args, dir_);
  }
  Result bench(const std::string& args) const { return run(LANCER_BENCH_BINARY, args); }

  // One small scene, primary rays, one repetition, 64x64 pixels, one thread.
  std::string tiny() const {
    return "--scenes cornell-box --sets primary --reps 1 --size 64 --threads 1 --json " + (dir_ / "r.json").string() +
           " --plot " + (dir_ / "r.svg").string();
  }

  fs::path dir_;
};

TEST_F(LancerBenchProgram, TinyRunPrintsTablesAndWritesJsonAndSvg) {
  const Result r = bench(tiny());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string header = kWithEmbree
                                 ? "| scene | set | rays | isa | threads | packet | single | embree | embree call |"
                                 : "| scene | set | rays | isa | threads | packet | single |";
  EXPECT_NE(r.out.find(header), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| cornell-box | primary | 4096 | "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("## Scenes"), std::string::npos);
  EXPECT_EQ(r.out.find("failed"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("packet == single on every ray"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("rtcIntersect16 (coherent)") != std::string::npos, kWithEmbree) << r.out;

  const nlohmann::json j = nlohmann::json::parse(file_text(dir_ / "r.json"));
  EXPECT_EQ(j.at("schema"), "lancer-bench/1");
  EXPECT_EQ(j.at("options").at("size"), 64);
  ASSERT_EQ(j.at("scenes").size(), 1u);
  const nlohmann::json& scene = j.at("scenes")[0];
  EXPECT_EQ(scene.at("name"), "cornell-box");
  EXPECT_EQ(scene.at("triangles"), 32);
  EXPECT_GT(scene.at("builds")[0].at("lancer_bytes").get<double>(), 0.0);
  EXPECT_EQ(scene.at("builds")[0].contains("embree_bytes"), kWithEmbree);
  ASSERT_EQ(scene.at("rows").size(), 1u);
  const nlohmann::json& row = scene.at("rows")[0];
  EXPECT_EQ(row.at("set"), "primary");
  EXPECT_EQ(row.at("rays"), 64 * 64);
  EXPECT_EQ(row.at("threads"), 1);
  EXPECT_EQ(row.at("modes").size(), kWithEmbree ? 3u : 2u);
  EXPECT_EQ(row.at("modes").contains("embree"), kWithEmbree);
  for (const auto& [mode, m] : row.at("modes").items()) {
    ASSERT_EQ(m.at("seconds_per_pass").size(), 1u) << mode;  // --reps 1
    const double s = m.at("seconds_per_pass")[0].get<double>();
    EXPECT_GT(s, 0.0) << mode;
    EXPECT_NEAR(m.at("mrays_median").get<double>(), 4096.0 / s * 1e-6, 1e-9 * 4096.0 / s) << mode;
    EXPECT_GE(m.at("passes_per_run").get<int>(), 1) << mode;
  }
  EXPECT_EQ(scene.at("checks")[0].at("packet_mismatches"), 0);
  // Camera rays into the Cornell box (32 triangles, a tree of a leaf or a few): nearly every
  // ray enters a leaf and tests several triangles there.
  const auto& work = scene.at("checks")[0].at("single_work_per_ray");
  EXPECT_GE(work.at("inner_steps").get<double>(), 0.0);
  EXPECT_GT(work.at("leaves").get<double>(), 0.5);
  EXPECT_GT(work.at("triangle_tests").get<double>(), 2.0 * work.at("leaves").get<double>());

  const std::string svg = file_text(dir_ / "r.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u) << svg.substr(0, 80);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(count(svg, "<rect"), kWithEmbree ? 3u : 2u);  // one bar per mode of the one scene
  EXPECT_NE(svg.find("primary rays, 1 thread"), std::string::npos);
  EXPECT_NE(svg.find(">Mrays/s<"), std::string::npos);
}

TEST_F(LancerBenchProgram, BadOptionsExitTwoWithAMessage) {
  struct Case {
    const char* args;
    const char* message;
  };
  const Case cases[] = {
      {"--scenes nosuch", "unknown scene 'nosuch'"},
      {"--scenes gears-99", "unknown scene 'gears-99'"},
      {"--sets primary,sideways", "--sets: unknown value 'sideways'"},
      {"--modes packet,warp", "--modes: unknown value 'warp'"},
      {"--isa mmx", "--isa: unknown value 'mmx'"},
      {"--size 60", "--size: 60 is not a multiple of 8"},
      {"--size big", "--size: 'big' is not a whole number"},
      {"--reps 0", "--reps: '0' is not a whole number in 1..1000"},
      {"--threads 1,-2", "--threads: '-2' is not a whole number"},
      {"--models /nonexistent/lancer-models", "--models: /nonexistent/lancer-models is not a folder"},
      {"--isa avx2 --all-isas", "exclude each other"},
      {"--frobnicate", "frobnicate"},
  };
  for (const Case& c : cases) {
    const Result r = bench(c.args);
    EXPECT_EQ(r.code, 2) << c.args;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << c.args << ": " << r.out;
  }
  const Result embree = bench("--modes embree --scenes cornell-box --sets primary --reps 1 --size 8 --threads 1");
  if (kWithEmbree) {
    EXPECT_EQ(embree.code, 0) << embree.err;
  } else {
    EXPECT_EQ(embree.code, 2);
    EXPECT_NE(embree.err.find("built without Embree"), std::string::npos) << embree.err;
  }
}

TEST_F(LancerBenchProgram, LancerBenchForwardsEveryArgument) {
  Result r = run(LANCER_BINARY, "bench --help");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Usage: lancer-bench"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--quick"), std::string::npos) << r.out;

  r = run(LANCER_BINARY, "bench --scenes nosuch");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("lancer-bench: --scenes: unknown scene 'nosuch'"), std::string::npos) << r.err;

  r = run(LANCER_BINARY, "bench " + tiny());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| cornell-box | primary | 4096 | "), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "r.json"));
}

}  // namespace
}  // namespace lancer
