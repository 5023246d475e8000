// Progress on stderr: a bar with percentage and ETA on a terminal, otherwise a plain line
// per 10 %. Safe to call from render worker threads.
#pragma once

#include <chrono>
#include <cstddef>
#include <iosfwd>
#include <mutex>

namespace lancer {

class ProgressReporter {
 public:
  ProgressReporter(std::ostream& err, bool terminal);

  void update(std::size_t done, std::size_t total);
  void finish();

 private:
  std::ostream& err_;
  bool terminal_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
  int last_decile_ = 0;  // no "0 %" line
  int last_permille_ = -1;
  bool drew_ = false;
};

}  // namespace lancer
