#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "binaural_cues.hpp"
#include "earshot/audio/renderer.hpp"

using namespace earshot::audio;
using earshot::HeadPose;
using earshot::quat_from_ypr;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::shared_ptr<const earshot::hrtf::HrtfSet> kemar() {
  static const auto set = std::make_shared<const earshot::hrtf::HrtfSet>(earshot::hrtf::HrtfSet::load_default(48000));
  return set;
}

struct Stereo {
  std::vector<float> l, r;
};

/// Renders `blocks` blocks of white noise from one source.
Stereo render_noise(const SourceState& src, const HeadPose& listener, int blocks = 200, unsigned seed = 1,
                    RendererConfig cfg = {}) {
  Renderer r(kemar(), cfg);
  const int id = r.add_source(src);
  r.set_listener(listener);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.05f, 0.05f);  // well below the limiter
  Stereo out;
  std::vector<float> l(r.block()), rr(r.block());
  for (int b = 0; b < blocks; ++b) {
    for (float& x : r.source_input(id)) x = u(rng);
    r.render(l, rr);
    out.l.insert(out.l.end(), l.begin(), l.end());
    out.r.insert(out.r.end(), rr.begin(), rr.end());
  }
  return out;
}

double rms_db(const std::vector<float>& x, std::size_t from) {
  double e = 0;
  for (std::size_t i = from; i < x.size(); ++i) e += double(x[i]) * x[i];
  return 10 * std::log10(e / double(x.size() - from));
}

/// ITD in microseconds (positive: left ear leads) from the cross-correlation peak.
double itd_us(const Stereo& s, std::size_t from) {
  auto c = [&](int k) {
    double acc = 0;
    for (std::size_t n = from; n + 60 < s.l.size(); ++n) acc += double(s.l[n]) * s.r[std::size_t(long(n) + k)];
    return acc;
  };
  int best = 0;
  double bv = -1e300;
  for (int k = -50; k <= 50; ++k)
    if (double v = c(k); v > bv) bv = v, best = k;
  const double a = c(best - 1), b = c(best + 1), den = a - 2 * bv + b;
  return (best + (den < 0 ? 0.5 * (a - b) / den : 0.0)) / 48000.0 * 1e6;
}

}  // namespace

TEST(HeadRelative, AppliesYawPitchAndRoll) {
  HeadPose l;
  EXPECT_NEAR(head_relative({-1, 0, 0}, l).azimuth, 90 * kDeg, 1e-12);  // OpenAL -x = SOFA left
  l.orientation = quat_from_ypr(90 * kDeg, 0, 0);  // head turned left, towards it
  EXPECT_NEAR(head_relative({-1, 0, 0}, l).azimuth, 0.0, 1e-12);
  l.orientation = quat_from_ypr(0, 90 * kDeg, 0);  // looking up
  const auto up = head_relative({0, 1, 0}, l);
  EXPECT_NEAR(up.azimuth, 0.0, 1e-9);
  EXPECT_NEAR(up.elevation, 0.0, 1e-9);
  l.orientation = quat_from_ypr(0, 0, 90 * kDeg);  // tilted onto the right shoulder
  EXPECT_NEAR(head_relative({1, 0, 0}, l).elevation, 90 * kDeg, 1e-9);
  l = HeadPose{};
  l.position = {0, 0, 2};
  EXPECT_NEAR(head_relative({0, 0, -1}, l).distance, 3.0, 1e-12);
}

TEST(Renderer, ASourceOnTheLeftIsHeardOnTheLeftAndAheadOnceFaced) {
  SourceState src;
  src.position = {-1, 0, 0};
  const Stereo side = render_noise(src, {});
  EXPECT_GT(rms_db(side.l, 4800) - rms_db(side.r, 4800), 6.0);
  EXPECT_GT(itd_us(side, 4800), 500.0);  // left ear leads by over half a millisecond

  HeadPose turned;
  turned.orientation = quat_from_ypr(90 * kDeg, 0, 0);
  const Stereo ahead = render_noise(src, turned);
  EXPECT_LT(std::abs(rms_db(ahead.l, 4800) - rms_db(ahead.r, 4800)), 1.0);
  EXPECT_LT(std::abs(itd_us(ahead, 4800)), 25.0);
}

