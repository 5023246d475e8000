// The distributed render end to end: the real `lancer` under `mpirun -np 3` on this machine
// (loopback), against the same render in one process. Byte-identical images; a worker killed
// with SIGKILL, or Ctrl-C (SIGINT to mpirun), leaves a checkpoint that `--resume` finishes
// to the identical image, with or without MPI; resumes of another seed or scene, sppm, and
// a scene that fails to load are refused with one message and no hang.
//
// Skipped where lancer was built without Open MPI. *Heavy: the sanitizer run leaves them out
// (MPI's own allocations are not ours to check); tests/dist/distributed_render_test.cpp
// checks the same logic in-process under the sanitizers.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "render/checkpoint_file.h"
#include "test_paths.h"
#include "test_process.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Seconds after which a process counts as hung, whatever load the machine is under.
constexpr double kHung = 300.0;

std::string slurp(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class MpiRenderHeavy : public ::testing::Test {
 protected:
  void SetUp() override {
#ifndef LANCER_MPIRUN
    GTEST_SKIP() << "lancer was built without Open MPI (libopenmpi-dev, openmpi-bin): no distributed render to test";
#endif
    dir_ = fs::temp_directory_path() / ("lancer_mpi_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }

  // `lancer render SCENE` with the options every render here shares, then `extra`.
  std::vector<std::string> lancer(const std::string& scene, const std::vector<std::string>& extra) const {
    std::vector<std::string> args = {LANCER_BINARY, "render", (test::scenes_dir() / scene).string(), "--no-progress"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }
  // The same under mpirun with `ranks` ranks.
  static std::vector<std::string> mpirun(int ranks, std::vector<std::string> args) {
#ifdef LANCER_MPIRUN
    std::vector<std::string> m = {LANCER_MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np",
                                  std::to_string(ranks)};
    args.insert(args.begin(), m.begin(), m.end());
#endif
    return args;
  }

  // Starts a process with stdout and stderr to files named after `name`.
  pid_t start(const std::vector<std::string>& args, const std::string& name) const {
    return test::spawn(args, (dir_ / (name + ".out")).string(), (dir_ / (name + ".err")).string());
  }
  // The exit status, or -1 for a death by signal; a process still running after kHung
  // seconds is killed and fails the test.
  static int wait_for(pid_t pid) {
    const auto end = Clock::now() + std::chrono::duration<double>(kHung);
    for (;;) {
      int status = 0;
      if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      if (Clock::now() > end) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        ADD_FAILURE() << "process " << pid << " hung";
        return -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  int run(const std::vector<std::string>& args, const std::string& name) const { return wait_for(start(args, name)); }
  std::string text(const std::string& name) const { return slurp(dir_ / name); }
  fs::path file(const std::string& name) const { return dir_ / name; }

  // The pid of rank `rank` among mpirun's children (from their environment), or 0.
  static pid_t rank_pid(pid_t mpirun_pid, int rank) {
    for (const auto& entry : fs::directory_iterator("/proc")) {
      const std::string name = entry.path().filename().string();
      if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
      std::ifstream stat(entry.path() / "stat");
      std::string line;
      std::getline(stat, line);
      const std::size_t close = line.rfind(')');
      if (close == std::string::npos) continue;
      char state = 0;
      int ppid = 0;
      if (std::sscanf(line.c_str() + close + 1, " %c %d", &state, &ppid) != 2 || ppid != mpirun_pid) continue;
      const std::string env = slurp(entry.path() / "environ");
      if (env.find(std::string("OMPI_COMM_WORLD_RANK=") + std::to_string(rank) + '\0') != std::string::npos)
        return static_cast<pid_t>(std::stoi(name));
    }
    return 0;
  }

  // Waits until `f` exists (a checkpoint was written) or the process ends; true if it exists.
  static bool wait_for_file(const fs::path& f, pid_t pid) {
    const auto end = Clock::now() + std::chrono::duration<double>(kHung);
    while (Clock::now() < end) {
      if (fs::exists(f)) return true;
      if (int status = 0; waitpid(pid, &status, WNOHANG) == pid) return fs::exists(f);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

  // The interrupted renders' settings (a resume repeats them): long enough (a few seconds
  // on two cores) that a checkpoint every 0.05 s comes well before the end.
  static std::vector<std::string> long_render(std::vector<std::string> more) {
    more.insert(more.begin(), {"--width", "64", "--spp", "600", "--seed", "3"});
    return more;
  }
  fs::path part() const { return file("part.exr"); }

  // Starts the long render under mpirun -np 3 (1 thread a rank), saving part() every
  // 0.05 s, and returns its pid once the first checkpoint is there (0 if none came).
  pid_t start_long_render() const {
    const pid_t job =
        start(mpirun(3, lancer("cornell-box.gltf",
                               long_render({"-o", part().string(), "--threads", "1", "--checkpoint", "0.05"}))),
              "job");
    return wait_for_file(part(), job) ? job : 0;
  }

  // Once the job has ended: part() holds an unfinished render, and resuming it (under
  // mpirun or in one process) ends with the bytes of the uninterrupted render.
  void expect_resume_gives_the_whole_image(bool with_mpi) const {
    const Checkpoint saved = read_checkpoint(part());
    ASSERT_LT(*std::min_element(saved.state.count.begin(), saved.state.count.end()), 600u)
        << "the render finished before the interruption: nothing was interrupted";
    ASSERT_EQ(run(lancer("cornell-box.gltf", long_render({"-o", file("whole.exr").string(), "--threads", "2"})),
                  "whole"),
              0)
        << text("whole.err");
    std::vector<std::string> resume =
        lancer("cornell-box.gltf", long_render({"--resume", part().string(), "-o", part().string(), "--threads", "1"}));
    ASSERT_EQ(run(with_mpi ? mpirun(3, resume) : resume, "resumed"), 0) << text("resumed.err");
    EXPECT_EQ(slurp(file("whole.exr")), slurp(part())) << "the resumed image differs";
  }

  fs::path dir_;
};

TEST_F(MpiRenderHeavy, ThreeRanksWriteTheBytesOneProcessWrites) {
  for (const char* scene : {"cornell-box-spheres.gltf", "cornell-box-dof.gltf"}) {
    SCOPED_TRACE(scene);
    const std::vector<std::string> common = {"--width", "72", "--height", "56", "--spp", "12", "--seed", "5"};
    auto with = [&](std::vector<std::string> more) {
      more.insert(more.begin(), common.begin(), common.end());
      return more;
    };
    ASSERT_EQ(run(lancer(scene, with({"-o", file("one.exr"), "-o", file("one.png"), "--threads", "2"})), "one"), 0)
        << text("one.err");
    // One and two threads per rank.
    ASSERT_EQ(run(mpirun(3, lancer(scene, with({"-o", file("mpi.exr"), "-o", file("mpi.png"), "--threads", "1"}))),
                  "mpi"),
              0)
        << text("mpi.err");
    EXPECT_EQ(slurp(file("one.exr")), slurp(file("mpi.exr"))) << "EXR bytes differ";
    EXPECT_EQ(slurp(file("one.png")), slurp(file("mpi.png"))) << "PNG bytes differ";
    EXPECT_NE(text("mpi.out").find("3 ranks x 1 thread"), std::string::npos) << text("mpi.out");
    ASSERT_EQ(run(mpirun(2, lancer(scene, with({"-o", file("mpi2.exr"), "--threads", "2"}))), "mpi2"), 0)
        << text("mpi2.err");
    EXPECT_EQ(slurp(file("one.exr")), slurp(file("mpi2.exr"))) << "2 ranks x 2 threads: EXR bytes differ";
  }
}

// kill -9 of rank 1 in the middle: Open MPI ends the job; rank 0 has saved what was done,
// and a resume in one process ends with the uninterrupted render's bytes.
TEST_F(MpiRenderHeavy, AKilledWorkerLeavesACheckpointThatResumesToTheSameImage) {
  const pid_t job = start_long_render();
  ASSERT_GT(job, 0) << text("job.err");
  const pid_t worker = rank_pid(job, 1);
  ASSERT_GT(worker, 0) << "rank 1 not found among mpirun's children";
  ASSERT_EQ(kill(worker, SIGKILL), 0);
  EXPECT_NE(wait_for(job), 0) << "the job ended as if nothing had happened: " << text("job.out");
  expect_resume_gives_the_whole_image(false);
}

// Ctrl-C reaches mpirun, which sends SIGTERM to every rank: rank 0 writes what it has. A
// resume under mpirun, in place, finishes it to the uninterrupted render's bytes.
TEST_F(MpiRenderHeavy, SigintToMpirunThenAnMpiResumeGivesTheSameImage) {
  const pid_t job = start_long_render();
  ASSERT_GT(job, 0) << text("job.err");
  ASSERT_EQ(kill(job, SIGINT), 0);
  EXPECT_NE(wait_for(job), 0) << text("job.out");
  expect_resume_gives_the_whole_image(true);
}

// A short render in one process, resumed to more samples under mpirun.
TEST_F(MpiRenderHeavy, AnMpiResumeOfAOneProcessRenderGivesTheSameImage) {
  const std::vector<std::string> common = {"--width", "40", "--seed", "9"};
  auto with = [&](std::vector<std::string> more) {
    more.insert(more.begin(), common.begin(), common.end());
    return more;
  };
  ASSERT_EQ(run(lancer("cornell-box-spheres.gltf", with({"--spp", "3", "-o", file("part.exr")})), "part"), 0);
  ASSERT_EQ(run(lancer("cornell-box-spheres.gltf", with({"--spp", "10", "-o", file("whole.exr")})), "whole"), 0);
  ASSERT_EQ(run(mpirun(3, lancer("cornell-box-spheres.gltf", with({"--spp", "10", "--resume", file("part.exr"), "-o",
                                                                   file("resumed.exr"), "--threads", "1"}))),
                "resumed"),
            0)
      << text("resumed.err");
  EXPECT_EQ(slurp(file("whole.exr")), slurp(file("resumed.exr")));
}

// Refusals end the whole job with one message (rank 0's) and a non-zero status.
TEST_F(MpiRenderHeavy, RefusalsEndTheJobWithOneMessage) {
  ASSERT_EQ(run(lancer("cornell-box.gltf", {"--width", "24", "--spp", "2", "-o", file("part.exr")}), "part"), 0);
  struct Case {
    std::string name, scene;
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"seed", "cornell-box.gltf", {"--width", "24", "--spp", "4", "--seed", "7", "--resume", file("part.exr")}, "seed"},
      {"scene", "cornell-box-spheres.gltf", {"--width", "24", "--spp", "4", "--resume", file("part.exr")}, "scene"},
      {"sppm", "cornell-box.gltf", {"--width", "24", "--spp", "2", "--integrator", "sppm"}, "sppm"},
      {"missing", "no-such-scene.gltf", {"--width", "24"}, "no-such-scene.gltf"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"-o", file("out-" + c.name + ".exr").string()});
    EXPECT_NE(run(mpirun(3, lancer(c.scene, args)), c.name), 0);
    const std::string err = text(c.name + ".err");
    EXPECT_NE(err.find(c.says), std::string::npos) << err;
    std::size_t errors = 0;
    for (std::size_t at = err.find("lancer: error"); at != std::string::npos; at = err.find("lancer: error", at + 1))
      ++errors;
    EXPECT_EQ(errors, 1u) << err;
    EXPECT_FALSE(fs::exists(file("out-" + c.name + ".exr")));
  }
}

}  // namespace
}  // namespace lancer
