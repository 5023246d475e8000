// lancer-bench reports the process's peak memory (issue 7): after each scene and for the
// whole run, in the JSON and in the markdown summary. The numbers must be the process's own
// high-water mark in bytes: never falling from one scene to the next, and growing by at
// least the kd-tree's own bytes when a large scene follows a small one (a count in KiB
// taken for bytes, or the children's usage, would fail that).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "temp_dir.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

std::string file_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(BenchPeakMemory, ReportedPerSceneAndForTheRunAndGrowsWithTheScene) {
  const test::TempDir dir("lancer_bench_peak");
  // The Cornell box (32 triangles), then SPD balls at depth 3 (262,402 triangles).
  const std::string command = std::string(LANCER_BENCH_BINARY) +
                              " --scenes cornell-box,balls-3 --sets primary --reps 1 --size 32 --threads 1 --json " +
                              (dir / "r.json").string() + " >" + (dir / "out.txt").string() + " 2>" +
                              (dir / "err.txt").string();
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << file_text(dir / "err.txt");

  const nlohmann::json j = nlohmann::json::parse(file_text(dir / "r.json"));
  ASSERT_EQ(j.at("scenes").size(), 2u);
  const nlohmann::json &small = j.at("scenes")[0], &large = j.at("scenes")[1];
  ASSERT_EQ(large.at("name"), "balls-3");
  const auto small_peak = small.at("peak_rss_bytes").get<std::int64_t>();
  const auto large_peak = large.at("peak_rss_bytes").get<std::int64_t>();
  const auto run_peak = j.at("peak_rss_bytes").get<std::int64_t>();
  const auto kd_bytes = large.at("builds")[0].at("lancer_bytes").get<std::int64_t>();
  EXPECT_GT(small_peak, std::int64_t(1) << 20) << "a running process holds more than a MiB";
  EXPECT_LT(run_peak, std::int64_t(24) << 30) << "more than the machine has";
  EXPECT_GE(large_peak, small_peak);
  EXPECT_GE(run_peak, large_peak);
  EXPECT_GT(kd_bytes, std::int64_t(4) << 20);
  EXPECT_GE(large_peak - small_peak, kd_bytes) << "the kd-tree of balls-3 alone is " << kd_bytes << " bytes";

  const std::string out = file_text(dir / "out.txt");
  EXPECT_NE(out.find("peak RSS"), std::string::npos) << out;
}

}  // namespace
}  // namespace lancer
