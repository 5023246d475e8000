// `lancer bench` (src/app/bench_command.h): where it looks for lancer-bench, and the
// message when the program is missing. (The forwarding itself runs the real binary:
// lancer_bench_program_test.cpp.)
#include "app/bench_command.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>

#include "temp_dir.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

TEST(BenchCommand, LooksForLancerBenchBesideTheRunningBinary) {
  const fs::path self = fs::read_symlink("/proc/self/exe");  // this test program
  EXPECT_EQ(bench_program_path(), self.parent_path() / "lancer-bench");
}

TEST(BenchCommand, MissingProgramIsAClearErrorNotACrash) {
  const test::TempDir dir("lancer_bench_command");
  const fs::path missing = dir / "lancer-bench";
  std::ostringstream err;
  EXPECT_EQ(exec_bench_program(missing, {"--quick"}, err), 1);
  EXPECT_NE(err.str().find(missing.string() + " not found"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("--target lancer-bench"), std::string::npos) << err.str();

  // A folder of that name is not a program either.
  fs::create_directories(missing);
  err.str("");
  EXPECT_EQ(exec_bench_program(missing, {}, err), 1);
  EXPECT_NE(err.str().find("not found"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace lancer
