#include "earshot/stop_signals.hpp"

#include <atomic>
#include <stdexcept>

namespace earshot {
namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

// A signal handler can reach only static storage. A lock-free atomic is safe
// in a handler and, unlike volatile sig_atomic_t, also between the thread the
// kernel picked to run the handler and the thread that polls the flag.
std::atomic<int> g_signal{0};
std::atomic<bool> g_installed{false};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void on_stop_signal(int sig) {
  int none = 0;
  g_signal.compare_exchange_strong(none, sig);  // keep the first one
}

}  // namespace

StopSignals::StopSignals() : old_{} {
  if (g_installed.exchange(true)) throw std::logic_error("StopSignals: one is already installed");
  g_signal.store(0);
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // writes in flight are not cut short by EINTR
  for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &sa, &old_[i]);
}

StopSignals::~StopSignals() {
  for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &old_[i], nullptr);
  g_installed.store(false);
}

int StopSignals::signal() const { return g_signal.load(); }

const char* StopSignals::name(int sig) {
  switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
  }
}

}  // namespace earshot
