// Ambisonic fields and the Ambisonic tier through the C API (ABI 1.5): a
// field buffer's plane wave heard from its side, turned by the head and by
// its own orientation, the same whatever layout and scaling it came in, a
// relative field that turns with the head, the argument checks, the tier's
// cues, and no allocation or lock in esRender with beds, a field callback
// and the tier, switches included; the control and audio threads together.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <numbers>
#include <span>
#include <thread>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "binaural_cues.hpp"
#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/earshot.h"

namespace {

namespace ambi = earshot::ambisonics;
constexpr ESuint kBlock = 128;
constexpr double kRate = 48000.0;

std::vector<float> white(std::size_t n, unsigned seed) {
  std::vector<float> x(n);
  unsigned s = seed;
  for (auto& v : x) {
    s = s * 1664525u + 1013904223u;
    v = 0.3f * (static_cast<float>(s >> 8) / 8388608.0f - 1.0f);
  }
  return x;
}

/// A plane wave of `signal` from `direction` (ambiX frame), interleaved in
/// `convention`'s channel order and scaling.
std::vector<float> plane_wave(const std::vector<float>& signal, int order, const earshot::Vec3& direction,
                              ambi::Convention convention = ambi::Convention::ambix) {
  const std::size_t C = ambi::channel_count(order);
  std::vector<double> sh(C);
  ambi::real_sh(order, direction, sh);
  const ambi::ChannelMap to = ambi::from_ambix(convention, order);  // other[n] = gain[n] ambix[source[n]]
  std::vector<float> out(signal.size() * C);
  for (std::size_t i = 0; i < signal.size(); ++i)
    for (std::size_t n = 0; n < C; ++n) out[i * C + n] = static_cast<float>(to.gain[n] * sh[to.source[n]]) * signal[i];
  return out;
}

struct Cues {
  double itd_us, ild_db;
};

struct World {
  ESworld w = 0;
  explicit World(ESuint max_sources = 8) {
    ESworldparams p;
    esWorldParamsDefault(&p);
    p.max_sources = max_sources;
    EXPECT_EQ(esCreateWorld(&p, &w), ES_OK);
  }
  ~World() {
    if (w) esDestroyWorld(w);
  }
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// A looping source playing `interleaved` as a field of `order`.
  ESsource field(const std::vector<float>& interleaved, int order, ESenum layout = ES_AMBISONIC_LAYOUT_ACN,
                 ESenum scaling = ES_AMBISONIC_SCALING_SN3D) const {
    const auto C = static_cast<ESuint>(ambi::channel_count(order));
    ESbuffer b = 0;
    EXPECT_EQ(esCreateAmbisonicBuffer(w, interleaved.data(), static_cast<ESuint>(interleaved.size()) / C, 48000,
                                      static_cast<ESuint>(order), layout, scaling, &b),
              ES_OK)
        << esGetErrorMessage(w);
    ESsource s = 0;
    EXPECT_EQ(esCreateSource(w, &s), ES_OK);
    EXPECT_EQ(esSourcei(w, s, ES_BUFFER, static_cast<ESint>(b)), ES_OK) << esGetErrorMessage(w);
    EXPECT_EQ(esSourcei(w, s, ES_LOOPING, ES_TRUE), ES_OK);
    EXPECT_EQ(esSourcePlay(w, s), ES_OK);
    return s;
  }
  void render(int n, std::vector<float>& l, std::vector<float>& r) const {
    std::array<float, kBlock> bl{}, br{};
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(esRender(w, bl.data(), br.data(), kBlock), ES_OK);
      l.insert(l.end(), bl.begin(), bl.end());
      r.insert(r.end(), br.begin(), br.end());
    }
  }
  /// The cues of the next n blocks after `skip` blocks.
  Cues cues(int skip = 20, int n = 60) const {
    std::vector<float> l, r;
    render(skip, l, r);
    l.clear();
    r.clear();
    render(n, l, r);
    // ITD below 1.5 kHz, where it is heard (MagLS keeps the HRTF's phase
    // only below its transition; above it fits magnitudes).
    return {earshot::analysis::itd_s(l, r, kRate, 1.2e-3, 1500.0) * 1e6, earshot::analysis::ild_db(l, r)};
  }
};

