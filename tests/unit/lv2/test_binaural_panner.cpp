// The LV2 plugin's DSP alone (lv2/src/binaural_panner.hpp) and its process
// registry of trackers (shared_tracker.hpp): latency, block-size
// independence, the azimuth convention, equality with the renderer it
// wraps, and no allocation or lock in update() / process().
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>
#include <numeric>
#include <random>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "binaural_cues.hpp"
#include "binaural_panner.hpp"
#include "bypass.hpp"
#include "head_controls.hpp"
#include "panner_switch.hpp"
#include "earshot/audio/hrtf_cache.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "shared_tracker.hpp"

using namespace earshot;
using namespace earshot::lv2;

namespace {

constexpr double kRate = 48000.0;

audio::PreparedHrtf kemar() {
  return audio::HrtfCache::shared().get(hrtf::HrtfSet::kDefaultPath, kRate, BinauralPanner::kBlock);
}

std::vector<float> noise(std::size_t n, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> d(0.0f, 0.1f);
  std::vector<float> v(n);
  for (auto& x : v) x = d(rng);
  return v;
}

struct Stereo {
  std::vector<float> left, right;
};

/// Runs `in` through a fresh panner in host blocks of `host_block` frames.
Stereo run(const std::vector<float>& in, std::size_t host_block, const PannerParams& p) {
  BinauralPanner panner(kemar(), kRate);
  panner.update(p);
  Stereo out{std::vector<float>(in.size()), std::vector<float>(in.size())};
  for (std::size_t i = 0; i < in.size(); i += host_block) {
    const std::size_t n = std::min(host_block, in.size() - i);
    panner.process(in.data() + i, out.left.data() + i, out.right.data() + i, n);
  }
  return out;
}

PannerParams at(double azimuth_deg) {
  PannerParams p;
  p.azimuth_deg = azimuth_deg;
  return p;
}

}  // namespace

TEST(BinauralPanner, PositionFollowsTheSofaAzimuthConvention) {
  const Vec3 left = position_of(90, 0, 2);
  EXPECT_NEAR(left[0], -2.0, 1e-12);  // +90 degrees: the listener's left (-x)
  const Vec3 ahead = position_of(0, 0, 1);
  EXPECT_NEAR(ahead[2], -1.0, 1e-12);
  const Vec3 up = position_of(0, 90, 1);
  EXPECT_NEAR(up[1], 1.0, 1e-12);
}

TEST(BinauralPanner, OutputIsTheInputOneBlockLaterWhateverTheHostBlock) {
  const auto in = noise(48000 / 4);
  const Stereo ref = run(in, BinauralPanner::kBlock, at(30));
  // The first block is the FIFO's silence: the latency the port reports.
  for (std::size_t i = 0; i < BinauralPanner::kBlock; ++i) ASSERT_EQ(ref.left[i], 0.0f);
  double energy = 0;
  for (float x : ref.left) energy += double(x) * x;
  ASSERT_GT(energy, 1.0);
  for (std::size_t host : {1u, 37u, 64u, 1000u, 4096u}) {
    const Stereo o = run(in, host, at(30));
    for (std::size_t i = 0; i < in.size(); ++i) {
      ASSERT_EQ(o.left[i], ref.left[i]) << "host block " << host << " frame " << i;
      ASSERT_EQ(o.right[i], ref.right[i]) << "host block " << host << " frame " << i;
    }
  }
}

TEST(BinauralPanner, InPlaceBuffersGiveTheSameOutput) {
  const auto in = noise(4096);
  const Stereo ref = run(in, 256, at(-45));
  BinauralPanner panner(kemar(), kRate);
  panner.update(at(-45));
  std::vector<float> left = in, right(in.size());
  for (std::size_t i = 0; i < in.size(); i += 256)
    panner.process(left.data() + i, left.data() + i, right.data() + i, 256);  // input aliased to the left output
  EXPECT_EQ(left, ref.left);
  EXPECT_EQ(right, ref.right);
}

TEST(BinauralPanner, IsTheRendererDelayedByOneBlock) {
  const auto in = noise(BinauralPanner::kBlock * 40);
  const Stereo o = run(in, 512, at(60));
  audio::RendererConfig c;
  c.sample_rate = kRate;
  c.block = BinauralPanner::kBlock;
  c.max_sources = 1;
  c.doppler_factor = 0.0;
  audio::Renderer r(kemar(), c);
  audio::SourceState s;
  s.position = position_of(60, 0, 1);
  const int src = r.add_source(s);
  std::vector<float> l(c.block), rr(c.block);
  for (std::size_t b = 0; b + 1 < in.size() / c.block; ++b) {
    std::copy_n(in.begin() + static_cast<std::ptrdiff_t>(b * c.block), c.block, r.source_input(src).begin());
    r.render(l, rr);
    for (std::size_t i = 0; i < c.block; ++i) {
      ASSERT_EQ(o.left[(b + 1) * c.block + i], l[i]) << "block " << b;
      ASSERT_EQ(o.right[(b + 1) * c.block + i], rr[i]) << "block " << b;
    }
  }
}

