#include "app/start_threads.h"

#include <atomic>
#include <chrono>
#include <thread>

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace lancer {

void start_worker_threads(int threads) {
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([] {
    const int n = tbb::this_task_arena::max_concurrency();
    if (n <= 1) return;
    std::atomic<int> arrived{0};
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
    // Each task waits until all have started or the deadline passes: one thread cannot
    // run them all, so every worker is asked for (and never waited for forever).
    tbb::parallel_for(
        0, n, 1,
        [&](int) {
          arrived.fetch_add(1);
          while (arrived.load() < n && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
        },
        tbb::simple_partitioner());
  });
}

}  // namespace lancer