void yaw_head(ESworld w, double yaw_rad) {
  const ESfloat pos[3] = {0, 0, 0};
  const ESfloat q[4] = {static_cast<ESfloat>(std::cos(yaw_rad / 2)), 0, static_cast<ESfloat>(std::sin(yaw_rad / 2)), 0};
  ASSERT_EQ(esSetHeadPose(w, pos, q), ES_OK);
}

const earshot::Vec3 kAhead{1, 0, 0}, kLeft{0, 1, 0};

TEST(AmbisonicWorld, AWaveFromTheLeftIsHeardOnTheLeftAndAheadOnceTheHeadTurnsToIt) {
  World t;
  const ESsource s = t.field(plane_wave(white(24000, 1), 1, kLeft), 1);
  ESint order = 0;
  ASSERT_EQ(esGetSourcei(t.w, s, ES_AMBISONIC_ORDER, &order), ES_OK);
  EXPECT_EQ(order, 1);
  const Cues left = t.cues();
  EXPECT_GT(left.ild_db, 6.0);
  EXPECT_GT(left.itd_us, 150.0);  // first order: about 210 us of KEMAR's 700 (docs/AMBISONICS.md)
  // The listener's position does not move a field of plane waves: a world
  // whose listener stands elsewhere renders the same samples.
  {
    World a, b;
    a.field(plane_wave(white(24000, 1), 1, kLeft), 1);
    b.field(plane_wave(white(24000, 1), 1, kLeft), 1);
    ASSERT_EQ(esListener3f(b.w, ES_POSITION, 5, 0, 3), ES_OK);
    std::vector<float> al, ar, bl, br;
    a.render(20, al, ar);
    b.render(20, bl, br);
    EXPECT_EQ(al, bl);
    EXPECT_EQ(ar, br);
  }
  yaw_head(t.w, std::numbers::pi / 2);  // the head turns left, to the wave
  const Cues ahead = t.cues();
  EXPECT_NEAR(ahead.ild_db, 0.0, 0.5);
  EXPECT_NEAR(ahead.itd_us, 0.0, 25.0);
}

TEST(AmbisonicWorld, TheFieldsOrientationTurnsIt) {
  World t;
  const ESsource s = t.field(plane_wave(white(24000, 2), 3, kAhead), 3);
  EXPECT_NEAR(t.cues().ild_db, 0.0, 0.5);
  // Turned 90 degrees to the left: the wave from the field's front comes from the left.
  const ESfloat at_up[6] = {-1, 0, 0, 0, 1, 0};
  ASSERT_EQ(esSourcefv(t.w, s, ES_ORIENTATION, at_up), ES_OK);
  const Cues turned = t.cues();
  EXPECT_GT(turned.ild_db, 6.0);
  EXPECT_GT(turned.itd_us, 300.0);
  ESfloat q[4] = {};
  ASSERT_EQ(esGetSourcefv(t.w, s, ES_ORIENTATION_QUAT, q), ES_OK);
  EXPECT_NEAR(q[0], std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(q[2], std::sqrt(0.5), 1e-6);
  ESfloat back[6] = {};
  ASSERT_EQ(esGetSourcefv(t.w, s, ES_ORIENTATION, back), ES_OK);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], at_up[i], 1e-6) << i;
}

TEST(AmbisonicWorld, EveryLayoutAndScalingGivesTheSameField) {
  const auto x = white(12000, 3);
  const earshot::Vec3 d{0.3, 0.8, 0.4};
  std::vector<float> ref_l, ref_r;
  {
    World t;
    t.field(plane_wave(x, 3, d), 3);
    t.render(40, ref_l, ref_r);
  }
  struct Case {
    ambi::Convention convention;
    ESenum layout, scaling;
  };
  for (const Case c : {Case{ambi::Convention::n3d, ES_AMBISONIC_LAYOUT_ACN, ES_AMBISONIC_SCALING_N3D},
                       Case{ambi::Convention::fuma, ES_AMBISONIC_LAYOUT_FUMA, ES_AMBISONIC_SCALING_FUMA}}) {
    World t;
    t.field(plane_wave(x, 3, d, c.convention), 3, c.layout, c.scaling);
    std::vector<float> l, r;
    t.render(40, l, r);
    float worst = 0;
    for (std::size_t i = 0; i < l.size(); ++i) worst = std::max({worst, std::abs(l[i] - ref_l[i]), std::abs(r[i] - ref_r[i])});
    EXPECT_LT(worst, 2e-6f) << ambi::convention_name(c.convention);
  }
}