TEST(BinauralPanner, PositiveAzimuthIsHeardOnTheLeftAndYawTurnsTheHead) {
  const auto in = noise(48000 / 2);
  const Stereo left = run(in, 128, at(60));
  EXPECT_GT(analysis::ild_db(left.left, left.right), 6.0);
  EXPECT_GT(analysis::itd_s(left.left, left.right, kRate), 300e-6);
  // The head turned 60 degrees left faces the source: no cue left.
  PannerParams faced = at(60);
  faced.head_orientation = quat_from_ypr(60 * std::numbers::pi / 180, 0, 0);
  const Stereo ahead = run(in, 128, faced);
  EXPECT_LT(std::abs(analysis::ild_db(ahead.left, ahead.right)), 1.0);
  EXPECT_LT(std::abs(analysis::itd_s(ahead.left, ahead.right, kRate)), 30e-6);
}

TEST(BinauralPanner, RoomAddsATailThatStopsWithoutIt) {
  const std::size_t n = 48000;
  std::vector<float> in(n, 0.0f);
  in[0] = 1.0f;
  PannerParams p = at(0);
  p.room = 8;  // concert-hall in the reference table's order
  p.reverb_send_db = 0.0;
  const Stereo wet = run(in, 128, p);
  p.room = 0;
  const Stereo dry = run(in, 128, p);
  auto tail = [](const std::vector<float>& x) {
    double e = 0;
    for (std::size_t i = 24000; i < x.size(); ++i) e += double(x[i]) * x[i];
    return e;
  };
  EXPECT_GT(tail(wet.left), 1e-6);
  EXPECT_LT(tail(dry.left), 1e-10);
}

TEST(BinauralPanner, UpdateAndProcessNeverAllocateOrLock) {
  BinauralPanner panner(kemar(), kRate);
  const auto in = noise(4096);
  std::vector<float> l(in.size()), r(in.size());
  panner.process(in.data(), l.data(), r.data(), in.size());  // warm
  earshot::testing::AllocationProbe probe;
  for (int i = 0; i < 64; ++i) {
    PannerParams p = at(i * 11.0);
    p.room = i % 5;  // rooms switched while playing
    p.head_orientation = quat_from_ypr(i * 0.1, 0.05, 0.0);
    p.distance_m = 0.5 + i * 0.1;
    panner.update(p);
    panner.process(in.data(), l.data(), r.data(), 1 + (static_cast<std::size_t>(i) * 97) % in.size());
  }
  EXPECT_EQ(probe.count(), 0u);
  EXPECT_EQ(probe.lock_count(), 0u);
}

TEST(SharedTrackers, InstancesAskingForOneSpecShareOneTracker) {
  SharedTrackers& trackers = SharedTrackers::process();
  const std::size_t before = trackers.running();
  {
    auto a = trackers.acquire("sim");
    auto b = trackers.acquire("sim");
    EXPECT_EQ(a.get(), b.get());
    EXPECT_EQ(trackers.running(), before + 1);
    // It publishes poses the audio thread can read.
    HeadPose p;
    for (int i = 0; i < 300 && p.sequence == 0; ++i) {
      if (auto q = a->slot.try_load()) p = *q;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_GT(p.sequence, 0u);
  }
  EXPECT_EQ(trackers.running(), before);
}

// One tracker per spec, so instances that share it share where it sends:
// the first decides, a later one asking for another list is told so.
TEST(SharedTrackers, InstancesSharingATrackerShareWhereItSends) {
  SharedTrackers& trackers = SharedTrackers::process();
  std::string note;
  auto a = trackers.acquire("sim", "osc:127.0.0.1:39001,format=sparta", &note);
  EXPECT_TRUE(note.empty()) << note;
  EXPECT_EQ(a->head->tracker().senders().senders().size(), 1u);
  auto b = trackers.acquire("sim", "osc:127.0.0.1:39001,format=sparta", &note);
  EXPECT_EQ(a.get(), b.get());
  EXPECT_TRUE(note.empty()) << note;
  auto c = trackers.acquire("sim", "opentrack", &note);
  EXPECT_EQ(a.get(), c.get());
  EXPECT_NE(note.find("already runs in this process, sending to 'osc:127.0.0.1:39001,format=sparta'"), std::string::npos)
      << note;
  try {
    (void)trackers.acquire("sim:1", "osc:70000");
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("sim"), std::string::npos) << e.what();
  }
  try {
    (void)trackers.acquire("replay:/nonexistent.csv", "osc:70000");
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("send 'osc:70000': bad UDP port"), std::string::npos) << e.what();
  }
}

