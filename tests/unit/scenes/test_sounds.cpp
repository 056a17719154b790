// Synthesised sounds and file signals: deterministic for a seed, finite and
// bounded; the bad ones are refused with an error naming the field or file.
#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "earshot/errors.hpp"
#include "earshot/scenes/scene.hpp"
#include "earshot/scenes/signal_source.hpp"
#include "../audio/alloc_counter.hpp"
#include "scene_test_util.hpp"
#include "../scratch_path.hpp"

using namespace earshot::scenes;
namespace fs = std::filesystem;

namespace {

constexpr double kRate = 48000.0;

Signal signal_from(const std::string& json_signal) {
  return parse_scene(R"({"sources": [{"signal": )" + json_signal + "}]}", "s.json", fs::temp_directory_path())
      .sources[0]
      .signal;
}

std::vector<float> generate(const Signal& s, double seconds, std::size_t block = 128, double rate = kRate) {
  SignalSource src(s, rate);
  std::vector<float> out(static_cast<std::size_t>(seconds * rate));
  for (std::size_t i = 0; i < out.size(); i += block)
    src.generate(std::span(out).subspan(i, std::min(block, out.size() - i)));
  return out;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const earshot::InputError& e) {
    return e.what();
  }
  return "";
}

const std::vector<std::string> kSounds = {
    R"({"type": "voice", "pitch_hz": 196, "melody": [0, 4, 7], "vowels": "aoi"})",
    R"({"type": "talk", "seed": SEED, "pitch_hz": 140})",
    R"({"type": "siren", "mode": "wail"})",
    R"({"type": "siren", "mode": "yelp"})",
    R"({"type": "birds", "seed": SEED})",
    R"({"type": "engine", "seed": SEED, "rpm": 3000})",
    R"({"type": "horn", "period_s": 1})",
    R"({"type": "footsteps", "seed": SEED})",
    R"({"type": "ambience", "kind": "city", "seed": SEED})",
    R"({"type": "ambience", "kind": "pink", "seed": SEED})",
    R"({"type": "animal", "kind": "lion", "seed": SEED, "interval_s": 2})",
    R"({"type": "animal", "kind": "elephant", "seed": SEED, "interval_s": 2})",
    R"({"type": "animal", "kind": "monkey", "seed": SEED, "interval_s": 1})",
    R"({"type": "animal", "kind": "parrot", "seed": SEED, "interval_s": 1})",
};

std::string with_seed(std::string s, int seed) {
  const auto p = s.find("SEED");
  return p == std::string::npos ? s : s.substr(0, p) + std::to_string(seed) + s.substr(p + 4);
}

}  // namespace

TEST(Sounds, EachIsDeterministicFiniteBoundedAndAudible) {
  for (const auto& json : kSounds) {
    SCOPED_TRACE(json);
    const Signal s = signal_from(with_seed(json, 7));
    const auto a = generate(s, 8.0), b = generate(s, 8.0, 97);  // another block size: same samples
    ASSERT_EQ(a, b);
    std::size_t clipped = 0;
    for (float x : a) {
      ASSERT_TRUE(std::isfinite(x));
      ASSERT_LE(std::abs(x), 1.0f);
      clipped += std::abs(x) > 0.999f;
    }
    EXPECT_LT(clipped, a.size() / 1000);
    const double level = 20 * std::log10(test::rms(a) + 1e-30);
    EXPECT_GT(level, -40.0);  // audible over 8 s
    EXPECT_LT(level, -3.0);   // with headroom
    if (json.find("SEED") != std::string::npos) {
      EXPECT_NE(a, generate(signal_from(with_seed(json, 8)), 8.0));
    }
  }
}

TEST(Sounds, FiniteAndBoundedAtTheEdgesOfTheSceneRates) {
  for (const double rate : {8000.0, 192000.0})
    for (const auto& json : kSounds) {
      SCOPED_TRACE(json + " at " + std::to_string(rate));
      const auto x = generate(signal_from(with_seed(json, 2)), 3.0, 128, rate);
      for (float v : x) ASSERT_TRUE(std::isfinite(v) && std::abs(v) <= 1.0f);
      EXPECT_GT(test::rms(x), 1e-3);
    }
}

