// The Ambisonic tier inside the renderer (renderer.hpp with an
// AmbisonicBus): a source is its delayed, distance-weighted signal encoded
// from its head-relative direction and decoded once, exactly; the head's
// turn moves it; render() never allocates or locks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "earshot/audio/ambisonics/ambisonic_bus.hpp"
#include "earshot/audio/ambisonics/binaural_decoder.hpp"
#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"
#include "earshot/audio/ambisonics/encoder.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

using namespace earshot;

namespace {

constexpr double kBusRate = 48000.0;
constexpr std::size_t kBusBlock = 128;

struct TierFixture {
  std::shared_ptr<const hrtf::HrtfSet> set =
      std::make_shared<const hrtf::HrtfSet>(hrtf::HrtfSet::load_default(kBusRate));
  audio::PreparedHrtf prepared{set, std::make_shared<const audio::HrtfSpectra>(*set, kBusBlock)};
  ambisonics::DecoderFilters filters = ambisonics::design_binaural_decoder(*set, 3);

  audio::Renderer tier(std::size_t sources, double doppler = 0.0) const {
    audio::RendererConfig cfg;
    cfg.sample_rate = kBusRate;
    cfg.block = kBusBlock;
    cfg.max_sources = sources;
    cfg.doppler_factor = doppler;
    return audio::Renderer(prepared, cfg, std::make_unique<ambisonics::AmbisonicBus>(filters, kBusBlock, sources));
  }
};

const TierFixture& tier_fixture() {
  static const TierFixture f;
  return f;
}

}  // namespace

TEST(AmbisonicTier, IsTheSourceEncodedAndDecodedOnce) {
  const TierFixture& fx = tier_fixture();
  audio::Renderer r = fx.tier(1);
  audio::SourceState s;
  s.position = {-1.0, 0.0, -1.0};  // ahead-left, 1.41 m: inverse-clamped gain 1 / 1.41
  s.gain = 0.5;
  const int id = r.add_source(s);
  ASSERT_EQ(id, 0);
  EXPECT_NE(r.bus(), nullptr);
  EXPECT_EQ(r.convolutions(), 0u);

  // By hand: the signal 8 samples late (the delay line's fixed latency, no
  // propagation delay), gain x distance gain, encoded from 45 deg left, decoded.
  ambisonics::Encoder enc(3, kBusBlock);
  ambisonics::BinauralDecoder dec(fx.filters, kBusBlock);
  const double g = 0.5 / std::sqrt(2.0);
  enc.update(Vec3{1, 1, 0}, static_cast<float>(g));
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  std::vector<float> history(8, 0.0f), bus(16 * kBusBlock), el(kBusBlock), er(kBusBlock), l(kBusBlock), rr(kBusBlock);
  float worst = 0, peak = 0;
  for (int b = 0; b < 30; ++b) {
    auto in = r.source_input(id);
    for (float& x : in) x = u(rng);
    std::vector<float> late(history);
    late.insert(late.end(), in.begin(), in.end());
    history.assign(late.end() - 8, late.end());
    late.resize(kBusBlock);
    std::fill(bus.begin(), bus.end(), 0.0f);
    enc.process(late, bus);
    dec.process(bus, el, er);
    r.render(l, rr);
    for (std::size_t i = 0; i < kBusBlock; ++i) {
      worst = std::max({worst, std::abs(l[i] - el[i]), std::abs(rr[i] - er[i])});
      peak = std::max(peak, std::abs(el[i]));
    }
  }
  EXPECT_GT(peak, 0.05f);
  EXPECT_LT(worst, 1e-5f * peak) << "peak " << peak;
}

TEST(AmbisonicTier, TheHeadsTurnMovesTheSourceAndRenderNeverAllocates) {
  const TierFixture& fx = tier_fixture();
  audio::Renderer r = fx.tier(32, 1.0);
  std::vector<int> ids;
  for (int i = 0; i < 32; ++i) {
    audio::SourceState s;
    s.position = {2 * std::cos(i * 0.7), 0.3, 2 * std::sin(i * 0.7)};
    s.air_absorption = 1.0;
    s.reverb_send = 0.1;
    ids.push_back(r.add_source(s));
  }
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-0.1f, 0.1f);
  std::vector<float> l(kBusBlock), rr(kBusBlock);
  std::size_t allocations = 0, locks = 0;
  for (int b = 0; b < 50; ++b) {
    HeadPose head;
    head.orientation = quat_from_ypr(0.05 * b, 0.0, 0.0);
    r.set_listener(head);
    for (int i = 0; i < 32; ++i) {
      audio::SourceState s;
      s.position = {2 * std::cos(i * 0.7 + 0.02 * b), 0.3, 2 * std::sin(i * 0.7 + 0.02 * b)};
      r.set_source(ids[static_cast<std::size_t>(i)], s);
      for (float& x : r.source_input(ids[static_cast<std::size_t>(i)])) x = u(rng);
    }
    earshot::testing::AllocationProbe probe;
    r.render(l, rr);
    allocations += probe.count();
    locks += probe.lock_count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(locks, 0u);

  // One source on the left; the head turned left to face it: centred.
  audio::Renderer one = fx.tier(1);
  audio::SourceState s;
  s.position = {-2, 0, 0};
  const int id = one.add_source(s);
  const auto energy = [&](double yaw) {
    HeadPose head;
    head.orientation = quat_from_ypr(yaw, 0.0, 0.0);
    one.set_listener(head);
    double el = 0, er = 0;
    for (int b = 0; b < 40; ++b) {
      for (float& x : one.source_input(id)) x = u(rng);
      one.render(l, rr);
      if (b < 10) continue;
      for (std::size_t i = 0; i < kBusBlock; ++i) el += double(l[i]) * l[i], er += double(rr[i]) * rr[i];
    }
    return 10 * std::log10(el / er);
  };
  EXPECT_GT(energy(0.0), 6.0);
  EXPECT_NEAR(energy(std::numbers::pi / 2), 0.0, 0.5);
}