// IEM SceneRotator's invert switches and rotation order (head_controls.hpp).
TEST(HeadControls, InvertEachAngleAndComposeInEitherOrder) {
  constexpr double d = std::numbers::pi / 180.0;
  const Quat head = quat_from_ypr(40 * d, -15 * d, 10 * d);
  EXPECT_EQ(adjust_head(head, {}), head) << "no switch: the head as it is";
  auto angles = [](const Quat& q) {
    const YawPitchRoll a = ypr_from_quat(q);
    return std::array<double, 3>{a.yaw / d, a.pitch / d, a.roll / d};
  };
  const auto y = angles(adjust_head(head, {true, false, false, 0}));
  EXPECT_NEAR(y[0], -40, 1e-9);
  EXPECT_NEAR(y[1], -15, 1e-9);
  EXPECT_NEAR(y[2], 10, 1e-9);
  const auto p = angles(adjust_head(head, {false, true, false, 0}));
  EXPECT_NEAR(p[1], 15, 1e-9);
  const auto r = angles(adjust_head(head, {false, false, true, 0}));
  EXPECT_NEAR(r[2], -10, 1e-9);
  // Roll first: the same three turns the other way round.
  const Quat rpy = adjust_head(head, {false, false, false, 1});
  const Quat want = multiply(multiply(quat_from_ypr(0, 0, 10 * d), quat_from_ypr(0, -15 * d, 0)), quat_from_ypr(40 * d, 0, 0));
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(rpy[i], want[i], 1e-12);
  // A single turn is the same in either order.
  const Quat yaw_only = quat_from_ypr(30 * d, 0, 0);
  const Quat same = adjust_head(yaw_only, {false, false, false, 1});
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(same[i], yaw_only[i], 1e-12);
}

// The bypass (bypass.hpp): off, the input delayed by the latency on both
// channels, exactly; the fade is monotonic and lasts kFadeFrames; in place
// (the input buffer is the left output) gives the same output.
TEST(Bypass, DryIsTheInputDelayedAndTheFadeIsSmooth) {
  constexpr std::size_t kLatency = 128, kN = 4000;
  std::vector<float> in(kN);
  std::mt19937 rng(4);
  std::normal_distribution<float> g(0.0f, 0.1f);
  for (auto& x : in) x = g(rng);
  const auto wet = [](const float* i, float* l, float* r, std::uint32_t n) {
    for (std::uint32_t k = 0; k < n; ++k) l[k] = r[k] = 0.5f * i[k];  // a stand-in renderer
  };
  Bypass b(kLatency);
  b.reset(false);
  std::vector<float> l(kN), r(kN);
  b.process(in.data(), l.data(), r.data(), 1000, false, wet);  // odd chunking: 1000 frames, then the rest
  b.process(in.data() + 1000, l.data() + 1000, r.data() + 1000, 3000, false, wet);
  for (std::size_t i = kLatency; i < kN; ++i) {
    ASSERT_EQ(l[i], in[i - kLatency]) << i;
    ASSERT_EQ(r[i], in[i - kLatency]) << i;
  }
  // In place, switched on: the fade from dry to wet over kFadeFrames, then wet.
  Bypass c(kLatency), d(kLatency);
  c.reset(false);
  d.reset(false);
  std::vector<float> inplace = in, l2(kN), r2(kN), ref_l(kN), ref_r(kN);
  c.process(inplace.data(), inplace.data(), r2.data(), kN, true, wet);
  d.process(in.data(), ref_l.data(), ref_r.data(), kN, true, wet);
  for (std::size_t i = 0; i < kN; ++i) ASSERT_EQ(inplace[i], ref_l[i]) << i;
  EXPECT_EQ(d.wet(), 1.0f);
  for (std::size_t i = Bypass::kFadeFrames; i < kN; ++i) ASSERT_EQ(ref_l[i], 0.5f * in[i]) << i;
  // Bounded: never beyond the larger of the two signals it mixes.
  for (std::size_t i = kLatency; i < kN; ++i)
    EXPECT_LE(std::abs(ref_l[i]), std::max(std::abs(0.5f * in[i]), std::abs(in[i - kLatency])) + 1e-6f) << i;
}

TEST(SharedTrackers, ABadSpecIsAnErrorNamingIt) {
  try {
    (void)SharedTrackers::process().acquire("bogus:1");
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("bogus"), std::string::npos) << e.what();
  }
}