TEST(Renderer, ListenerTranslationChangesGainByTheDistanceModel) {
  SourceState src;
  src.position = {0, 0, -1};
  HeadPose near_l, far_l;
  far_l.position = {0, 0, 1};  // two metres from the source
  // No propagation delay here, so both renders hold the same noise samples;
  // no near field (KEMAR is measured at 1.4 m: the 1 m source would get the
  // sphere's near-field level on top of the distance law tested here).
  RendererConfig cfg;
  cfg.doppler_factor = 0.0;
  cfg.near_field = false;
  const Stereo a = render_noise(src, near_l, 200, 1, cfg), b = render_noise(src, far_l, 200, 1, cfg);
  const double expect = 20 * std::log10(distance_gain(2.0, src.distance) / distance_gain(1.0, src.distance));
  EXPECT_NEAR(rms_db(b.l, 4800) - rms_db(a.l, 4800), expect, 0.01);
  EXPECT_NEAR(expect, -6.02, 0.01);
}

TEST(Renderer, IsDeterministic) {
  SourceState src;
  src.position = {0.5, 0.2, -1};
  const Stereo a = render_noise(src, {}, 50), b = render_noise(src, {}, 50);
  EXPECT_EQ(a.l, b.l);
  EXPECT_EQ(a.r, b.r);
}

TEST(Renderer, NeverExceedsFullScaleNorPassesNaN) {
  Renderer r(kemar(), {});
  std::vector<int> ids;
  SourceState loud;
  loud.gain = 20.0;
  for (int i = 0; i < 8; ++i) {
    loud.position = {std::cos(i), 0, std::sin(i)};
    ids.push_back(r.add_source(loud));
  }
  std::vector<float> l(r.block()), rr(r.block());
  for (int b = 0; b < 100; ++b) {
    for (int id : ids)
      for (float& x : r.source_input(id)) x = (b % 2) ? 1.0f : -1.0f;
    if (b == 50) r.source_input(ids[0])[3] = NAN;
    r.render(l, rr);
    for (std::size_t i = 0; i < l.size(); ++i) {
      ASSERT_TRUE(std::isfinite(l[i]) && std::isfinite(rr[i])) << "block " << b;
      ASSERT_LE(std::abs(l[i]), 1.0f);
      ASSERT_LE(std::abs(rr[i]), 1.0f);
    }
  }
}

TEST(Renderer, RenderTakesNoHeapAllocationNorLockWithManyMovingSources) {
  RendererConfig cfg;
  cfg.max_sources = 32;
  Renderer r(kemar(), cfg);
  std::vector<int> ids;
  for (int i = 0; i < 32; ++i) ids.push_back(r.add_source({}));
  std::vector<float> l(r.block()), rr(r.block());
  auto move = [&](int b) {
    for (int i = 0; i < 32; ++i) {
      SourceState s;
      const double a = 0.05 * b + i;
      s.position = {2 * std::cos(a), 0.3 * std::sin(0.1 * b), 2 * std::sin(a)};
      r.set_source(ids[static_cast<std::size_t>(i)], s);
      for (float& x : r.source_input(ids[static_cast<std::size_t>(i)])) x = 0.01f * float(i);
    }
    HeadPose L;
    L.orientation = quat_from_ypr(0.02 * b, 0, 0);
    r.set_listener(L);
  };
  move(0);
  r.render(l, rr);  // warm-up
  earshot::testing::AllocationProbe probe;
  for (int b = 1; b < 100; ++b) {
    move(b);
    r.render(l, rr);
  }
  EXPECT_EQ(probe.count(), 0u);
  EXPECT_EQ(probe.lock_count(), 0u);
}

TEST(DistanceModel, OpenAlFormulas) {
  DistanceParams p;
  p.reference_distance = 2;
  p.rolloff = 1.5;
  p.max_distance = 10;
  p.model = DistanceModel::inverse;
  EXPECT_DOUBLE_EQ(distance_gain(4, p), 2.0 / (2 + 1.5 * 2));
  p.model = DistanceModel::inverse_clamped;
  EXPECT_DOUBLE_EQ(distance_gain(1, p), 1.0);
  EXPECT_DOUBLE_EQ(distance_gain(20, p), 2.0 / (2 + 1.5 * 8));
  p.model = DistanceModel::linear_clamped;
  EXPECT_DOUBLE_EQ(distance_gain(6, p), 1 - 1.5 * 4 / 8);
  EXPECT_DOUBLE_EQ(distance_gain(30, p), 0.0);
  p.model = DistanceModel::exponent;
  EXPECT_DOUBLE_EQ(distance_gain(4, p), std::pow(2.0, -1.5));
  p.model = DistanceModel::none;
  EXPECT_DOUBLE_EQ(distance_gain(400, p), 1.0);
  EXPECT_EQ(distance_model_from("exponent-clamped"), DistanceModel::exponent_clamped);
  EXPECT_FALSE(distance_model_from("square").has_value());
}

