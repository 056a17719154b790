#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "binaural_cues.hpp"
#include "earshot/errors.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "earshot/scenes/scene.hpp"
#include "earshot/host/scene_render.hpp"
#include "../scratch_path.hpp"

using namespace earshot::scenes;
using namespace earshot::host;  // render_scene
namespace fs = std::filesystem;

namespace {

std::string parse_error(const std::string& json) {
  try {
    (void)parse_scene(json, "s.json");
  } catch (const earshot::InputError& e) {
    return e.what();
  }
  return "";
}

struct Wav {
  std::vector<float> l, r;
};
Wav render(const std::string& json, const std::string& name) {
  const fs::path dir = earshot::test::scratch_path("scene_tests");
  fs::create_directories(dir);
  RenderOptions o;
  o.out = dir / (name + ".wav");
  render_scene(parse_scene(json, name), o);
  SF_INFO info{};
  SNDFILE* f = sf_open(o.out.c_str(), SFM_READ, &info);
  EXPECT_NE(f, nullptr);
  std::vector<float> inter(static_cast<std::size_t>(info.frames) * 2);
  sf_readf_float(f, inter.data(), info.frames);
  sf_close(f);
  Wav w;
  for (std::size_t i = 4800; i < inter.size() / 2; ++i) w.l.push_back(inter[2 * i]), w.r.push_back(inter[2 * i + 1]);
  return w;
}

}  // namespace

TEST(SceneJson, ListenerHeadSizeAndSourceAirAbsorption) {
  const Scene s = parse_scene(R"({"doppler_factor": 0.5, "speed_of_sound": 340,
      "listener": {"head_size": "large"},
      "sources": [{"signal": {"type": "noise"}, "air_absorption": 2}]})", "s.json");
  ASSERT_TRUE(s.listener.head_radius_m.has_value());
  EXPECT_DOUBLE_EQ(*s.listener.head_radius_m, 0.10);
  EXPECT_DOUBLE_EQ(s.sources[0].air_absorption, 2.0);
  EXPECT_DOUBLE_EQ(s.doppler_factor, 0.5);
  EXPECT_DOUBLE_EQ(s.speed_of_sound, 340.0);
  EXPECT_FALSE(parse_scene(R"({"sources": []})", "s.json").listener.head_radius_m.has_value());
  EXPECT_DOUBLE_EQ(*parse_scene(R"({"listener": {"head_size": 0.08}, "sources": []})", "s.json").listener.head_radius_m,
                   0.08);
}

TEST(SceneJson, BadValuesNameTheField) {
  EXPECT_EQ(parse_error(R"({"listener": {"head_size": "huge"}, "sources": []})"),
            "s.json: field 'listener.head_size': expected measured, small, medium, large or a radius in metres, got "
            "\"huge\"");
  EXPECT_EQ(parse_error(R"({"listener": {"head_size": 2}, "sources": []})"),
            "s.json: field 'listener.head_size': radius out of range: 2 (0.05 to 0.15 m)");
  EXPECT_EQ(parse_error(R"({"sources": [{"signal": {"type": "noise"}, "air_absorption": -1}]})"),
            "s.json: field 'sources[0].air_absorption': out of range: -1 (allowed 0 to 10)");
  EXPECT_EQ(parse_error(R"({"doppler_factor": "yes", "sources": []})"),
            "s.json: field 'doppler_factor': expected a number, got \"yes\"");
}

TEST(SceneJson, HeadSizeSetsTheRenderedItd) {
  // The thesis's listener sizes: a larger head hears a larger ITD, by as
  // much as Woodworth's formula says (0.10 m vs 0.075 m at 90 deg: 187 us).
  auto scene = [](const char* size) {
    return std::string(R"({"duration_s": 1, "listener": {"head_size": ")") + size +
           R"("}, "sources": [{"signal": {"type": "noise", "seed": 3}, "position": [-1, 0, 0], "gain_db": -12}]})";
  };
  const Wav small = render(scene("small"), "small"), large = render(scene("large"), "large");
  const double itd_small = earshot::analysis::itd_s(small.l, small.r, 48000.0);
  const double itd_large = earshot::analysis::itd_s(large.l, large.r, 48000.0);
  EXPECT_GT(itd_small, 400e-6);
  const double expect = earshot::hrtf::woodworth_itd(M_PI / 2, 0, 0.10) - earshot::hrtf::woodworth_itd(M_PI / 2, 0, 0.075);
  EXPECT_NEAR(itd_large - itd_small, expect, 5e-6);
}

