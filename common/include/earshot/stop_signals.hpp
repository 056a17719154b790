// Ends a long-running command cleanly on SIGINT, SIGTERM or SIGHUP: Ctrl-C,
// `kill`, `timeout`, systemd and a closed terminal all ask the same way, and
// the command finishes its last row or block, flushes and closes its files.
//
//   StopSignals stop;                 // handlers installed
//   while (!stop.requested()) work();
//   // ~StopSignals: the previous handlers are back
//
// The handler only stores the signal's number in a lock-free atomic (it may
// run on any thread). One StopSignals may exist at a time; a second one
// throws std::logic_error. Not for the audio thread: it is a control-side flag.
#pragma once

#include <csignal>

namespace earshot {

class StopSignals {
 public:
  StopSignals();   ///< installs the handlers; the flag starts clear
  ~StopSignals();  ///< restores the handlers that were there before
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// True once any of the signals arrived.
  [[nodiscard]] bool requested() const { return signal() != 0; }
  /// The first signal that arrived (SIGINT, SIGTERM, SIGHUP), 0 if none.
  [[nodiscard]] int signal() const;
  /// "SIGINT", "SIGTERM", "SIGHUP" (for messages); "a signal" otherwise.
  [[nodiscard]] static const char* name(int sig);

 private:
  struct sigaction old_[3];
};

}  // namespace earshot
