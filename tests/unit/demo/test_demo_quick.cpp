// Quick checks of `earshot demo`'s error and fallback paths (no audio server).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "demo_run.hpp"
#include "../scratch_path.hpp"

namespace {

using earshot::testing::run;

TEST(DemoQuick, WithoutASoundCardItSaysSoAndRendersAWav) {
  if (std::filesystem::exists("/proc/asound/pcm") && std::filesystem::file_size("/proc/asound/pcm") > 0)
    GTEST_SKIP() << "this machine has a sound card";
  const std::filesystem::path out = earshot::test::scratch_path("demo-quick.wav");
  std::filesystem::remove(out);
  const auto r = run(std::string(EARSHOT_EXE) + " demo --duration 1 --out " + out.string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("no audio device"), std::string::npos) << r.output;
  EXPECT_GT(std::filesystem::file_size(out), 48000u * 2u) << r.output;
}

TEST(DemoQuick, ADeviceAskedForWhereThereIsNoneIsNamedAndItRendersAWav) {
  setenv("JACK_DEFAULT_SERVER", "earshot-no-such-server", 1);
  setenv("JACK_NO_START_SERVER", "1", 1);
  const std::filesystem::path out = earshot::test::scratch_path("demo-nodev.wav");
  std::filesystem::remove(out);
  const auto r = run(std::string(EARSHOT_EXE) + " demo --device no-such-device --duration 1 --out " + out.string());
  if (r.output.find("Output devices") != std::string::npos || r.output.find("earshot demo: playing") != std::string::npos)
    GTEST_SKIP() << "this machine has audio output devices";
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("no audio output device (asked for 'no-such-device')"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(out)) << r.output;
}

TEST(DemoQuick, AnUnknownSceneIsNamedAndNothingCrashes) {
  const auto r = run(std::string(EARSHOT_EXE) + " demo --scene no-such-scene --duration 1");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("no-such-scene"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("Segmentation"), std::string::npos) << r.output;
}

TEST(DemoQuick, HelpListsTheKeys) {
  const auto r = run(std::string(EARSHOT_EXE) + " demo --help");
  EXPECT_EQ(r.status, 0);
  // The keys of keys.hpp, which the window and the terminal print too.
  for (const char* key : {"r recenter the head", "n next scene preset", "m next room preset", "q or Esc quit"})
    EXPECT_NE(r.output.find(key), std::string::npos) << key << " missing from:\n" << r.output;
  EXPECT_NE(r.output.find("--buffer"), std::string::npos) << r.output;
}

}  // namespace
