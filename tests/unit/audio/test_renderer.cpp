#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "earshot/audio/renderer.hpp"

using namespace earshot::audio;

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
Stereo render_noise(const SourceState& src, const ListenerState& listener, int blocks = 200, unsigned seed = 1,
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
  ListenerState l;
  EXPECT_NEAR(head_relative({-1, 0, 0}, l).azimuth, 90 * kDeg, 1e-12);  // OpenAL -x = SOFA left
  l.orientation = quat_from_ypr(90 * kDeg, 0, 0);  // head turned left, towards it
  EXPECT_NEAR(head_relative({-1, 0, 0}, l).azimuth, 0.0, 1e-12);
  l.orientation = quat_from_ypr(0, 90 * kDeg, 0);  // looking up
  const auto up = head_relative({0, 1, 0}, l);
  EXPECT_NEAR(up.azimuth, 0.0, 1e-9);
  EXPECT_NEAR(up.elevation, 0.0, 1e-9);
  l.orientation = quat_from_ypr(0, 0, 90 * kDeg);  // tilted onto the right shoulder
  EXPECT_NEAR(head_relative({1, 0, 0}, l).elevation, 90 * kDeg, 1e-9);
  l = ListenerState{};
  l.position = {0, 0, 2};
  EXPECT_NEAR(head_relative({0, 0, -1}, l).distance, 3.0, 1e-12);
}

TEST(Renderer, ASourceOnTheLeftIsHeardOnTheLeftAndAheadOnceFaced) {
  SourceState src;
  src.position = {-1, 0, 0};
  const Stereo side = render_noise(src, {});
  EXPECT_GT(rms_db(side.l, 4800) - rms_db(side.r, 4800), 6.0);
  EXPECT_GT(itd_us(side, 4800), 500.0);  // left ear leads by over half a millisecond

  ListenerState turned;
  turned.orientation = quat_from_ypr(90 * kDeg, 0, 0);
  const Stereo ahead = render_noise(src, turned);
  EXPECT_LT(std::abs(rms_db(ahead.l, 4800) - rms_db(ahead.r, 4800)), 1.0);
  EXPECT_LT(std::abs(itd_us(ahead, 4800)), 25.0);
}

TEST(Renderer, ListenerTranslationChangesGainByTheDistanceModel) {
  SourceState src;
  src.position = {0, 0, -1};
  ListenerState near_l, far_l;
  far_l.position = {0, 0, 1};  // two metres from the source
  // No propagation delay here, so both renders hold the same noise samples.
  RendererConfig cfg;
  cfg.doppler_factor = 0.0;
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

TEST(Renderer, RenderMakesNoHeapAllocationWithManyMovingSources) {
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
    ListenerState L;
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
