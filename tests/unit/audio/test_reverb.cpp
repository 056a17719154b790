// Room reverbs: decay times, levels, stereo decorrelation, stability of
// every preset, no allocation in process(), clear errors for bad presets and
// parameters, and the room's wiring (renderer send/return; the Scene JSON
// side is in tests/unit/scenes/test_scene_json.cpp). RT60s are measured as
// tests/bench/reverb_decay does (T30, tests/analysis/reverb_measure.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/audio/room_presets.hpp"
#include "earshot/audio/room_reverb.hpp"
#include "earshot/errors.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "reverb_measure.hpp"  // tests/analysis

using namespace earshot::audio;
namespace analysis = earshot::analysis;

namespace {
constexpr double kFs = 48000.0;
constexpr std::size_t kBlock = 128;

struct Ir {
  std::vector<float> left, right;
};

// Feeds `in` (zero-padded to `frames`) through a fresh reverb.
Ir render(const RoomParams& p, LateReverbType type, std::size_t frames, const std::vector<float>& in) {
  RoomReverb reverb(kFs, kBlock, p, type);
  Ir out{std::vector<float>(frames), std::vector<float>(frames)};
  std::vector<float> x(kBlock), l(kBlock), r(kBlock);
  for (std::size_t done = 0; done < frames; done += kBlock) {
    for (std::size_t i = 0; i < kBlock; ++i) x[i] = done + i < in.size() ? in[done + i] : 0.0f;
    reverb.process(x, l, r);
    for (std::size_t i = 0; i < kBlock && done + i < frames; ++i) out.left[done + i] = l[i], out.right[done + i] = r[i];
  }
  return out;
}

Ir impulse_response(const RoomParams& p, LateReverbType type, double seconds) {
  return render(p, type, static_cast<std::size_t>(seconds * kFs), {1.0f});
}

std::vector<float> noise(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> v(n);
  for (auto& x : v) x = u(rng);
  return v;
}

const char* name(LateReverbType t) { return t == LateReverbType::fdn ? "fdn" : "schroeder"; }
}  // namespace

TEST(RoomPresets, EveryRoomOfTable1IsThereAndInRange) {
  const char* table1[] = {"generic", "padded-cell", "room", "small-room", "medium-room", "large-room",
                          "bathroom", "living-room", "stone-room", "auditorium", "concert-hall", "cave",
                          "arena", "hangar", "carpeted-hallway", "hallway", "stone-corridor", "medium-hall",
                          "large-hall", "alley", "forest", "city", "mountains", "quarry", "plain",
                          "parking-lot", "sewer-pipe", "underwater", "plate", "default", "musical-plate"};
  for (const char* n : table1) {
    SCOPED_TRACE(n);
    EXPECT_NO_THROW(validate(room_preset(n)));
  }
  EXPECT_EQ(room_presets().size(), 29u);
  EXPECT_DOUBLE_EQ(room_preset("concert-hall").decay_time_s, 3.92);
  EXPECT_DOUBLE_EQ(room_preset("stone-corridor").decay_hf_ratio, 0.79);
  EXPECT_DOUBLE_EQ(room_preset("default").decay_time_s, room_preset("generic").decay_time_s);
}

TEST(RoomPresets, UnknownNameIsAnInputErrorListingTheValidNames) {
  try {
    (void)room_preset("concert_hall");
    FAIL() << "no error";
  } catch (const earshot::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'concert_hall'"), std::string::npos) << what;
    EXPECT_NE(what.find("concert-hall"), std::string::npos) << what;
    EXPECT_NE(what.find("padded-cell"), std::string::npos) << what;
  }
  EXPECT_THROW((void)late_reverb_type("moorer"), earshot::InputError);
}

