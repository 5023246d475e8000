// One rank's renderer in a distributed render: a thread that takes work units from a queue,
// renders each with the rank's threads (its passes in parallel: they do not depend on each
// other) and queues the results, while the rank's main thread talks to the other ranks.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "dist/work_unit.h"
#include "render/sample_renderer.h"
#include "render/tile_scheduler.h"

namespace lancer {

// Renders `task`'s passes over `tile` on `runner`'s threads, the passes in parallel, then
// adds their samples into the task's sums pass by pass, each onto the pixels that have as
// many samples as its index (the rule render_image follows). When `stop` says so, ends early
// and adds only the passes finished before the first one left unfinished. Throws
// std::invalid_argument when the sums do not fit the tile.
UnitResult render_unit(const SampleRenderer& renderer, const Tile& tile, UnitTask task, TileRunner& runner,
                       const std::atomic<bool>& stop);

class LocalWorker {
 public:
  // Keeps references: all must outlive the worker. `threads` is the runner's (for the record).
  LocalWorker(const SampleRenderer& renderer, const std::vector<Tile>& tiles, TileRunner& runner, int threads);
  ~LocalWorker();  // stop()
  LocalWorker(const LocalWorker&) = delete;
  LocalWorker& operator=(const LocalWorker&) = delete;

  // Queues a unit; throws std::invalid_argument for a tile out of range.
  void push(UnitTask task);
  // A finished (or, after stop, partly finished) unit's result, if one is ready. Rethrows
  // what a unit's rendering threw (the worker then takes no more).
  std::optional<UnitResult> take_result();
  // Waits up to `timeout` for a result (returns at once when one is ready).
  void wait_for_result(std::chrono::microseconds timeout);
  // Ends the unit in progress at its next wavefront, drops the queued ones and joins the
  // thread; the partial result stays for take_result. Idempotent.
  void stop();
  // stop() without the wait: the unit in progress ends soon; stop() joins.
  void request_stop() { stop_.store(true); }

 private:
  void run();

  const SampleRenderer& renderer_;
  const std::vector<Tile>& tiles_;
  TileRunner& runner_;
  int threads_;
  std::mutex mutex_;
  std::condition_variable wake_worker_, wake_owner_;
  std::deque<UnitTask> units_;
  std::deque<UnitResult> results_;
  bool quit_ = false;
  std::exception_ptr failure_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace lancer
