// The LV2 plugin's DSP alone (lv2/src/binaural_panner.hpp) and its process
// registry of trackers (shared_tracker.hpp): latency, block-size
// independence, the azimuth convention, equality with the renderer it
// wraps, and no allocation or lock in update() / process().
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "binaural_cues.hpp"
#include "binaural_panner.hpp"
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

TEST(SharedTrackers, ABadSpecIsAnErrorNamingIt) {
  try {
    (void)SharedTrackers::process().acquire("bogus:1");
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("bogus"), std::string::npos) << e.what();
  }
}