TEST(RoomPresets, OutOfRangeParametersAreInputErrorsNamingTheField) {
  auto expect_field = [](RoomParams p, const char* field) {
    try {
      validate(p);
      ADD_FAILURE() << field << ": no error";
    } catch (const earshot::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  RoomParams p = room_preset("generic");
  p.decay_time_s = 25.0;
  expect_field(p, "decay_time_s");
  p = room_preset("generic");
  p.decay_hf_ratio = std::nan("");
  expect_field(p, "decay_hf_ratio");
  p = room_preset("generic");
  p.reflections_delay_s = -0.001;
  expect_field(p, "reflections_delay_s");
  p = room_preset("generic");
  p.wet_db = 30.0;
  expect_field(p, "wet_db");

  // The reverb refuses them too, and update() keeps the old parameters.
  p = room_preset("generic");
  p.late_reverb_gain = 11.0;
  EXPECT_THROW(RoomReverb(kFs, kBlock, p), earshot::InputError);
  RoomReverb reverb(kFs, kBlock, room_preset("room"));
  EXPECT_THROW(reverb.update(p), earshot::InputError);
  EXPECT_DOUBLE_EQ(reverb.params().decay_time_s, room_preset("room").decay_time_s);
}

// RT60 in the 500 Hz and 1 kHz octave bands within 5% of the preset's decay
// time, and the high band's decay ratio within 10%.
TEST(RoomReverb, DecayTimesMeetTheirTargets) {
  struct Case {
    const char* preset;
    LateReverbType type;
  };
  for (const Case c : {Case{"generic", LateReverbType::fdn}, Case{"concert-hall", LateReverbType::fdn},
                       Case{"room", LateReverbType::fdn}, Case{"stone-corridor", LateReverbType::schroeder}}) {
    SCOPED_TRACE(std::string(c.preset) + " " + name(c.type));
    RoomParams p = room_preset(c.preset);
    p.gain_hf = 1.0;  // the high band must carry signal to be measured
    const auto ir = impulse_response(p, c.type, 1.4 * p.decay_time_s + 0.3);
    const auto t500 = analysis::band_rt60(ir.left, ir.right, analysis::octave(500), kFs);
    const auto t1k = analysis::band_rt60(ir.left, ir.right, analysis::octave(1000), kFs);
    const auto thf = analysis::band_rt60(ir.left, ir.right, analysis::third_octave(p.hf_reference_hz), kFs);
    ASSERT_TRUE(t500 && t1k && thf);
    EXPECT_NEAR(*t500 / p.decay_time_s, 1.0, 0.05);
    EXPECT_NEAR(*t1k / p.decay_time_s, 1.0, 0.05);
    EXPECT_NEAR(*thf / (0.5 * (*t500 + *t1k)) / p.decay_hf_ratio, 1.0, 0.10);
  }
}

TEST(RoomReverb, LongerDecayTimeRingsLonger) {
  RoomParams p = room_preset("generic");
  p.decay_time_s = 0.5;
  const auto a = impulse_response(p, LateReverbType::fdn, 1.0);
  p.decay_time_s = 2.0;
  const auto b = impulse_response(p, LateReverbType::fdn, 3.0);
  const auto ta = analysis::band_rt60(a.left, a.right, analysis::octave(1000), kFs);
  const auto tb = analysis::band_rt60(b.left, b.right, analysis::octave(1000), kFs);
  ASSERT_TRUE(ta && tb);
  EXPECT_GT(*tb, 3.5 * *ta);
}

TEST(RoomReverb, EarsAreDecorrelated) {
  for (auto type : {LateReverbType::fdn, LateReverbType::schroeder}) {
    SCOPED_TRACE(name(type));
    const auto ir = impulse_response(room_preset("concert-hall"), type, 2.0);
    // The tail after the early reflections.
    const auto from = static_cast<std::size_t>(0.1 * kFs);
    const auto ic = analysis::interaural_coherence(std::span(ir.left).subspan(from), std::span(ir.right).subspan(from), kFs);
    EXPECT_LT(ic, 0.2);
  }
}

TEST(RoomReverb, FdnEchoDensityBuildsUpWithin100ms) {
  const auto ir = impulse_response(room_preset("concert-hall"), LateReverbType::fdn, 1.0);
  const auto t = analysis::echo_density_time(ir.left, kFs);
  ASSERT_TRUE(t);
  EXPECT_LE(*t, 0.1);
}

// Every preset, both reverbs, noise in: output finite and bounded, and
// silent again once the input stops and the tail has had 1.5 decay times.
TEST(RoomReverb, EveryPresetIsStableAndFinite) {
  const auto in = noise(static_cast<std::size_t>(0.5 * kFs), 3);
  for (const auto& preset : room_presets()) {
    for (auto type : {LateReverbType::fdn, LateReverbType::schroeder}) {
      SCOPED_TRACE(std::string(preset.name) + " " + name(type));
      const RoomParams& p = preset.params;
      const double tail = p.decay_time_s * std::max(1.0, p.decay_hf_ratio);
      const auto frames = static_cast<std::size_t>((0.5 + 0.4 + 1.5 * tail) * kFs);
      const auto out = render(p, type, frames, in);
      double peak = 0.0, end_peak = 0.0;
      bool finite = true;
      for (std::size_t i = 0; i < frames; ++i) {
        const double m = std::max(std::abs(out.left[i]), std::abs(out.right[i]));
        finite = finite && std::isfinite(out.left[i]) && std::isfinite(out.right[i]);
        peak = std::max(peak, m);
        if (i + static_cast<std::size_t>(0.05 * kFs) >= frames) end_peak = std::max(end_peak, m);
      }
      EXPECT_TRUE(finite);
      EXPECT_LT(peak, 20.0);
      EXPECT_GT(peak, 1e-3);
      EXPECT_LT(end_peak, peak * 1e-3);  // more than 60 dB down after 1.5 decay times
    }
  }
}

TEST(RoomReverb, ProcessAndUpdateNeverAllocate) {
  for (auto type : {LateReverbType::fdn, LateReverbType::schroeder}) {
    SCOPED_TRACE(name(type));
    RoomReverb reverb(kFs, kBlock, room_preset("generic"), type);
    const auto in = noise(kBlock, 5);
    std::vector<float> l(kBlock), r(kBlock);
    const RoomParams& hall = room_preset("concert-hall");
    earshot::testing::AllocationProbe probe;
    for (int b = 0; b < 200; ++b) {
      if (b == 100) reverb.update(hall);
      reverb.process(in, l, r);
    }
    EXPECT_EQ(probe.count(), 0u);
  }
}

TEST(RoomReverb, DryAndWetLevels) {
  RoomParams p = room_preset("generic");
  p.wet_db = -120.0;  // silent wet
  p.dry_db = 0.0;
  const auto in = noise(kBlock * 4, 9);
  const auto out = render(p, LateReverbType::fdn, in.size(), in);
  for (std::size_t i = 0; i < in.size(); ++i) {
    EXPECT_FLOAT_EQ(out.left[i], in[i]);
    EXPECT_FLOAT_EQ(out.right[i], in[i]);
  }
}

// Table 1: "0 dB gives a reverb tail with roughly the same energy as the input".
TEST(RoomReverb, LateLevelFollowsLateReverbGain) {
  for (const char* preset : {"concert-hall", "padded-cell"})
  for (auto type : {LateReverbType::fdn, LateReverbType::schroeder}) {
    SCOPED_TRACE(std::string(preset) + " " + name(type));
    RoomParams p = room_preset(preset);
    // Flat decay: a shorter high-frequency decay takes its share of the energy away.
    p.gain = 1.0, p.gain_hf = 1.0, p.reflections_gain = 0.0, p.decay_hf_ratio = 1.0;
    double energy[2] = {};
    for (int k = 0; k < 2; ++k) {
      p.late_reverb_gain = k == 0 ? 1.0 : 0.5;
      const auto ir = impulse_response(p, type, 6.0);
      for (std::size_t i = 0; i < ir.left.size(); ++i) energy[k] += 0.5 * (ir.left[i] * ir.left[i] + ir.right[i] * ir.right[i]);
    }
    EXPECT_NEAR(10 * std::log10(energy[0]), 0.0, 2.0);                // unit impulse in: about 0 dB out per ear
    EXPECT_NEAR(10 * std::log10(energy[1] / energy[0]), -6.02, 0.1);  // level is a plain gain
  }
}

// The renderer's send bus through the room and back, as `earshot render` wires it:
// an impulse from a source with its send open rings on after the direct sound.
TEST(RoomReverb, RendererSendAndReturn) {
  auto hrtf = std::make_shared<const earshot::hrtf::HrtfSet>(earshot::hrtf::HrtfSet::load_default(kFs));
  double tail[2] = {};
  for (int with_room = 0; with_room < 2; ++with_room) {
    RendererConfig cfg;
    cfg.block = kBlock;
    Renderer renderer(hrtf, cfg);
    SourceState s;
    s.position = {1.0, 0.0, -2.0};
    s.reverb_send = 1.0;
    const int id = renderer.add_source(s);
    RoomReverb room(kFs, kBlock, room_preset("concert-hall"));
    std::vector<float> l(kBlock), r(kBlock);
    for (int b = 0; b < 400; ++b) {  // ~1 s
      auto in = renderer.source_input(id);
      std::fill(in.begin(), in.end(), 0.0f);
      if (b == 0) in[0] = 1.0f;
      renderer.render(l, r);
      if (with_room) room.process(renderer.reverb_send(), renderer.return_left(), renderer.return_right());
      if (b >= 100)  // after 0.27 s: the direct sound is long gone
        for (std::size_t i = 0; i < kBlock; ++i) tail[with_room] += l[i] * l[i] + r[i] * r[i];
    }
  }
  EXPECT_EQ(tail[0], 0.0);
  EXPECT_GT(tail[1], 1e-4);
}

// The corners of the parameter ranges, beyond what any preset asks.
TEST(RoomReverb, ExtremeParametersStayFinite) {
  const auto in = noise(static_cast<std::size_t>(0.3 * kFs), 11);
  for (double t60 : {0.1, 20.0})
    for (double ratio : {0.1, 2.0})
      for (double density : {0.0, 1.0})
        for (double f_hf : {1000.0, 20000.0})
          for (auto type : {LateReverbType::fdn, LateReverbType::schroeder}) {
            RoomParams p = room_preset("generic");
            p.decay_time_s = t60, p.decay_hf_ratio = ratio, p.density = density, p.hf_reference_hz = f_hf;
            p.late_reverb_gain = 10.0, p.reflections_gain = 3.16, p.gain = 1.0, p.wet_db = 20.0;
            SCOPED_TRACE(testing::Message() << name(type) << " t60 " << t60 << " ratio " << ratio << " density "
                                            << density << " hf " << f_hf);
            const auto out = render(p, type, static_cast<std::size_t>(1.0 * kFs), in);
            double peak = 0.0;
            for (std::size_t i = 0; i < out.left.size(); ++i) {
              ASSERT_TRUE(std::isfinite(out.left[i]) && std::isfinite(out.right[i])) << i;
              peak = std::max({peak, double(std::abs(out.left[i])), double(std::abs(out.right[i]))});
            }
            EXPECT_LT(peak, 1000.0);
          }
}
