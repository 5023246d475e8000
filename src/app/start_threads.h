// Starting oneTBB's worker threads when a command starts, not in the middle of its work.
#pragma once

namespace lancer {

// Runs one task on each of `threads` threads (0: every thread of the default arena),
// waiting at most about a tenth of a second for them to arrive, so that the workers a
// command will use, their stacks and oneTBB's own structures exist before the scene is
// loaded. oneTBB's allocations do not say how much they asked for: under a memory limit
// they then usually fail here rather than in the middle of a load or build, whose own
// allocations name their sizes. Throws what oneTBB throws to the calling thread
// (std::bad_alloc; std::runtime_error when it cannot create a thread).
void start_worker_threads(int threads);

}  // namespace lancer