namespace {

/// Cues of a rendered noise source: ILD (dB) and ITD (us, left leads > 0).
struct Cues {
  double ild_db, itd_us;
};
Cues cues_of(const SourceState& src, const HeadPose& listener) {
  const Stereo s = render_noise(src, listener, 150);
  const std::span<const float> l(s.l), r(s.r);
  return {earshot::analysis::ild_db(l.subspan(4800), r.subspan(4800)),
          earshot::analysis::itd_s(l.subspan(4800), r.subspan(4800), 48000.0) * 1e6};
}

}  // namespace

TEST(Renderer, HeadTrackingAppliesYawPitchAndRollToTheCues) {
  SourceState src;
  HeadPose l;
  // Yaw: a source on the left, the head turned +90 deg (left) towards it.
  src.position = {-1, 0, 0};
  const Cues side = cues_of(src, l);
  EXPECT_GT(side.ild_db, 6.0);
  EXPECT_GT(side.itd_us, 500.0);
  l.orientation = quat_from_ypr(90 * kDeg, 0, 0);
  Cues c = cues_of(src, l);
  EXPECT_LT(std::abs(c.ild_db), 1.0);
  EXPECT_LT(std::abs(c.itd_us), 25.0);
  // Pitch: a source straight above, the head looking up at it, sounds as a
  // source ahead of a level head does.
  src.position = {0, 1, 0};
  l.orientation = quat_from_ypr(0, 90 * kDeg, 0);
  c = cues_of(src, l);
  SourceState ahead;
  ahead.position = {0, 0, -1};
  const Cues front = cues_of(ahead, {});
  EXPECT_NEAR(c.ild_db, front.ild_db, 0.05);
  EXPECT_NEAR(c.itd_us, front.itd_us, 2.0);
  // Roll: a source on the right, the head tilted onto the right shoulder,
  // is now above the head: no interaural difference; and one above a tilted
  // head is on its left.
  src.position = {1, 0, 0};
  l.orientation = quat_from_ypr(0, 0, 90 * kDeg);
  c = cues_of(src, l);
  EXPECT_LT(std::abs(c.ild_db), 1.0);
  EXPECT_LT(std::abs(c.itd_us), 25.0);
  src.position = {0, 1, 0};
  c = cues_of(src, l);
  EXPECT_GT(c.ild_db, 6.0);
  EXPECT_GT(c.itd_us, 500.0);
}

TEST(Renderer, ListenerTranslationMovesTheSourceAcrossTheHead) {
  // Stepping 2 m to the right of a source 1 m ahead puts it front-left.
  SourceState src;
  src.position = {0, 0, -1};
  HeadPose l;
  l.position = {2, 0, 0};
  const Cues c = cues_of(src, l);
  EXPECT_GT(c.ild_db, 3.0);
  EXPECT_GT(c.itd_us, 300.0);
}

TEST(Renderer, AFastHeadTurnDoesNotClick) {
  // A 500 Hz sine 1 m ahead while the head yaws at 360 deg/s for 5 s, the
  // pose updated every 128-frame block: whatever the crossfades and delay
  // glides add above 2 kHz must stay 60 dB below the tone (issue 3; the
  // project's own target is 80 dB, measured in tests/bench/click_test).
  Renderer r(kemar(), {});
  SourceState src;
  src.position = {0, 0, -1};
  const int id = r.add_source(src);
  std::vector<float> left, right, l(r.block()), rr(r.block());
  const double rate = 48000.0;
  std::size_t n = 0;
  for (int b = 0; b < 5 * 48000 / 128; ++b) {
    HeadPose L;
    L.orientation = quat_from_ypr(2 * std::numbers::pi * double(n) / rate, 0, 0);
    r.set_listener(L);
    for (float& x : r.source_input(id)) x = 0.1f * float(std::sin(2 * std::numbers::pi * 500.0 * double(n++) / rate));
    r.render(l, rr);
    left.insert(left.end(), l.begin(), l.end());
    right.insert(right.end(), rr.begin(), rr.end());
  }
  const std::span<const float> sl(left), sr(right);
  const double el = earshot::analysis::energy_above_db(sl.subspan(4800), rate, 2000.0);
  const double er = earshot::analysis::energy_above_db(sr.subspan(4800), rate, 2000.0);
  RecordProperty("above_2khz_db", std::to_string(el) + " / " + std::to_string(er));
  std::printf("energy above 2 kHz: left %.1f dB, right %.1f dB\n", el, er);
  EXPECT_LT(el, -60.0);
  EXPECT_LT(er, -60.0);
}