TEST(AmbisonicWorld, ARelativeFieldTurnsWithTheHead) {
  World t;
  const ESsource s = t.field(plane_wave(white(24000, 4), 2, kLeft), 2);
  ASSERT_EQ(esSourcei(t.w, s, ES_SOURCE_RELATIVE, ES_TRUE), ES_OK);
  yaw_head(t.w, std::numbers::pi / 2);
  const Cues c = t.cues();
  EXPECT_GT(c.ild_db, 6.0);  // still on the left of the head
}

TEST(AmbisonicWorld, ArgumentsAreChecked) {
  World t;
  const auto one = white(8, 5);
  std::vector<float> x(one.size() * 16, 0.1f);
  ESbuffer b = 0;
  EXPECT_EQ(esCreateAmbisonicBuffer(t.w, x.data(), 8, 48000, 0, ES_AMBISONIC_LAYOUT_ACN, ES_AMBISONIC_SCALING_SN3D, &b),
            ES_INVALID_VALUE);
  EXPECT_EQ(esCreateAmbisonicBuffer(t.w, x.data(), 1, 48000, 8, ES_AMBISONIC_LAYOUT_ACN, ES_AMBISONIC_SCALING_SN3D, &b),
            ES_INVALID_VALUE);
  std::vector<float> big(25 * 8, 0.1f);
  EXPECT_EQ(esCreateAmbisonicBuffer(t.w, big.data(), 8, 48000, 4, ES_AMBISONIC_LAYOUT_FUMA, ES_AMBISONIC_SCALING_FUMA, &b),
            ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("FuMa"), std::string::npos) << esGetErrorMessage(t.w);
  EXPECT_EQ(esCreateAmbisonicBuffer(t.w, x.data(), 8, 48000, 3, 0x1234, ES_AMBISONIC_SCALING_SN3D, &b), ES_INVALID_VALUE);
  EXPECT_EQ(esCreateAmbisonicBuffer(t.w, x.data(), 8, 48000, 3, ES_AMBISONIC_LAYOUT_ACN, 0x1234, &b), ES_INVALID_VALUE);
  EXPECT_EQ(esCreateAmbisonicBuffer(t.w, nullptr, 8, 48000, 3, ES_AMBISONIC_LAYOUT_ACN, ES_AMBISONIC_SCALING_SN3D, &b),
            ES_INVALID_VALUE);
  EXPECT_EQ(esCreateAmbisonicBuffer(t.w, x.data(), 8, 48000, 3, ES_AMBISONIC_LAYOUT_ACN, ES_AMBISONIC_SCALING_SN3D, nullptr),
            ES_INVALID_VALUE);
  ESsource s = 0;
  ASSERT_EQ(esCreateSource(t.w, &s), ES_OK);
  EXPECT_EQ(esSourcef(t.w, s, ES_ORIENTATION, 1.0f), ES_INVALID_ENUM);  // six floats, not one
  EXPECT_EQ(esSourceAmbisonicCallback(t.w, s, 9, [](void*, float*, ESuint, ESuint) {}, nullptr), ES_INVALID_VALUE);
  const ESfloat zero[4] = {0, 0, 0, 0};
  EXPECT_EQ(esSourcefv(t.w, s, ES_ORIENTATION_QUAT, zero), ES_INVALID_VALUE);
  EXPECT_EQ(esWorldi(t.w, ES_QUALITY, ES_QUALITY_AMBISONIC(8)), ES_INVALID_VALUE);
  EXPECT_EQ(esWorldi(t.w, ES_QUALITY, 7), ES_INVALID_VALUE);
  EXPECT_EQ(esWorldi(t.w, ES_AMBISONIC_DECODER, 0), ES_INVALID_VALUE);
  ESint v = 0;
  ASSERT_EQ(esGetWorldi(t.w, ES_QUALITY, &v), ES_OK);
  EXPECT_EQ(v, ES_QUALITY_DIRECT);
  ASSERT_EQ(esGetWorldi(t.w, ES_AMBISONIC_DECODER, &v), ES_OK);
  EXPECT_EQ(v, ES_DECODER_MAGLS);
  ASSERT_EQ(esGetSourcei(t.w, s, ES_AMBISONIC_ORDER, &v), ES_OK);
  EXPECT_EQ(v, 0);
}

