// A long render is never lost: the real `lancer` binary, interrupted by SIGINT or SIGTERM,
// writes the image so far (valid files, no temporaries left) and exits 130 or 143, also
// while checkpoints are being written and for a 512 x 512 image; --time ends the render on
// its own; --checkpoint writes the outputs while it runs.
//
// How soon it exits is the renderer's guarantee, tested without a clock in
// tests/render/progressive_test.cpp (the stop flag is read before every wavefront of at
// most four 8x8 blocks). Here
// the bound is only "it did not hang": an idle machine exits in about 0.2 s, and kPromptExit
// leaves room for any load a shared machine sees.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "render/checkpoint_file.h"
#include "render/image_io.h"
#include "test_paths.h"
#include "test_process.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Seconds from the signal to the exit that count as prompt, whatever else runs.
constexpr double kPromptExit = 10.0;

class RenderProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lancer_interrupt_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Starts `lancer render` on the Cornell box with `extra` options, stdout/stderr to files.
  pid_t start(const std::vector<std::string>& extra, int width = 96) {
    std::vector<std::string> args = {LANCER_BINARY, "render", (test::scenes_dir() / "cornell-box.gltf").string(),
                                     "-o", exr().string(), "-o", png().string(), "--width", std::to_string(width),
                                     "--no-progress", "--threads", "2"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::spawn(args, (dir_ / "stdout").string(), (dir_ / "stderr").string());
  }

  // Waits up to `limit` seconds; returns the exit status (or -1 on a signal death / timeout).
  static int wait_for(pid_t pid, double limit) {
    const auto end = Clock::now() + std::chrono::duration<double>(limit);
    for (;;) {
      int status = 0;
      const pid_t r = waitpid(pid, &status, WNOHANG);
      if (r == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      if (Clock::now() > end) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        return -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  void expect_valid_images() const {
    for (const fs::path& f : {exr(), png()}) {
      const ImageRGB image = read_image(f);
      EXPECT_EQ(image.width, 96) << f;
      double total = 0.0;
      for (float v : image.rgb) {
        ASSERT_TRUE(std::isfinite(v)) << f;
        total += v;
      }
      EXPECT_GT(total, 0.0) << f << " is black";
    }
  }

  // No temporary file of the atomic writes (image_io.cpp: "<file>.tmp", then rename) is
  // left behind: an interrupted write must not leave litter or a half file.
  void expect_no_temporaries() const {
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_NE(entry.path().extension(), ".tmp") << entry.path() << " was left behind";
  }

  // Sends `sig` and checks the exit status and the time it took to arrive.
  void interrupt_and_expect(pid_t pid, int sig, int expected_code, double within_s) {
    ASSERT_EQ(kill(pid, sig), 0);
    const auto sent = Clock::now();
    const int code = wait_for(pid, 3 * kPromptExit);
    const double took = std::chrono::duration<double>(Clock::now() - sent).count();
    EXPECT_EQ(code, expected_code) << read("stderr");
    EXPECT_LT(took, within_s) << "seconds from the signal to the exit";
  }

  std::string read(const char* name) const {
    std::FILE* f = std::fopen((dir_ / name).c_str(), "r");
    std::string s;
    if (!f) return s;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
    std::fclose(f);
    return s;
  }

  fs::path exr() const { return dir_ / "render.exr"; }
  fs::path png() const { return dir_ / "render.png"; }
  fs::path dir_;
};

// A huge --spp keeps the render busy; 1.5 s in, it is well into its passes.
TEST_F(RenderProcess, SigintWritesTheImageSoFarAndExits130) {
  const pid_t pid = start({"--spp", "1000000"});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  interrupt_and_expect(pid, SIGINT, 130, kPromptExit);
  EXPECT_NE(read("stdout").find("interrupted after"), std::string::npos) << read("stdout");
  expect_valid_images();
  expect_no_temporaries();
}

// Checkpoints after every pass keep the outputs being rewritten; a SIGINT that lands during
// a write still ends with whole, valid files and no temporaries.
TEST_F(RenderProcess, SigintWhileCheckpointsAreWrittenLeavesValidFiles) {
  const pid_t pid = start({"--spp", "1000000", "--checkpoint", "0.001"});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  interrupt_and_expect(pid, SIGINT, 130, kPromptExit);
  expect_valid_images();
  expect_no_temporaries();
}

// A real image size: the partial render of 512 x 512 pixels is encoded as EXR and PNG and
// each flushed to the disk before the exit (about 0.2 s on an idle machine, most of it
// encoding; 1.1 s was seen under load on 2 cores). *Heavy: `make test` runs it, the
// sanitizer run does not (too slow there).
using RenderProcessHeavy = RenderProcess;

TEST_F(RenderProcessHeavy, SigintOnA512ImageWritesTheWholeImage) {
  const pid_t pid = start({"--spp", "1000000"}, 512);
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  interrupt_and_expect(pid, SIGINT, 130, kPromptExit);
  EXPECT_NE(read("stdout").find("interrupted after"), std::string::npos) << read("stdout");
  for (const fs::path& f : {exr(), png()}) {
    const ImageRGB image = read_image(f);
    EXPECT_EQ(image.width, 512) << f;
    EXPECT_EQ(image.height, 512) << f;
  }
  expect_no_temporaries();
}

TEST_F(RenderProcess, SigtermExits143WithTheImage) {
  const pid_t pid = start({"--spp", "1000000"});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  EXPECT_EQ(wait_for(pid, 10.0), 143) << read("stderr");
  expect_valid_images();
}

TEST_F(RenderProcess, TimeLimitEndsTheRenderWithStatus0) {
  const pid_t pid = start({"--time", "0.5"});
  EXPECT_EQ(wait_for(pid, 30.0), 0) << read("stderr");
  EXPECT_NE(read("stdout").find("time limit reached"), std::string::npos) << read("stdout");
  expect_valid_images();
}

// With --checkpoint the outputs appear while the render still runs.
TEST_F(RenderProcess, CheckpointsWriteTheOutputsWhileRendering) {
  const pid_t pid = start({"--time", "4", "--checkpoint", "0.2"});
  bool seen_while_running = false;
  for (int i = 0; i < 300 && !seen_while_running; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) break;  // finished: too late to look
    seen_while_running = fs::exists(exr()) && fs::exists(png());
  }
  EXPECT_TRUE(seen_while_running) << "no checkpoint within 3 s";
  if (seen_while_running) expect_valid_images();
  EXPECT_EQ(wait_for(pid, 30.0), 0) << read("stderr");
  expect_valid_images();
}

// Ctrl-C in the middle of a render, then `--resume` of the EXR it left, in place and without
// --spp (on to the interrupted render's target): the file ends byte for byte as the one an
// uninterrupted render writes.
TEST_F(RenderProcess, SigintThenResumeGivesTheUninterruptedFile) {
  const std::vector<std::string> options = {"--spp", "120", "--checkpoint", "0.001", "--seed", "4"};
  ASSERT_EQ(wait_for(start(options, 48), 120.0), 0) << read("stderr");
  const fs::path straight = dir_ / "straight.exr";
  fs::rename(exr(), straight);

  const pid_t pid = start(options, 48);
  for (int i = 0; i < 2000 && !fs::exists(exr()); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  interrupt_and_expect(pid, SIGINT, 130, kPromptExit);
  const Checkpoint interrupted = read_checkpoint(exr());
  EXPECT_LT(interrupted.state.passes, 120) << "the render was interrupted";

  ASSERT_EQ(wait_for(start({"--resume", exr().string(), "--seed", "4"}, 48), 120.0), 0) << read("stderr");
  auto bytes = [](const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  EXPECT_EQ(bytes(exr()), bytes(straight));
  expect_no_temporaries();
}

}  // namespace
}  // namespace lancer
