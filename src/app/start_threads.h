// Starting oneTBB's worker threads when a command starts, not in the middle of its work.
#pragma once

namespace lancer {

// Runs one task on every thread of the default arena (waiting at most about a tenth of a
// second for them to arrive), so that oneTBB's worker threads, their stacks and its own
// structures exist before the scene is loaded. oneTBB's allocations do not say how much
// they asked for: under a memory limit they then fail here, at once, rather than in the
// middle of a load or build whose own allocations name their sizes. Throws what oneTBB
// throws (std::bad_alloc, or std::runtime_error when a thread cannot be created).
void start_worker_threads();

}  // namespace lancer