namespace {

/// A set other than KEMAR, written by the fixture tool (once per process).
audio::PreparedHrtf synthetic_set() {
  // Per process (ctest runs each test in its own), removed when it ends.
  struct TempSofa {
    std::string path;
    TempSofa() : path((std::filesystem::temp_directory_path() / ("earshot_switch_test_" + std::to_string(getpid()) + ".sofa")).string()) {
      const std::string cmd = std::string("/usr/bin/python3 ") + EARSHOT_MAKE_SOFA + " --out '" + path +
                              "' --length 64 --grid fibonacci:300";
      if (std::system(cmd.c_str()) != 0) throw std::runtime_error("make_sofa.py failed: " + cmd);
    }
    ~TempSofa() { std::filesystem::remove(path); }
  };
  static const TempSofa file;
  const std::string& path = file.path;
  return audio::HrtfCache::shared().get(path, kRate, BinauralPanner::kBlock);
}

std::vector<float> tone(std::size_t n, double hz) {
  std::vector<float> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<float>(0.2 * std::sin(2 * std::numbers::pi * hz * double(i) / kRate));
  return v;
}

/// Largest sample-to-sample step of `x` in [from, to).
double largest_step(const std::vector<float>& x, std::size_t from, std::size_t to) {
  double m = 0;
  for (std::size_t i = from + 1; i < to; ++i) m = std::max(m, std::abs(double(x[i]) - double(x[i - 1])));
  return m;
}

}  // namespace

TEST(PannerSwitch, SwitchingSetsWhilePlayingLeavesNoGapAndNoStep) {
  const auto in = tone(48000, 300.0);
  const std::size_t when = 9000;  // the switch, mid host block
  PannerSwitch panners(std::make_unique<BinauralPanner>(kemar(), kRate));
  panners.update(at(30));
  std::vector<float> l(in.size()), r(in.size());
  std::unique_ptr<BinauralPanner> finished;
  for (std::size_t i = 0; i < in.size(); i += 100) {
    const std::size_t n = std::min<std::size_t>(100, in.size() - i);
    if (i <= when && when < i + n) {
      (void)panners.switch_to(std::make_unique<BinauralPanner>(synthetic_set(), kRate));
      panners.update(at(30));
    }
    panners.process(in.data() + i, l.data() + i, r.data() + i, n);
    if (auto f = panners.finished()) finished = std::move(f);
  }
  ASSERT_TRUE(finished) << "the old panner was never released";
  EXPECT_FALSE(panners.switching());
  // No gap: every 128-frame window after the switch keeps most of the level.
  auto rms = [&](std::size_t from) {
    double e = 0;
    for (std::size_t i = from; i < from + 128; ++i) e += double(l[i]) * l[i];
    return std::sqrt(e / 128);
  };
  const double before = rms(when - 1000);
  for (std::size_t w = when; w < when + 3000; w += 64) EXPECT_GT(rms(w), 0.5 * before) << "frame " << w;
  // No step: a 300 Hz tone changes by at most ~0.2 * 2 pi 300 / 48000 per
  // sample (times the set's gain); the switch may not add a jump beyond that.
  // The two sets differ in level: the bound is the larger steady slope.
  const double steady = std::max(largest_step(l, 4000, 8000), largest_step(l, when + 4000, when + 8000));
  EXPECT_LT(largest_step(l, when, when + 3000), 1.5 * steady);
}

TEST(PannerSwitch, ToTheSameSetTheOutputIsUnchangedAfterTheWarmUp) {
  const auto in = noise(20000);
  BinauralPanner reference(kemar(), kRate);
  reference.update(at(-70));
  std::vector<float> rl(in.size()), rr(in.size());
  reference.process(in.data(), rl.data(), rr.data(), in.size());

  PannerSwitch panners(std::make_unique<BinauralPanner>(kemar(), kRate));
  panners.update(at(-70));
  std::vector<float> l(in.size()), r(in.size());
  panners.process(in.data(), l.data(), r.data(), 5000);
  (void)panners.switch_to(std::make_unique<BinauralPanner>(kemar(), kRate));
  panners.update(at(-70));
  panners.process(in.data() + 5000, l.data() + 5000, r.data() + 5000, in.size() - 5000);
  // Until the fade both are the old panner's; the new one, after 1024+ frames of
  // the same input, has the same history within the HRIR's length.
  for (std::size_t i = 0; i < 5000 + PannerSwitch::kWarm; ++i) ASSERT_EQ(l[i], rl[i]) << i;
  for (std::size_t i = 5000 + PannerSwitch::kWarm + PannerSwitch::kFade + 2048; i < in.size(); ++i)
    ASSERT_NEAR(l[i], rl[i], 1e-4) << i;
}