TEST(Sounds, EngineRunsAtItsFiringFrequency) {
  // 3000 rpm, four cylinders, four-stroke: two firings per turn, 100 Hz.
  const auto x = generate(signal_from(R"({"type": "engine", "rpm": 3000, "cylinders": 4})"), 2.0);
  EXPECT_NEAR(test::peak_hz(x, kRate, 50, 150), 100.0, 0.5);
}

TEST(Sounds, TalkersDifferByPitch) {
  // Each talker's voice sits near its pitch_hz (accents and the fall over a
  // phrase move it by +-20 %), so two talkers are told apart.
  double f[2];
  int k = 0;
  for (double pitch : {100.0, 220.0}) {
    const auto x = generate(signal_from(R"({"type": "talk", "seed": 3, "pitch_hz": )" + std::to_string(pitch) + "}"), 4.0);
    f[k] = test::median_pitch_hz(x, kRate);
    EXPECT_GT(f[k], 0.75 * pitch) << pitch;
    EXPECT_LT(f[k], 1.25 * pitch) << pitch;
    ++k;
  }
  EXPECT_GT(f[1], 1.6 * f[0]);
}

TEST(Sounds, SirenSweepsBetweenItsLimits) {
  const auto x = generate(signal_from(R"({"type": "siren", "low_hz": 600, "high_hz": 1200, "period_s": 4})"), 4.0);
  // At the start the wail is at its low note, halfway at its high note.
  const auto at = [&](double t) { return std::span<const float>(x).subspan(static_cast<std::size_t>(t * kRate), 2400); };
  EXPECT_NEAR(test::peak_hz(at(0.0), kRate, 400, 1500), 600, 15);
  EXPECT_NEAR(test::peak_hz(at(1.975), kRate, 400, 1500), 1200, 15);
}

TEST(Sounds, BadSoundsNameTheField) {
  auto err = [](const std::string& sig) {
    return error_of([&] { (void)signal_from(sig); });
  };
  EXPECT_EQ(err(R"({"type": "kazoo"})"),
            "s.json: field 'sources[0].signal.type': unknown signal type 'kazoo' (noise, sine, impulse, file, voice, "
            "talk, siren, birds, engine, horn, footsteps, ambience, animal)");
  EXPECT_EQ(err(R"({"type": "animal", "kind": "unicorn"})"),
            "s.json: field 'sources[0].signal.kind': unknown kind 'unicorn' (lion, elephant, monkey, parrot)");
  EXPECT_EQ(err(R"({"type": "animal"})"),
            "s.json: field 'sources[0].signal.kind': missing (lion, elephant, monkey, parrot)");
  EXPECT_EQ(err(R"({"type": "siren", "mode": "whoop"})"),
            "s.json: field 'sources[0].signal.mode': unknown mode 'whoop' (wail, yelp)");
  EXPECT_EQ(err(R"({"type": "engine", "rpm": 50000})"),
            "s.json: field 'sources[0].signal.rpm': out of range: 50000 (allowed 300 to 12000)");
  EXPECT_EQ(err(R"({"type": "talk", "pitch_hz": -1})"),
            "s.json: field 'sources[0].signal.pitch_hz': out of range: -1 (allowed 50 to 500)");
  EXPECT_EQ(err(R"({"type": "voice", "vowels": "xyz"})"),
            "s.json: field 'sources[0].signal.vowels': expected letters from a, e, i, o, u, got \"xyz\"");
  EXPECT_EQ(err(R"({"type": "voice", "melody": []})"),
            "s.json: field 'sources[0].signal.melody': expected 1 to 1000 semitone offsets");
  EXPECT_EQ(err(R"({"type": "siren", "low_hz": 900, "high_hz": 800})"),
            "s.json: field 'sources[0].signal.high_hz': below low_hz");
  EXPECT_EQ(err(R"({"type": "birds", "rpm": 1})"), "s.json: field 'sources[0].signal.rpm': unknown field");
  EXPECT_EQ(err(R"({"type": "file", "path": "x.wav", "loop": "yes"})"),
            "s.json: field 'sources[0].signal.loop': expected true or false, got \"yes\"");
}

