// Early reflections against the room parameters that define them, for every
// preset: the first tap at the preset's reflections delay, eight taps within
// ~20 ms (a shorter spread for a less dense room), each louder in one ear,
// the taps' energy summed over both ears equal to reflections_gain^2, left
// and right patterns nearly uncorrelated; output added to what is there;
// block size and reset() do not change the result; no allocation in
// process() or update().
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "earshot/audio/early_reflections.hpp"
#include "earshot/audio/room_presets.hpp"

using namespace earshot::audio;

namespace {

constexpr double kFs = 48000.0;
constexpr std::size_t kBlock = 128;

struct Stereo {
  std::vector<float> left, right;
};

/// `in` through a fresh EarlyReflections in blocks of `block`, `frames` long.
Stereo run(const RoomParams& p, const std::vector<float>& in, std::size_t frames, std::size_t block = kBlock) {
  EarlyReflections er(kFs, block);
  er.update(p);
  Stereo out{std::vector<float>(frames, 0.0f), std::vector<float>(frames, 0.0f)};
  std::vector<float> x(block);
  for (std::size_t done = 0; done < frames; done += block) {
    const std::size_t n = std::min(block, frames - done);
    for (std::size_t i = 0; i < n; ++i) x[i] = done + i < in.size() ? in[done + i] : 0.0f;
    er.process(std::span(x).first(n), std::span(out.left).subspan(done, n), std::span(out.right).subspan(done, n));
  }
  return out;
}

Stereo impulse_response(const RoomParams& p, std::size_t block = kBlock) {
  return run(p, {1.0f}, static_cast<std::size_t>(0.4 * kFs), block);
}

double energy(const std::vector<float>& x) {
  double e = 0;
  for (float v : x) e += double(v) * v;
  return e;
}

/// Sample indices where either ear is not zero.
std::vector<std::size_t> taps(const Stereo& s) {
  std::vector<std::size_t> t;
  for (std::size_t i = 0; i < s.left.size(); ++i)
    if (s.left[i] != 0.0f || s.right[i] != 0.0f) t.push_back(i);
  return t;
}

}  // namespace

TEST(EarlyReflections, EveryPresetsTapsFollowItsDelayGainAndDensity) {
  for (const auto& preset : room_presets()) {
    const RoomParams& p = preset.params;
    SCOPED_TRACE(preset.name);
    const Stereo ir = impulse_response(p);
    const auto t = taps(ir);
    if (p.reflections_gain == 0.0) {  // the quarry: no early reflections at all
      EXPECT_TRUE(t.empty());
      continue;
    }
    ASSERT_EQ(t.size(), EarlyReflections::kTaps);
    // The first reflection arrives reflections_delay_s after the direct sound.
    EXPECT_EQ(t.front(), static_cast<std::size_t>(std::lround(p.reflections_delay_s * kFs)));
    // The rest within 20 ms of it, closer together in a less dense room
    // (density 1: up to 20 ms; density 0: 0.4 of that).
    const double span_s = double(t.back() - t.front()) / kFs;
    EXPECT_LE(span_s, 0.020 * (0.4 + 0.6 * p.density) + 1.0 / kFs);
    EXPECT_GE(span_s, 0.010 * (0.4 + 0.6 * p.density));
    // Energy: the taps' energies, both ears together, add up to gain^2.
    const double g2 = p.reflections_gain * p.reflections_gain;
    const double el = energy(ir.left), er = energy(ir.right);
    EXPECT_NEAR(el + er, g2, 0.01 * g2);
    EXPECT_GT(el, 0.35 * g2);  // and it is shared between the ears, not all in one
    EXPECT_GT(er, 0.35 * g2);
    // Taps alternate the louder ear: left, right, left...
    for (std::size_t k = 0; k < t.size(); ++k) {
      const float l = std::abs(ir.left[t[k]]), r = std::abs(ir.right[t[k]]);
      if (k % 2 == 0) EXPECT_GT(l, 1.5f * r) << "tap " << k;
      else EXPECT_GT(r, 1.5f * l) << "tap " << k;
    }
    // The ears' patterns are different: a low normalised correlation.
    double lr = 0;
    for (std::size_t i : t) lr += double(ir.left[i]) * ir.right[i];
    EXPECT_LT(std::abs(lr) / std::sqrt(el * er), 0.2);
    // And later reflections are weaker.
    const auto level = [&](std::size_t k) { return std::hypot(ir.left[t[k]], ir.right[t[k]]); };
    EXPECT_GT(level(0), level(t.size() - 1));
  }
}