namespace {
/// Frequency (Hz) of a tone from its rising zero crossings, interpolated.
double tone_hz(std::span<const float> x, double rate) {
  double first = -1, last = -1;
  int crossings = 0;
  for (std::size_t i = 1; i < x.size(); ++i)
    if (x[i - 1] < 0 && x[i] >= 0) {
      const double t = double(i - 1) + x[i - 1] / (x[i - 1] - x[i]);
      if (first < 0) first = t;
      else ++crossings;
      last = t;
    }
  return crossings * rate / (last - first);
}

/// A 1 kHz tone from a source approaching head-on at `speed` m/s.
double approaching_tone_hz(double speed, double doppler_factor) {
  RendererConfig cfg;
  cfg.doppler_factor = doppler_factor;
  Renderer r(kemar(), cfg);
  SourceState src;
  src.distance.model = DistanceModel::none;
  const int id = r.add_source(src);
  std::vector<float> left, l(r.block()), rr(r.block());
  std::size_t n = 0;
  for (int b = 0; b < 48000 / 128; ++b) {
    src.position = {0, 0, -(60.0 - speed * double(n) / 48000.0)};
    r.set_source(id, src);
    for (float& x : r.source_input(id)) x = 0.1f * float(std::sin(2 * std::numbers::pi * 1000.0 * double(n++) / 48000.0));
    r.render(l, rr);
    left.insert(left.end(), l.begin(), l.end());
  }
  return tone_hz(std::span<const float>(left).subspan(24000), 48000.0);
}
}  // namespace

TEST(Renderer, AMovingSourceIsDopplerShiftedAsOpenAlComputesIt) {
  // OpenAL: f' = f (c - DF vl) / (c - DF vs), here vl = 0, vs = 20 m/s towards.
  const double c = RendererConfig{}.speed_of_sound;
  EXPECT_NEAR(approaching_tone_hz(20.0, 1.0), 1000.0 * c / (c - 20.0), 0.5);
  EXPECT_NEAR(approaching_tone_hz(20.0, 2.0), 1000.0 * c / (c - 40.0), 0.5);
  EXPECT_NEAR(approaching_tone_hz(20.0, 0.0), 1000.0, 0.05);
}

TEST(Cone, OpenAlAnglesAndGains) {
  ConeParams c;
  c.direction = {0, 0, 1};  // pointing towards +z
  c.inner_angle_deg = 90;
  c.outer_angle_deg = 180;
  c.outer_gain = 0.2;
  EXPECT_DOUBLE_EQ(cone_gain({0, 0, 1}, c), 1.0);           // on axis
  EXPECT_DOUBLE_EQ(cone_gain({1, 0, 1}, c), 1.0);           // 45 deg: the inner edge
  EXPECT_NEAR(cone_gain({std::sqrt(3.0), 0, 1}, c), 1.0 + (0.2 - 1.0) * (60.0 - 45.0) / 45.0, 1e-12);  // 60 deg
  EXPECT_DOUBLE_EQ(cone_gain({1, 0, 0}, c), 0.2);           // 90 deg: the outer edge
  EXPECT_DOUBLE_EQ(cone_gain({0, 0, -1}, c), 0.2);          // behind
  c.direction = {0, 0, 0};
  EXPECT_DOUBLE_EQ(cone_gain({0, 0, -1}, c), 1.0);          // omnidirectional
}

TEST(Renderer, ConeAndGainLimitsShapeTheLevel) {
  SourceState src;
  src.position = {0, 0, -1};
  src.distance.model = DistanceModel::none;
  const double open = rms_db(render_noise(src, {}).l, 4800);
  src.cone.direction = {0, 0, -1};  // facing away from the listener at the origin
  src.cone.inner_angle_deg = 60;
  src.cone.outer_angle_deg = 120;
  src.cone.outer_gain = 0.1;
  EXPECT_NEAR(rms_db(render_noise(src, {}).l, 4800) - open, -20.0, 0.05);
  src.min_gain = 0.5;  // clamps the cone's attenuation
  EXPECT_NEAR(rms_db(render_noise(src, {}).l, 4800) - open, -6.02, 0.05);
}
