#include "app/progress_reporter.h"

#include <cstdio>
#include <ostream>
#include <string>

namespace lancer {

ProgressReporter::ProgressReporter(std::ostream& err, bool terminal)
    : err_(err), terminal_(terminal), start_(std::chrono::steady_clock::now()) {}

void ProgressReporter::update(std::size_t done, std::size_t total) {
  if (total == 0) return;
  const double fraction = static_cast<double>(done) / static_cast<double>(total);
  std::lock_guard lock(mutex_);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (terminal_) {
    const int permille = static_cast<int>(fraction * 1000.0);
    if (permille == last_permille_) return;  // redraw only when the bar changes
    last_permille_ = permille;
    constexpr int kWidth = 40;
    const int filled = static_cast<int>(fraction * kWidth);
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    char line[160];
    std::snprintf(line, sizeof line, "\r[%s%s] %5.1f%%  ETA %5.1fs ", std::string(filled, '#').c_str(),
                  std::string(kWidth - filled, '.').c_str(), 100.0 * fraction, eta);
    err_ << line << std::flush;
    drew_ = true;
  } else {
    const int decile = static_cast<int>(fraction * 10.0);
    if (decile <= last_decile_) return;
    last_decile_ = decile;
    char line[80];
    std::snprintf(line, sizeof line, "progress: %3d%% (%.1fs)\n", decile * 10, elapsed);
    err_ << line << std::flush;
  }
}

void ProgressReporter::finish() {
  std::lock_guard lock(mutex_);
  if (terminal_ && drew_) err_ << "\n" << std::flush;
}

}  // namespace lancer
