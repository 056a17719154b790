// Scene JSON beds and quality: parsed and checked with the field named; a
// bed rendered through the plugin's world (streamed by FieldPlayer) heard
// from its side and turned by its yaw; a file at another rate resampled; a
// bed that does not loop falls silent at its end; the tier chosen by the
// scene.
#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "binaural_cues.hpp"
#include "earshot/errors.hpp"
#include "earshot/host/scene_render.hpp"
#include "earshot/scenes/field_stream.hpp"
#include "earshot/scenes/scene.hpp"
#include "../scratch_path.hpp"

using namespace earshot::scenes;
namespace fs = std::filesystem;

namespace {

const fs::path kBedDir = earshot::test::scratch_path("scene_beds");

/// A first-order plane wave of noise from azimuth `az_deg` (90 = left), `seconds` at `rate`.
fs::path write_field(const std::string& name, double az_deg, int rate, double seconds) {
  fs::create_directories(kBedDir);
  const fs::path p = kBedDir / name;
  SF_INFO info{};
  info.samplerate = rate;
  info.channels = 4;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  SNDFILE* f = sf_open(p.c_str(), SFM_WRITE, &info);
  EXPECT_NE(f, nullptr);
  const double az = az_deg * 3.14159265358979323846 / 180.0;
  const auto n = static_cast<std::size_t>(seconds * rate);
  std::vector<float> x(4 * n);
  unsigned s = 7;
  for (std::size_t i = 0; i < n; ++i) {
    s = s * 1664525u + 1013904223u;
    const float v = 0.2f * (static_cast<float>(s >> 8) / 8388608.0f - 1.0f);
    x[4 * i] = v;
    x[4 * i + 1] = static_cast<float>(std::sin(az)) * v;
    x[4 * i + 3] = static_cast<float>(std::cos(az)) * v;
  }
  sf_writef_float(f, x.data(), static_cast<sf_count_t>(n));
  sf_close(f);
  return p;
}

struct Heard {
  double ild_db, rms_tail;
};

Heard render_bed_scene(const std::string& json, const std::string& name) {
  earshot::host::RenderOptions o;
  o.out = kBedDir / (name + ".wav");
  (void)earshot::host::render_scene(parse_scene(json, name + ".json", kBedDir), o);
  SF_INFO info{};
  SNDFILE* f = sf_open(o.out.c_str(), SFM_READ, &info);
  EXPECT_NE(f, nullptr);
  std::vector<float> inter(static_cast<std::size_t>(info.frames) * 2);
  sf_readf_float(f, inter.data(), info.frames);
  sf_close(f);
  std::vector<float> l, r;
  const std::size_t frames = inter.size() / 2;
  for (std::size_t i = 4800; i < frames * 6 / 10; ++i) l.push_back(inter[2 * i]), r.push_back(inter[2 * i + 1]);
  double tail = 0;
  for (std::size_t i = frames * 9 / 10; i < frames; ++i) tail += double(inter[2 * i]) * inter[2 * i];
  return {earshot::analysis::ild_db(l, r), std::sqrt(tail / double(frames / 10))};
}

std::string bed_parse_error(const std::string& json) {
  try {
    (void)parse_scene(json, "b.json");
  } catch (const earshot::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SceneBeds, ParsedWithTheirFieldsAndChecked) {
  const Scene s = parse_scene(R"({"quality": "ambisonic:3", "beds": [{"path": "f.wav", "convention": "fuma",
                                   "gain_db": -6, "yaw_deg": 30, "loop": true}]})",
                              "b.json", "/data");
  ASSERT_EQ(s.beds.size(), 1u);
  EXPECT_EQ(s.beds[0].path, fs::path("/data/f.wav"));
  EXPECT_EQ(s.beds[0].convention, "fuma");
  EXPECT_EQ(s.beds[0].gain_db, -6);
  EXPECT_EQ(s.beds[0].yaw_deg, 30);
  EXPECT_TRUE(s.beds[0].loop);
  EXPECT_TRUE(s.sources.empty());
  EXPECT_EQ(s.quality, "ambisonic:3");
  EXPECT_EQ(quality_order("direct"), 0);
  EXPECT_EQ(quality_order("ambisonic:5"), 5);
  EXPECT_FALSE(quality_order("ambisonic:0"));
  EXPECT_FALSE(quality_order("ambisonic:33"));
  EXPECT_NE(bed_parse_error(R"({"beds": [{"path": "f.wav", "convention": "b-format"}]})")
                .find("field 'beds[0].convention': unknown convention 'b-format'"),
            std::string::npos);
  EXPECT_NE(bed_parse_error(R"({"beds": [{"gain_db": 0}]})").find("field 'beds[0].path': missing"), std::string::npos);
  EXPECT_NE(bed_parse_error(R"({"beds": [{"path": "f.wav", "colour": 1}]})").find("field 'beds[0].colour': unknown field"),
            std::string::npos);
  EXPECT_NE(bed_parse_error(R"({"quality": "best", "sources": []})").find("field 'quality': unknown quality 'best'"),
            std::string::npos);
  EXPECT_NE(bed_parse_error(R"({"quality": "direct"})").find("field 'sources'"), std::string::npos);  // no beds: sources needed
}

TEST(SceneBeds, ABedIsHeardFromItsSideTurnedByItsYawAndEndsSilent) {
  write_field("left.wav", 90, 48000, 1.0);
  write_field("ahead_44k.wav", 0, 44100, 1.0);
  const Heard left = render_bed_scene(R"({"duration_s": 1.5, "beds": [{"path": "left.wav"}]})", "bed_left");
  EXPECT_GT(left.ild_db, 6.0);
  EXPECT_LT(left.rms_tail, 1e-6);  // 1 s of file, 1.5 s rendered: silent at the end
  // A field from ahead at 44.1 kHz (resampled), turned 90 degrees left by the bed's yaw.
  const Heard turned = render_bed_scene(R"({"duration_s": 1.5, "beds": [{"path": "ahead_44k.wav", "yaw_deg": 90,
                                            "loop": true}]})",
                                        "bed_turned");
  EXPECT_GT(turned.ild_db, 6.0);
  EXPECT_GT(turned.rms_tail, 1e-3);  // looping: still playing
  const Heard ahead = render_bed_scene(R"({"duration_s": 1.0, "beds": [{"path": "ahead_44k.wav"}],
                                          "sources": [{"signal": {"type": "noise"}, "position": [0, 0, -2]}],
                                          "quality": "ambisonic:2"})",
                                       "bed_and_tier");
  EXPECT_NEAR(ahead.ild_db, 0.0, 1.0);
}

TEST(SceneBeds, AFileThatIsNotAmbisonicIsAnErrorNamingIt) {
  fs::create_directories(kBedDir);
  const fs::path p = kBedDir / "stereo.wav";
  SF_INFO info{};
  info.samplerate = 48000;
  info.channels = 2;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  SNDFILE* f = sf_open(p.c_str(), SFM_WRITE, &info);
  ASSERT_NE(f, nullptr);
  std::vector<float> x(200, 0.1f);
  sf_writef_float(f, x.data(), 100);
  sf_close(f);
  earshot::host::RenderOptions o;
  o.out = kBedDir / "never.wav";
  try {
    (void)earshot::host::render_scene(parse_scene(R"({"beds": [{"path": "stereo.wav"}]})", "s.json", kBedDir), o);
    FAIL() << "a 2-channel bed was accepted";
  } catch (const earshot::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stereo.wav: field 'channels': 2 channels"), std::string::npos) << e.what();
  }
}