TEST(SceneJson, AirAbsorptionDarkensAFarSource) {
  auto scene = [](int air) {
    return R"({"duration_s": 1, "sources": [{"signal": {"type": "noise", "seed": 3}, "position": [0, 0, -50],
               "distance_model": "none", "gain_db": -12, "air_absorption": )" +
           std::to_string(air) + "}]}";
  };
  const Wav dry = render(scene(0), "dry"), air = render(scene(3), "air");
  const double dry_hf = earshot::analysis::energy_above_db(dry.l, 48000.0, 8000.0);
  const double air_hf = earshot::analysis::energy_above_db(air.l, 48000.0, 8000.0);
  EXPECT_LT(air_hf, dry_hf - 3.0);  // 0.994^150: -7.5 dB above 5 kHz
}

TEST(SceneJson, DescriptionIsFreeText) {
  EXPECT_EQ(parse_scene(R"({"description": "a car passes", "sources": []})", "s.json").description, "a car passes");
  EXPECT_EQ(parse_scene(R"({"sources": []})", "s.json").description, "");
  EXPECT_EQ(parse_error(R"({"description": 3, "sources": []})"),
            "s.json: field 'description': expected a string, got 3");
}

// (Moved here from the reverb tests: it is about the scene parser.)
TEST(SceneJson, RoomTakesPresetNamesAndReverbItsType) {
  const auto s = parse_scene(R"({"room": "concert-hall", "reverb": "schroeder", "sources": []})", "s.json");
  EXPECT_EQ(s.room, "concert-hall");
  EXPECT_EQ(s.reverb, "schroeder");
  EXPECT_EQ(parse_scene(R"({"room": "generic", "sources": []})", "s.json").reverb, "fdn");
  try {
    (void)parse_scene(R"({"room": "concert_hall", "sources": []})", "s.json");
    FAIL() << "no error";
  } catch (const earshot::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("s.json"), std::string::npos) << what;
    EXPECT_NE(what.find("'room'"), std::string::npos) << what;
    EXPECT_NE(what.find("stone-corridor"), std::string::npos) << what;
  }
  EXPECT_THROW((void)parse_scene(R"({"room": "generic", "reverb": "moorer", "sources": []})", "s.json"),
               earshot::InputError);
}

// render_scene goes through the plugin's C API; what the plugin refuses still
// reaches the user as one InputError naming the file or field.
TEST(SceneRender, PluginPathReportsBadInputByName) {
  const fs::path dir = earshot::test::scratch_path("scene_tests");
  fs::create_directories(dir);
  const Scene one = parse_scene(R"({"duration_s": 0.1, "sources": [{"signal": {"type": "noise"}}]})", "one.json");
  auto error = [&](const Scene& s, RenderOptions o) -> std::string {
    o.out = dir / "refused.wav";
    try {
      (void)render_scene(s, o);
    } catch (const earshot::InputError& e) {
      return e.what();
    }
    return "";
  };
  RenderOptions o;
  const fs::path not_sofa = dir / "not_a.sofa";
  std::ofstream(not_sofa) << "{}";
  o.hrtf = not_sofa;
  EXPECT_NE(error(one, o).find(not_sofa.string() + ": not a SOFA file"), std::string::npos) << error(one, o);

  RenderOptions slow;
  slow.sample_rate = 4000;
  EXPECT_NE(error(one, slow).find("--rate"), std::string::npos) << error(one, slow);

  std::string many = R"({"duration_s": 0.1, "sources": [)";
  for (int i = 0; i < 257; ++i) many += std::string(i ? "," : "") + R"({"signal": {"type": "sine"}})";
  EXPECT_NE(error(parse_scene(many + "]}", "many.json"), {}).find("many.json: field 'sources': 257 sources"),
            std::string::npos);

  RenderOptions fine;
  fine.out = dir / "fine.wav";
  EXPECT_EQ(render_scene(one, fine).frames, 4800u);
}

TEST(SceneRoom, NamesAreCheckedAgainstThePresetTable) {
  EXPECT_TRUE(is_room_name("none"));
  EXPECT_TRUE(is_room_name("generic"));
  EXPECT_TRUE(is_room_name("default"));  // generic's other name
  EXPECT_FALSE(is_room_name("Generic"));
  EXPECT_FALSE(is_room_name("\", \"sources\": [{"));  // text that would have broken JSON built from it
  EXPECT_EQ(checked_room_name("hallway", "--room"), "hallway");
  try {
    (void)checked_room_name("bogus", "--room");
    ADD_FAILURE() << "bogus accepted";
  } catch (const earshot::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--room: unknown room preset 'bogus' (available: none, generic, ", 0), 0u) << e.what();
  }
  EXPECT_NE(parse_error(R"({"room": "bogus", "sources": []})").find("field 'room': unknown room preset 'bogus'"),
            std::string::npos);
}
