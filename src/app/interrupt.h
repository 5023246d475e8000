// SIGINT and SIGTERM during a render: the handler only records the signal, the renderer
// sees it between pixel blocks and returns the image so far, which the program writes
// before it exits with 128 + the signal's number (130 for SIGINT, 143 for SIGTERM).
#pragma once

#include <atomic>

namespace lancer {

// Installs the handlers for its lifetime and restores the previous ones afterwards. One
// at a time per process.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  // The signal received so far (0: none); what RenderControl::stop watches.
  const std::atomic<int>& flag() const;
  // 128 + the signal, or 0 when none was received.
  int exit_code() const;
};

}  // namespace lancer
