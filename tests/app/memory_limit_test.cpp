// Under an address-space limit (ulimit -v) `lancer info` either succeeds or says how much
// memory it could not get: swept from limits where the program cannot even start to one
// where it succeeds, on a scene small enough for the lean one-thread kd-tree build and
// on one built by every thread. oneTBB's own allocations and its threads' stacks do not
// say their size; the program starts them first (start_threads.h), and a failure there
// says that the worker threads could not be started.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "test_process.h"
#include "test_sanitizer.h"
#include "temp_dir.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

struct LimitedRun {
  int status = -1;  // exit status, or -1 when the child did not exit normally
  std::string err;
};

// `args` under an address-space limit of `bytes`, stderr captured.
LimitedRun run_limited(const std::vector<std::string>& args, rlim_t bytes, const fs::path& err_file) {
  const pid_t pid = test::spawn(args, "/dev/null", err_file.string(), bytes);
  LimitedRun r;
  int status = 0;
  if (waitpid(pid, &status, 0) == pid && WIFEXITED(status)) r.status = WEXITSTATUS(status);
  std::ifstream in(err_file);
  std::stringstream text;
  text << in.rdbuf();
  r.err = text.str();
  return r;
}

TEST(MemoryLimit, EveryAllocationFailureNamesItsSize) {
  if (test::kAddressSanitized) GTEST_SKIP() << "AddressSanitizer reserves more address space than any limit here allows";
  const test::TempDir dir("lancer_memory_limit_test");
  const std::string bin = LANCER_BINARY;
  // rings-1: 11,522 triangles, the lean build; rings-3: 161,282, built on every thread.
  for (const char* size : {"1", "3"}) {
    const std::string scene = (dir / (std::string("rings-") + size + ".glb")).string();
    ASSERT_EQ(run_limited({bin, "gen", "spd", "rings", "-s", size, "-o", scene}, RLIM_INFINITY, dir / "gen.txt").status,
              0);
    int sized = 0;
    bool succeeded = false;
    // 1 MiB steps from 8 MiB: the loader needs some 20 MiB for the libraries first (exit
    // 127). The most tried grows with the cores, whose worker threads have stacks.
    const rlim_t most = 512 + 16 * rlim_t(std::max(1u, std::thread::hardware_concurrency()));
    for (rlim_t mib = 8; mib <= most && !succeeded; ++mib) {
      const LimitedRun r = run_limited({bin, "info", scene}, mib << 20, dir / "err.txt");
      if (r.status == 0) {
        succeeded = true;
      } else if (r.status == 127 || (r.status >= 97 && r.status <= 99)) {
        continue;  // the dynamic loader, or the child before exec (test_process.h), ran out

      } else if (r.err.find("lancer: error:") == std::string::npos) {
        ADD_FAILURE() << "rings-" << size << " at " << mib << " MiB: exit status " << r.status
                      << " (-1: killed by a signal) without an error line: " << r.err;
      } else {
        const bool names_size = r.err.find("out of memory: could not allocate ") != std::string::npos;
        const bool at_start = r.err.find("starting the worker threads") != std::string::npos ||
                              r.err.find("could not start the worker threads") != std::string::npos;
        EXPECT_TRUE(names_size || at_start) << "rings-" << size << " at " << mib << " MiB: " << r.err;
        sized += names_size ? 1 : 0;
      }
    }
    EXPECT_TRUE(succeeded) << "rings-" << size << ": lancer info did not succeed under any limit up to " << most
                           << " MiB";
    EXPECT_GT(sized, 0) << "rings-" << size << ": no limit made lancer info fail inside the load or build";
  }
}

}  // namespace
}  // namespace lancer
