// A distributed render inside one test process: rank 0 on the calling thread, ranks
// 1..n-1 on threads of their own, each with its own TileRunner and SampleRenderer over the
// same scene, tree and camera, talking through an InProcessChannel.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "dist/distributed_render.h"
#include "in_process_channel.h"

namespace lancer::test {

// Ends the test program when a test hangs (a rank waiting forever for another), so a
// deadlock shows as a failure with a message instead of a stuck test run. Generous: it
// says nothing about speed.
class HangWatchdog {
 public:
  explicit HangWatchdog(std::string what, std::chrono::seconds limit = std::chrono::seconds(300))
      : thread_([this, what = std::move(what), limit] {
          std::unique_lock<std::mutex> lock(mutex_);
          if (!wake_.wait_for(lock, limit, [this] { return done_; })) {
            std::fprintf(stderr, "hang: %s did not end\n", what.c_str());
            std::abort();
          }
        }) {}
  ~HangWatchdog() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;
};

struct RankSetup {
  int threads = 1;
  bool ok = true;  // false: the rank's setup failed (no renderer), with this error
  std::string error;
  std::string facts;  // its WorkerReady::facts (rank 0's is always "")
  // Called on the rank's thread before it sends Ready (to hold a rank back). Without it,
  // rank 0 starts once the rank is ready, so that every rank gets units from the first.
  std::function<void()> before_ready;
};

struct DistributedRun {
  ImageRGB image;
  RenderStats stats;
  DistributedReport report;
  std::vector<int> results;  // per rank but 0: the results it sent
};

// Renders with one rank per entry of `ranks` ([0] is rank 0's setup, which must be ok).
// Rethrows what render_distributed threw once every worker has ended; a worker's own
// exception is a test failure.
inline DistributedRun run_distributed(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                                      const RenderSettings& settings, const std::vector<RankSetup>& ranks,
                                      RenderState& state, const ProgressCallback& progress = {},
                                      const RenderControl& control = {}, unsigned shuffle_seed = 0) {
  const HangWatchdog watchdog("a distributed render over " + std::to_string(ranks.size()) + " ranks");
  InProcessHub hub(static_cast<int>(ranks.size()), shuffle_seed);
  std::mutex errors_mutex;
  std::vector<std::string> errors;
  std::vector<std::thread> workers;
  for (int r = 1; r < static_cast<int>(ranks.size()); ++r) {
    workers.emplace_back([&, r] {
      const RankSetup& setup = ranks[static_cast<std::size_t>(r)];
      InProcessChannel channel(hub, r);
      RenderSettings s = settings;
      s.threads = setup.threads;
      WorkerReady me;
      me.threads = setup.threads;
      me.host = "thread-" + std::to_string(r);
      me.facts = setup.facts;
      try {
        if (setup.before_ready) setup.before_ready();
        if (!setup.ok) {
          me.ok = false;
          me.error = setup.error;
          serve_distributed(channel, nullptr, s, nullptr, me);
          return;
        }
        TileRunner runner(setup.threads);
        const SampleRenderer renderer(scene, accel, camera, s, runner);
        serve_distributed(channel, &renderer, s, &runner, me);
      } catch (const std::exception& e) {
        const std::lock_guard<std::mutex> lock(errors_mutex);
        errors.push_back("rank " + std::to_string(r) + ": " + e.what());
      }
    });
  }
  for (int r = 1; r < hub.size(); ++r)
    if (!ranks[static_cast<std::size_t>(r)].before_ready)
      while (hub.posted(r, MessageKind::Ready) == 0) std::this_thread::yield();
  InProcessChannel channel(hub, 0);
  RenderSettings s = settings;
  s.threads = ranks.at(0).threads;
  WorkerReady me;
  me.threads = s.threads;
  me.host = "main";
  DistributedRun run;
  std::exception_ptr failure;
  try {
    TileRunner runner(s.threads);
    const SampleRenderer renderer(scene, accel, camera, s, runner);
    run.image = render_distributed(channel, renderer, s, runner, me, state, run.stats, run.report, progress, control);
  } catch (...) {
    failure = std::current_exception();
    // Let the workers end, whether or not rank 0 told them to (a second Stop is ignored).
    for (int r = 1; r < hub.size(); ++r) channel.send(r, MessageKind::Stop, {});
  }
  for (std::thread& w : workers) w.join();
  for (const std::string& e : errors) ADD_FAILURE() << e;
  run.results.assign(ranks.size(), 0);
  for (int r = 1; r < hub.size(); ++r) run.results[static_cast<std::size_t>(r)] = hub.posted(r, MessageKind::Result);
  if (failure) std::rethrow_exception(failure);
  return run;
}

}  // namespace lancer::test
