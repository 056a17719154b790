#pragma once
// A JACK server on its dummy driver (48 kHz, 128 frames) under a unique
// server name, for a test's life: real-time where this machine allows it.
// The tests that play through JACK (demo, LV2 in jalv) share it.
#include <sys/types.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <string>
#include <thread>

#include "demo_run.hpp"

namespace earshot::testing {

/// A jackd on the dummy driver, under a unique server name, for the test's life.
class DummyJack {
 public:
  DummyJack()
      : name_("earshot-test-" + std::to_string(getpid()) + "-" +
              std::to_string(std::chrono::steady_clock::now().time_since_epoch().count() % 1000000)) {
    setenv("JACK_NO_AUDIO_RESERVATION", "1", 1);
    setenv("JACK_DEFAULT_SERVER", name_.c_str(), 1);
    // Real-time, as JACK runs by default, where this machine allows it (root or
    // rtprio): a non-real-time server and client are late whenever anything
    // else runs (a window drawn in software under Xvfb cost 50 xruns in 30 s).
    const bool rt = run("chrt -f 1 true").status == 0;
    const std::string cmd = std::string("jackd ") + (rt ? "-R -P 70" : "--no-realtime") + " -n " + name_ +
                            " -d dummy -r 48000 -p 128 >" + log() + " 2>&1 & echo $!";
    pid_ = std::atoi(run(cmd).output.c_str());
    std::this_thread::sleep_for(std::chrono::seconds(2));
  }
  ~DummyJack() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    for (int i = 0; i < 50 && kill(pid_, 0) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  DummyJack(const DummyJack&) = delete;
  DummyJack& operator=(const DummyJack&) = delete;
  [[nodiscard]] bool running() const { return pid_ > 0 && kill(pid_, 0) == 0; }
  [[nodiscard]] std::string log() const { return "/tmp/" + name_ + ".log"; }

 private:
  std::string name_;
  int pid_ = -1;
};

}  // namespace earshot::testing