TEST(EarlyReflections, DelayAndGainFollowUpdatesAndAreClamped) {
  RoomParams p = room_preset("generic");
  for (double delay : {0.0, 0.001, 0.05, 0.3}) {
    p.reflections_delay_s = delay;
    EXPECT_EQ(taps(impulse_response(p)).front(), static_cast<std::size_t>(std::lround(delay * kFs))) << delay;
  }
  p.reflections_gain = 0.0;
  EXPECT_TRUE(taps(impulse_response(p)).empty());
  p.reflections_gain = 2.0;
  auto ir = impulse_response(p);
  EXPECT_NEAR(energy(ir.left) + energy(ir.right), 4.0, 0.04);
  // Beyond the EFX ranges: the largest gain and delay, not more.
  p.reflections_gain = 10.0, p.reflections_delay_s = 1.0;
  ir = impulse_response(p);
  EXPECT_NEAR(energy(ir.left) + energy(ir.right), 3.16 * 3.16, 0.1);
  EXPECT_EQ(taps(ir).front(), static_cast<std::size_t>(std::lround(0.3 * kFs)));
  // Density 0 puts the taps 0.4 times as far apart as density 1.
  p = room_preset("generic");
  p.density = 1.0;
  const auto wide = taps(impulse_response(p));
  p.density = 0.0;
  const auto narrow = taps(impulse_response(p));
  ASSERT_EQ(wide.size(), narrow.size());
  for (std::size_t k = 1; k < wide.size(); ++k)
    EXPECT_NEAR(double(narrow[k] - narrow[0]), 0.4 * double(wide[k] - wide[0]), 1.0) << k;
}

TEST(EarlyReflections, IsLinearAddsToTheOutputAndIgnoresTheBlockSize) {
  const RoomParams& p = room_preset("stone-room");
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> in(20000);
  for (auto& v : in) v = u(rng);
  const Stereo a = run(p, in, 24000, 128), b = run(p, in, 24000, 1), c = run(p, in, 24000, 100);
  EXPECT_EQ(a.left, b.left);
  EXPECT_EQ(a.right, b.right);
  EXPECT_EQ(a.left, c.left);
  // Noise in, the sum of the impulse response's taps applied to it out.
  const Stereo h = impulse_response(p);
  for (std::size_t n : {100u, 5000u, 19999u}) {
    double want = 0;
    for (std::size_t k : taps(h))
      if (k <= n) want += double(h.left[k]) * in[n - k];
    EXPECT_NEAR(a.left[n], want, 1e-5) << n;
  }
  // process() adds into the outputs.
  EarlyReflections er(kFs, kBlock);
  er.update(p);
  std::vector<float> x(kBlock, 0.0f), l(kBlock, 0.5f), r(kBlock, -0.25f);
  er.process(x, l, r);
  EXPECT_TRUE(std::all_of(l.begin(), l.end(), [](float v) { return v == 0.5f; }));
  EXPECT_TRUE(std::all_of(r.begin(), r.end(), [](float v) { return v == -0.25f; }));
}

TEST(EarlyReflections, ResetForgetsThePast) {
  const RoomParams& p = room_preset("hangar");
  EarlyReflections er(kFs, kBlock);
  er.update(p);
  std::vector<float> x(kBlock, 1.0f), l(kBlock), r(kBlock);
  for (int i = 0; i < 50; ++i) er.process(x, l, r);
  er.reset();
  std::fill(x.begin(), x.end(), 0.0f);
  for (int i = 0; i < 200; ++i) {
    std::fill(l.begin(), l.end(), 0.0f);
    std::fill(r.begin(), r.end(), 0.0f);
    er.process(x, l, r);
    ASSERT_TRUE(std::all_of(l.begin(), l.end(), [](float v) { return v == 0.0f; })) << "block " << i;
    ASSERT_TRUE(std::all_of(r.begin(), r.end(), [](float v) { return v == 0.0f; })) << "block " << i;
  }
}

TEST(EarlyReflections, ProcessAndUpdateNeverAllocate) {
  EarlyReflections er(kFs, kBlock);
  std::vector<float> x(kBlock, 0.1f), l(kBlock), r(kBlock);
  const auto presets = room_presets();
  earshot::testing::AllocationProbe probe;
  for (std::size_t i = 0; i < 100; ++i) {
    er.update(presets[i % presets.size()].params);
    er.process(x, l, r);
  }
  EXPECT_EQ(probe.count(), 0u);
  EXPECT_EQ(probe.lock_count(), 0u);
}
