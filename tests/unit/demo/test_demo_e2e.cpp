// End to end, with a real audio server and no sound card: a JACK server on
// its dummy driver (48 kHz, 128 frames), `earshot demo` playing through it
// with the simulated tracker. Slow (30 s of audio per scene): label slow.
#include <gtest/gtest.h>
#include <sys/types.h>
#include <csignal>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "binaural_cues.hpp"
#include "demo_run.hpp"
#include "dummy_jack.hpp"
#include "../scratch_path.hpp"

namespace {

using earshot::testing::DummyJack;
using earshot::testing::run;

double field(const std::string& out, const std::string& re) {
  std::smatch m;
  return std::regex_search(out, m, std::regex(re)) ? std::stod(m[1]) : -1.0;
}

TEST(DemoEndToEnd, PlaysThroughJackDummyWithoutXrunAndCuesFollowTheHead) {
  if (run("command -v jackd").status != 0) GTEST_SKIP() << "jackd missing (apt-get install jackd2)";
  DummyJack jack;
  ASSERT_TRUE(jack.running()) << "jackd did not start; see " << jack.log();
  const std::string wav = earshot::test::scratch_path("e2e.wav").string(), poses = earshot::test::scratch_path("e2e.csv").string();
  const auto r = run(std::string(EARSHOT_EXE) + " demo --scene " + EARSHOT_TEST_SCENE +
                     " --device system --buffer 128 --tracker sim --duration 30 --capture " + wav +
                     " --capture-poses " + poses + " </dev/null");
  std::printf("%s\n", r.output.c_str());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(field(r.output, R"(blocks, (\d+) xruns)"), 0.0) << r.output;

  const auto [left, right] = earshot::testing::read_float_wav(wav);
  ASSERT_GE(left.size(), 29u * 48000u);
  double peak = 0;
  for (std::size_t i = 0; i < left.size(); ++i) {
    ASSERT_TRUE(std::isfinite(left[i]) && std::isfinite(right[i])) << "sample " << i;
    peak = std::max({peak, double(std::abs(left[i])), double(std::abs(right[i]))});
  }
  EXPECT_GT(peak, 0.01) << "silent";

  // The head's yaw per control tick; windows of 0.1 s compared with the yaw at their middle.
  std::ifstream pf(poses);
  std::string line;
  std::getline(pf, line);
  std::vector<std::pair<double, double>> yaw;
  while (std::getline(pf, line)) {
    const auto c = line.find(',');
    yaw.emplace_back(std::stod(line.substr(0, c)), std::stod(line.substr(c + 1)));
  }
  ASSERT_GT(yaw.size(), 100u);
  auto yaw_at = [&](double t) {
    for (const auto& [tt, y] : yaw)
      if (tt >= t) return y;
    return yaw.back().second;
  };
  const std::size_t win = 4800;
  int straight = 0, turned = 0, agree = 0;
  double ild_straight = 0, ild_turned = 0;
  for (std::size_t at = 48000; at + win <= left.size(); at += win) {
    const double y = yaw_at((double(at) + win / 2.0) / 48000.0);
    const double ild = earshot::analysis::ild_db({left.data() + at, win}, {right.data() + at, win});
    if (std::abs(y) < 3) ++straight, ild_straight += std::abs(ild);
    if (std::abs(y) > 15) {
      ++turned, ild_turned += std::abs(ild);
      // Head turned left (yaw > 0): the source ahead is now on the right, the right ear louder.
      if ((y > 0) == (ild < 0)) ++agree;
    }
  }
  ASSERT_GT(straight, 5);
  ASSERT_GT(turned, 5);
  ild_straight /= straight, ild_turned /= turned;
  std::printf("cues: |ILD| %.2f dB with the head straight (%d windows), %.2f dB turned > 15 deg (%d windows), "
              "side agrees with the yaw in %d\n", ild_straight, straight, ild_turned, turned, agree);
  EXPECT_LT(ild_straight, 2.0);
  EXPECT_GT(ild_turned, ild_straight + 3.0);
  EXPECT_GE(agree, turned * 9 / 10);
}

TEST(DemoEndToEnd, AnUnknownDeviceNameListsTheDevices) {
  if (run("command -v jackd").status != 0) GTEST_SKIP() << "jackd missing (apt-get install jackd2)";
  DummyJack jack;
  ASSERT_TRUE(jack.running()) << "jackd did not start; see " << jack.log();
  const auto r = run(std::string(EARSHOT_EXE) + " demo --device no-such-device --duration 1 </dev/null");
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("no output device named 'no-such-device'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("system (JACK"), std::string::npos) << r.output;
}

// The plugin's wiimote tracker starts and keeps looking for a remote: the demo
// says so (esGetTrackerState: searching, with how to pair one) and the audio
// plays on with the head held straight.
TEST(DemoEndToEnd, WithNoRemoteTheAudioPlaysOnWithTheHeadStraight) {
  if (run("command -v jackd").status != 0) GTEST_SKIP() << "jackd missing (apt-get install jackd2)";
  DummyJack jack;
  ASSERT_TRUE(jack.running()) << "jackd did not start; see " << jack.log();
  const std::string wav = earshot::test::scratch_path("e2e-noremote.wav").string();
  const auto r = run(std::string(EARSHOT_EXE) + " demo --scene " + EARSHOT_TEST_SCENE +
                     " --device system --tracker wiimote --duration 3 --capture " + wav + " </dev/null");
  std::printf("%s\n", r.output.c_str());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("played 3.0 s"), std::string::npos) << r.output;
  if (r.output.find("tracker wiimote: tracking") != std::string::npos) GTEST_SKIP() << "a Wii Remote is here";
  EXPECT_NE(r.output.find("tracker wiimote searching: no Wii Remote found"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bluetoothctl"), std::string::npos) << r.output;
  const auto [left, right] = earshot::testing::read_float_wav(wav);
  ASSERT_GE(left.size(), 2u * 48000u);
  const double ild = earshot::analysis::ild_db(left, right);
  EXPECT_LT(std::abs(ild), 1.0) << "a source ahead of a straight head is centred";
}

// The tracker's input stops mid-run (a replay of 1 s in a 4 s run, as a
// remote that goes away would): the demo says the tracker is lost and why,
// the head eases back to straight, and the audio plays to the end.
TEST(DemoEndToEnd, ATrackerThatStopsMidRunIsReportedAndTheAudioPlaysOn) {
  if (run("command -v jackd").status != 0) GTEST_SKIP() << "jackd missing (apt-get install jackd2)";
  const std::string dots = "/tmp/earshot-e2e-short-" + std::to_string(getpid()) + ".csv";
  ASSERT_EQ(run(std::string(EARSHOT_EXE) + " track simulate --frames 100 --out " + dots).status, 0);
  DummyJack jack;
  ASSERT_TRUE(jack.running()) << "jackd did not start; see " << jack.log();
  const std::string wav = earshot::test::scratch_path("e2e-stop.wav").string();
  const auto r = run(std::string(EARSHOT_EXE) + " demo --scene " + EARSHOT_TEST_SCENE +
                     " --device system --tracker replay:" + dots + " --duration 4 --capture " + wav + " </dev/null");
  std::printf("%s\n", r.output.c_str());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("played 4.0 s"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lost: end of " + dots), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("eases to straight ahead"), std::string::npos) << r.output;
  const auto [left, right] = earshot::testing::read_float_wav(wav);
  ASSERT_GE(left.size(), 3u * 48000u);
  double tail = 0;  // the last second, long after the replay ended
  for (std::size_t i = left.size() - 48000; i < left.size(); ++i) {
    ASSERT_TRUE(std::isfinite(left[i]) && std::isfinite(right[i]));
    tail = std::max({tail, double(std::abs(left[i])), double(std::abs(right[i]))});
  }
  EXPECT_GT(tail, 0.01) << "the audio went silent after the tracker stopped";
  std::remove(dots.c_str());
}

// A scene file with errors: named with the field, Circles plays instead; a
// tracker that cannot start: named, the head held straight; audio plays on.
TEST(DemoEndToEnd, ABadSceneFileAndABadTrackerAreNamedAndTheAudioPlaysOn) {
  if (run("command -v jackd").status != 0) GTEST_SKIP() << "jackd missing (apt-get install jackd2)";
  const std::string bad = "/tmp/earshot-e2e-bad-" + std::to_string(getpid()) + ".json";
  {
    std::ofstream f(bad);
    f << R"({"sources": [{"name": "x", "signal": {"type": "nois"}, "position": [0, 0, -1]}]})";
  }
  DummyJack jack;
  ASSERT_TRUE(jack.running()) << "jackd did not start; see " << jack.log();
  const auto r = run(std::string(EARSHOT_EXE) + " demo --scene " + bad +
                     " --device system --tracker carrier-pigeon --duration 2 </dev/null");
  std::printf("%s\n", r.output.c_str());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(bad), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nois"), std::string::npos) << "names the bad value: " << r.output;
  EXPECT_NE(r.output.find("playing circles instead"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("tracker carrier-pigeon failed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("played 2.0 s"), std::string::npos) << r.output;
  std::remove(bad.c_str());
}

TEST(DemoEndToEnd, CirclesWithReverbKeepsTheAudioThreadUnderAQuarterOfACore) {
  if (run("command -v jackd").status != 0) GTEST_SKIP() << "jackd missing (apt-get install jackd2)";
  DummyJack jack;
  ASSERT_TRUE(jack.running()) << "jackd did not start; see " << jack.log();
  const auto r = run(std::string(EARSHOT_EXE) +
                     " demo --scene circles --device system --buffer 128 --tracker sim --duration 30 </dev/null");
  std::printf("%s\n", r.output.c_str());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(field(r.output, R"(blocks, (\d+) xruns)"), 0.0);
  const double mean = field(r.output, R"(load mean ([0-9.]+)%)");
  ASSERT_GE(mean, 0.0) << r.output;
  EXPECT_LT(mean, 25.0);
}

}  // namespace