/// A point source of noise at `position`, the tier's cues.
Cues tier_cues(int order, const std::array<float, 3>& position) {
  World t;
  if (order > 0) {
    EXPECT_EQ(esWorldi(t.w, ES_QUALITY, ES_QUALITY_AMBISONIC(order)), ES_OK) << esGetErrorMessage(t.w);
  }
  const auto x = white(24000, 6);
  ESbuffer b = 0;
  EXPECT_EQ(esCreateBuffer(t.w, x.data(), static_cast<ESuint>(x.size()), 48000, &b), ES_OK);
  ESsource s = 0;
  EXPECT_EQ(esCreateSource(t.w, &s), ES_OK);
  EXPECT_EQ(esSourcei(t.w, s, ES_BUFFER, static_cast<ESint>(b)), ES_OK);
  EXPECT_EQ(esSourcei(t.w, s, ES_LOOPING, ES_TRUE), ES_OK);
  EXPECT_EQ(esSource3f(t.w, s, ES_POSITION, position[0], position[1], position[2]), ES_OK);
  EXPECT_EQ(esSourcePlay(t.w, s), ES_OK);
  return t.cues();
}

TEST(AmbisonicWorld, TheAmbisonicTierKeepsTheSidesCues) {
  for (const auto& pos : {std::array<float, 3>{-2, 0, 0}, std::array<float, 3>{-1.4f, 0, -1.4f}, std::array<float, 3>{0, 0, -2}}) {
    const Cues direct = tier_cues(0, pos), tier = tier_cues(3, pos);
    EXPECT_NEAR(tier.itd_us, direct.itd_us, 50.0) << pos[0] << " " << pos[2];
    EXPECT_NEAR(tier.ild_db, direct.ild_db, 2.5) << pos[0] << " " << pos[2];
  }
}

TEST(AmbisonicWorld, TheTierCanBeChosenAndLeftWhilePlaying) {
  World t;
  const auto x = white(24000, 7);
  ESbuffer b = 0;
  ASSERT_EQ(esCreateBuffer(t.w, x.data(), static_cast<ESuint>(x.size()), 48000, &b), ES_OK);
  ESsource s = 0;
  ASSERT_EQ(esCreateSource(t.w, &s), ES_OK);
  ASSERT_EQ(esSourcei(t.w, s, ES_BUFFER, static_cast<ESint>(b)), ES_OK);
  ASSERT_EQ(esSourcei(t.w, s, ES_LOOPING, ES_TRUE), ES_OK);
  ASSERT_EQ(esSource3f(t.w, s, ES_POSITION, -2, 0, 0), ES_OK);
  ASSERT_EQ(esSourcePlay(t.w, s), ES_OK);
  std::vector<float> l, r;
  t.render(10, l, r);
  ASSERT_EQ(esWorldi(t.w, ES_QUALITY, ES_QUALITY_AMBISONIC(2)), ES_OK);
  ESint v = 0;
  ASSERT_EQ(esGetWorldi(t.w, ES_QUALITY, &v), ES_OK);
  EXPECT_EQ(v, ES_QUALITY_AMBISONIC(2));
  t.render(20, l, r);  // the fade (1024 frames) is over
  EXPECT_GT(t.cues(0, 40).ild_db, 6.0);
  ASSERT_EQ(esWorldi(t.w, ES_QUALITY, ES_QUALITY_DIRECT), ES_OK);
  EXPECT_GT(t.cues(10, 40).ild_db, 6.0);
  // No step where the tiers changed: the largest sample-to-sample jump stays
  // that of the noise.
  float jump = 0;
  for (std::size_t i = 1; i < l.size(); ++i) jump = std::max(jump, std::abs(l[i] - l[i - 1]));
  EXPECT_LT(jump, 0.5f);
}