namespace {
/// A sine of `seconds` at `rate` in a stereo file of the given format.
fs::path write_tone(const std::string& name, int rate, double hz, double seconds, int format) {
  const fs::path p = earshot::test::scratch_path("sound_tests") / name;
  fs::create_directories(p.parent_path());
  SF_INFO info{};
  info.samplerate = rate;
  info.channels = 2;
  info.format = format;
  SNDFILE* f = sf_open(p.c_str(), SFM_WRITE, &info);
  EXPECT_NE(f, nullptr) << sf_strerror(nullptr);
  const auto n = static_cast<std::size_t>(seconds * rate);
  std::vector<float> inter(2 * n);
  for (std::size_t i = 0; i < n; ++i)
    inter[2 * i] = inter[2 * i + 1] = static_cast<float>(0.5 * std::sin(2 * M_PI * hz * static_cast<double>(i) / rate));
  sf_writef_float(f, inter.data(), static_cast<sf_count_t>(n));
  sf_close(f);
  return p;
}
}  // namespace

TEST(FileSignal, AnyRateIsResampledAndLoops) {
  for (int format : {SF_FORMAT_WAV | SF_FORMAT_PCM_16, SF_FORMAT_FLAC | SF_FORMAT_PCM_16, SF_FORMAT_OGG | SF_FORMAT_VORBIS}) {
    const int type = format & SF_FORMAT_TYPEMASK;
    const std::string ext = type == SF_FORMAT_FLAC ? ".flac" : type == SF_FORMAT_OGG ? ".ogg" : ".wav";
    const fs::path p = write_tone("tone44k" + ext, 44100, 1000.0, 1.0, format);
    Signal s = signal_from(R"({"type": "file", "path": ")" + p.string() + R"("})");
    const auto x = generate(s, 2.0);
    // One second at 44.1 kHz is one second at 48 kHz, still at 1 kHz.
    EXPECT_NEAR(test::peak_hz(std::span(x).subspan(4800, 38400), kRate, 900, 1100), 1000.0, 0.5) << ext;
    EXPECT_GT(test::rms(std::span(x).subspan(1000, 46000)), 0.3);
    EXPECT_LT(test::rms(std::span(x).subspan(48100, 40000)), 1e-3);  // then silence
    s.loop = true;
    const auto looped = generate(s, 2.0);
    EXPECT_GT(test::rms(std::span(looped).subspan(49000, 40000)), 0.3);  // round again
  }
}

TEST(FileSignal, MissingOrUnreadableFileNamesTheFile) {
  const fs::path dir = earshot::test::scratch_path("sound_tests");
  fs::create_directories(dir);
  Signal s;
  s.type = Signal::Type::file;
  s.path = dir / "no-such-file.wav";
  EXPECT_EQ(error_of([&] { SignalSource src(s, kRate); }), s.path.string() + ": audio file not found");
  s.path = dir / "not-audio.wav";
  std::ofstream(s.path) << "this is not a WAV file";
  const std::string e = error_of([&] { SignalSource src(s, kRate); });
  EXPECT_EQ(e.rfind(s.path.string() + ": cannot read audio file: ", 0), 0u) << e;
}

TEST(Sounds, GenerateNeverAllocates) {
  // Generators run in the render loop: after construction, not one allocation.
  for (const auto& json : kSounds) {
    SCOPED_TRACE(json);
    SignalSource src(signal_from(with_seed(json, 5)), kRate);
    std::vector<float> block(128);
    earshot::testing::AllocationProbe probe;
    for (int i = 0; i < 400; ++i) src.generate(block);  // about a second
    EXPECT_EQ(probe.count(), 0u);
  }
}
