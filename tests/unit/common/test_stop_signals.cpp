// StopSignals: SIGINT, SIGTERM and SIGHUP set the flag instead of killing the
// process, the first one is remembered, a signal sent to another thread is
// seen by the polling one, and the handlers that were there before are back
// afterwards. (The commands that use it are tested end to end by
// tests/unit/cli/stop_signals_cli.cmake.)
#include <gtest/gtest.h>
#include <pthread.h>

#include <atomic>
#include <csignal>
#include <stdexcept>
#include <thread>

#include "earshot/stop_signals.hpp"

using earshot::StopSignals;

namespace {

std::atomic<int> g_previous_handler_saw{0};
extern "C" void previous_handler(int sig) { g_previous_handler_saw.store(sig); }

void (*current_handler(int sig))(int) {
  struct sigaction now {};
  sigaction(sig, nullptr, &now);
  return now.sa_handler;
}

}  // namespace

TEST(StopSignals, EachSignalSetsTheFlagInsteadOfEndingTheProcess) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    StopSignals stop;
    EXPECT_FALSE(stop.requested());
    EXPECT_EQ(stop.signal(), 0);
    ASSERT_EQ(std::raise(sig), 0);  // the default action would end the test binary here
    EXPECT_TRUE(stop.requested()) << StopSignals::name(sig);
    EXPECT_EQ(stop.signal(), sig);
  }
}

TEST(StopSignals, TheFirstSignalIsTheOneReported) {
  StopSignals stop;
  ASSERT_EQ(std::raise(SIGTERM), 0);
  ASSERT_EQ(std::raise(SIGHUP), 0);
  ASSERT_EQ(std::raise(SIGINT), 0);
  EXPECT_EQ(stop.signal(), SIGTERM);
}

TEST(StopSignals, ASignalHandledOnAnotherThreadIsSeenByThePoller) {
  StopSignals stop;
  std::atomic<bool> ready{false};
  std::thread other([&] {
    ready = true;
    while (!stop.requested()) std::this_thread::yield();
  });
  while (!ready) std::this_thread::yield();
  ASSERT_EQ(pthread_kill(other.native_handle(), SIGTERM), 0);
  other.join();  // hangs (ctest timeout) if the flag never shows
  EXPECT_EQ(stop.signal(), SIGTERM);
}

TEST(StopSignals, RestoresThePreviousHandlersAndStartsClear) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, previous_handler);
  {
    StopSignals stop;
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) EXPECT_NE(current_handler(sig), &previous_handler);
    ASSERT_EQ(std::raise(SIGHUP), 0);
    EXPECT_EQ(g_previous_handler_saw.load(), 0);  // ours took it
  }
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) EXPECT_EQ(current_handler(sig), &previous_handler);
  ASSERT_EQ(std::raise(SIGTERM), 0);
  EXPECT_EQ(g_previous_handler_saw.load(), SIGTERM);
  StopSignals again;  // a new one does not inherit the old request
  EXPECT_FALSE(again.requested());
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, SIG_DFL);
}

TEST(StopSignals, OnlyOneAtATime) {
  StopSignals first;
  EXPECT_THROW(StopSignals second, std::logic_error);
  EXPECT_STREQ(StopSignals::name(SIGTERM), "SIGTERM");
  EXPECT_STREQ(StopSignals::name(SIGHUP), "SIGHUP");
  EXPECT_STREQ(StopSignals::name(SIGINT), "SIGINT");
}