void pull_field(void* user, float* out, ESuint channels, ESuint frames) {
  auto* phase = static_cast<double*>(user);
  for (ESuint i = 0; i < frames; ++i) {
    const auto v = static_cast<float>(0.2 * std::sin(*phase));
    *phase += 0.05;
    out[i] = v;                       // W
    if (channels > 1) out[frames + i] = v;  // Y: from the left
    for (ESuint c = 2; c < channels; ++c) out[c * frames + i] = 0.0f;
  }
}

TEST(AmbisonicWorld, RenderNeverAllocatesOrLocksWithFieldsAndTheTier) {
  World t(40);
  t.field(plane_wave(white(9600, 8), 3, kLeft), 3);
  double phase = 0;
  ESsource cb = 0;
  ASSERT_EQ(esCreateSource(t.w, &cb), ES_OK);
  ASSERT_EQ(esSourceAmbisonicCallback(t.w, cb, 1, pull_field, &phase), ES_OK);
  ASSERT_EQ(esSourcePlay(t.w, cb), ES_OK);
  const auto x = white(4800, 9);
  ESbuffer b = 0;
  ASSERT_EQ(esCreateBuffer(t.w, x.data(), 4800, 48000, &b), ES_OK);
  std::vector<ESsource> s(32);
  for (auto& id : s) {
    ASSERT_EQ(esCreateSource(t.w, &id), ES_OK);
    ASSERT_EQ(esSourcei(t.w, id, ES_BUFFER, static_cast<ESint>(b)), ES_OK);
    ASSERT_EQ(esSourcei(t.w, id, ES_LOOPING, ES_TRUE), ES_OK);
    ASSERT_EQ(esSourcef(t.w, id, ES_AIR_ABSORPTION_FACTOR, 1.0f), ES_OK);
    ASSERT_EQ(esSourcePlay(t.w, id), ES_OK);
  }
  ASSERT_EQ(esWorldi(t.w, ES_QUALITY, ES_QUALITY_AMBISONIC(3)), ES_OK);
  std::array<float, kBlock> l{}, r{};
  ASSERT_EQ(esRender(t.w, l.data(), r.data(), kBlock), ES_OK);
  std::size_t allocations = 0, locks = 0;
  for (int block = 0; block < 60; ++block) {
    const auto a = static_cast<float>(block) * 0.1f;
    for (std::size_t i = 0; i < s.size(); ++i)
      ASSERT_EQ(esSource3f(t.w, s[i], ES_POSITION, 2 * std::cos(a + static_cast<float>(i)), 0,
                           2 * std::sin(a + static_cast<float>(i))),
                ES_OK);
    yaw_head(t.w, a);
    if (block == 20) {
      ASSERT_EQ(esWorldi(t.w, ES_QUALITY, ES_QUALITY_DIRECT), ES_OK);  // a fade under the probe
    }
    if (block == 40) {
      ASSERT_EQ(esWorldHrtf(t.w, nullptr), ES_OK);  // the fields' decoders fade too
    }
    earshot::testing::AllocationProbe probe;
    ASSERT_EQ(esRender(t.w, l.data(), r.data(), kBlock), ES_OK);
    allocations += probe.count();
    locks += probe.lock_count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(locks, 0u);
}

TEST(AmbisonicThreads, FieldsAndTiersSwitchWhileAnotherThreadRenders) {
  World t(8);
  t.field(plane_wave(white(9600, 10), 2, kLeft), 2);
  std::atomic<bool> stop{false};
  std::atomic<int> blocks{0};
  std::thread audio([&] {
    std::array<float, kBlock> l{}, r{};
    while (!stop.load()) {
      if (esRender(t.w, l.data(), r.data(), kBlock) == ES_OK) blocks.fetch_add(1);
      std::this_thread::yield();
    }
  });
  const auto x = plane_wave(white(4800, 11), 1, kAhead);
  for (int round = 0; round < 6; ++round) {
    ASSERT_EQ(esWorldi(t.w, ES_QUALITY, round % 2 ? ES_QUALITY_DIRECT : ES_QUALITY_AMBISONIC(1)), ES_OK);
    t.field(x, 1);
    ASSERT_EQ(esWorldHrtf(t.w, nullptr), ES_OK);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  while (blocks.load() < 100) std::this_thread::yield();
  stop.store(true);
  audio.join();
}

}  // namespace
