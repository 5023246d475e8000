// lancer_bench_micro's SIMD-primitive and triangle-test rows (bench/simd_bench*.cpp,
// bench/triangle_bench*.cpp), run as `make bench-micro` runs it but with a tiny minimum
// time: every ISA this CPU supports has its rows, no other ISA has any, and no benchmark
// failed its check against the scalar reference.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "simd/isa.h"
#include "temp_dir.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

// Runs the program with `args`, JSON to a file; returns the exit code and stderr.
struct MicroRun {
  int code = -1;
  std::string err;
  nlohmann::json rows;  // the "benchmarks" array
};

std::string text_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

MicroRun run_micro(const std::string& args) {
  const test::TempDir dir("lancer_micro_test");
  const std::string command = std::string(LANCER_BENCH_MICRO_BINARY) + " " + args +
                              " --benchmark_format=json >" + (dir / "out.json").string() + " 2>" +
                              (dir / "err.txt").string();
  const int status = std::system(command.c_str());
  MicroRun r;
  if (WIFEXITED(status)) r.code = WEXITSTATUS(status);
  r.err = text_of(dir / "err.txt");
  const nlohmann::json j = nlohmann::json::parse(text_of(dir / "out.json"), nullptr, /*allow_exceptions=*/false);
  if (j.is_object() && j.contains("benchmarks")) r.rows = j.at("benchmarks");
  return r;
}

int width_of(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return 1;
    case Isa::Sse4: return 4;
    case Isa::Avx2: return 8;
    case Isa::Avx512: return 16;
  }
  return 0;
}

TEST(MicroBenchProgram, EverySupportedIsaHasCheckedSimdAndTriangleRows) {
  const MicroRun r = run_micro("--benchmark_filter='^BM_(Simd|TriangleTest)/' --benchmark_min_time=0.001");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(r.rows.is_array() && !r.rows.empty()) << "no JSON rows; stderr: " << r.err;

  std::map<std::string, nlohmann::json> by_name;
  for (const nlohmann::json& row : r.rows) {
    const std::string name = row.at("name");
    EXPECT_FALSE(row.value("error_occurred", false)) << name << ": " << row.value("error_message", "");
    by_name[name] = row;
  }

  const std::vector<std::string> ops = {"add",    "mul",        "div",        "rcp",       "sqrt",
                                        "minmax", "cmp_movemask", "select", "reduce_add", "load_store", "gather"};
  std::vector<std::string> expected;
  for (Isa isa : supported_isas()) {
    const std::string prefix = "BM_Simd/" + std::string(isa_name(isa)) + "/";
    for (const std::string& op : ops) expected.push_back(prefix + op);
    // fma only where the width has the instruction.
    if (isa == Isa::Avx2 || isa == Isa::Avx512) expected.push_back(prefix + "fma");
    expected.push_back("BM_TriangleTest/" + std::string(isa_name(isa)) + "/w" + std::to_string(width_of(isa)));
  }
  expected.push_back("BM_TriangleTest/scalar/watertight");

  for (const std::string& name : expected) {
    const auto it = by_name.find(name);
    ASSERT_NE(it, by_name.end()) << name << " is missing";
    EXPECT_GT(it->second.value("items_per_second", 0.0), 0.0) << name;
    if (name.rfind("BM_TriangleTest/", 0) == 0) {
      // The data set is made so that some pairs hit and most miss.
      const double hit_fraction = it->second.value("hit_fraction", -1.0);
      EXPECT_GT(hit_fraction, 0.0) << name;
      EXPECT_LT(hit_fraction, 0.5) << name;
    }
  }
  // Nothing else: no rows for an ISA this CPU lacks, no fma at widths without it.
  EXPECT_EQ(by_name.size(), expected.size());
  for (const auto& [name, row] : by_name)
    EXPECT_NE(std::find(expected.begin(), expected.end(), name), expected.end()) << "unexpected row " << name;
}

}  // namespace
}  // namespace lancer
