#include "app/interrupt.h"

#include <csignal>
#include <stdexcept>

namespace lancer {

namespace {

// Lock-free, so storing to it is async-signal-safe.
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
std::atomic<bool> g_installed{false};
struct sigaction g_previous_int, g_previous_term;

extern "C" void record_signal(int sig) { g_signal.store(sig, std::memory_order_relaxed); }

}  // namespace

InterruptGuard::InterruptGuard() {
  if (g_installed.exchange(true)) throw std::logic_error("InterruptGuard: one at a time");
  g_signal.store(0);
  struct sigaction action {};
  action.sa_handler = record_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
  g_installed.store(false);
}

const std::atomic<int>& InterruptGuard::flag() const { return g_signal; }

int InterruptGuard::exit_code() const {
  const int sig = g_signal.load();
  return sig == 0 ? 0 : 128 + sig;
}

}  // namespace lancer
