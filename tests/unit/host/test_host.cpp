// The host layer: a Scene turned into plugin calls (world, sources, room,
// paths, tracker) and the WAV writer, checked through the plugin's getters.
#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <vector>

#include "earshot/errors.hpp"
#include "earshot/host/distance_models.hpp"
#include "earshot/host/listener.hpp"
#include "earshot/host/rooms.hpp"
#include "earshot/host/scene_sources.hpp"
#include "earshot/host/tracker_status.hpp"
#include "earshot/host/wav_writer.hpp"
#include "earshot/host/world_handle.hpp"
#include "earshot/scenes/scene.hpp"
#include "../scratch_path.hpp"

namespace {

using namespace earshot;
namespace fs = std::filesystem;

ESworldparams params() {
  ESworldparams p;
  esWorldParamsDefault(&p);
  p.block_size = 128;
  return p;
}

scenes::Scene two_sources() {
  scenes::Scene s;
  s.origin = "two.json";
  s.room = "living-room";
  scenes::SceneSource a;
  a.name = "still";
  a.signal.type = scenes::Signal::Type::sine;
  a.position = {1, 0, -2};
  a.gain_db = -6;
  a.distance.model = audio::DistanceModel::linear;
  scenes::SceneSource b;
  b.name = "moving";
  scenes::CirclePath circle;
  circle.radius = 2;
  circle.period_s = 8;
  b.path = circle;
  s.sources = {a, b};
  return s;
}

std::array<float, 3> position_of(ESworld w, ESsource id) {
  std::array<float, 3> x{};
  EXPECT_EQ(esGetSourcefv(w, id, ES_POSITION, x.data()), ES_OK);
  return x;
}

TEST(HostDistanceModels, EveryModelHasItsOwnPluginValueAndIndex) {
  std::set<ESenum> seen;
  for (std::size_t i = 0; i < host::kDistanceModels.size(); ++i) {
    const auto m = host::kDistanceModels[i].model;
    seen.insert(host::es_distance_model(m));
    EXPECT_EQ(host::distance_model_index(m), int(i));
  }
  EXPECT_EQ(seen.size(), host::kDistanceModels.size());
  EXPECT_EQ(host::es_distance_model(audio::DistanceModel::inverse_clamped), ES_INVERSE_DISTANCE_CLAMPED);
  EXPECT_EQ(host::es_distance_model(audio::DistanceModel::none), ES_NONE);
}

TEST(HostRooms, EveryListedRoomPassesTheSceneCheckAndAnUnknownOneIsNamed) {
  EXPECT_EQ(host::room_names().front(), "none");
  for (const auto& r : host::room_names()) EXPECT_EQ(scenes::checked_room_name(r, "--room"), r);
  try {
    (void)scenes::checked_room_name("nope", "--room");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--room"), std::string::npos) << m;
    EXPECT_NE(m.find("'nope'"), std::string::npos) << m;
    EXPECT_NE(m.find("concert-hall"), std::string::npos) << m;
  }
}

TEST(HostWorld, ABadParameterIsAnInputErrorWithThePluginsReason) {
  ESworldparams p = params();
  p.sample_rate = 10;
  try {
    const host::WorldHandle w(p);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sample_rate"), std::string::npos) << e.what();
  }
}

TEST(HostSceneSources, LoadSetsSourcesRoomAndGainAndPathsMove) {
  const host::WorldHandle world(params());
  host::SceneSources sources(world, 48000);
  sources.load(two_sources());
  ASSERT_EQ(sources.size(), 2u);
  const ESworld w = world.id();
  float gain = 0;
  ASSERT_EQ(esGetSourcef(w, sources.id(0), ES_GAIN, &gain), ES_OK);
  EXPECT_NEAR(gain, std::pow(10.0, -6 / 20.0), 1e-6);
  ESint model = 0;
  ASSERT_EQ(esGetSourcei(w, sources.id(0), ES_DISTANCE_MODEL, &model), ES_OK);
  EXPECT_EQ(model, ES_LINEAR_DISTANCE);
  sources.move(10.0);  // the paths' clock starts here
  sources.move(12.0);
  const auto heard = position_of(w, sources.id(1));
  const auto at0 = sources.position(1, 10.0), at2 = sources.position(1, 12.0);
  EXPECT_NEAR(std::hypot(at0[0], at0[2]), 2.0, 1e-9);
  EXPECT_GT(std::hypot(at2[0] - at0[0], at2[2] - at0[2]), 1.0) << "a quarter turn later it moved";
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(heard[std::size_t(k)], at2[std::size_t(k)], 1e-6);
  const auto fixed = sources.position(0, 12.0);
  EXPECT_EQ(fixed[0], 1.0);
  EXPECT_EQ(fixed[2], -2.0);
  EXPECT_EQ(sources.scene().room, "living-room");
}

TEST(HostSceneSources, ASoundThatCannotBeMadeChangesNothing) {
  const host::WorldHandle world(params());
  host::SceneSources sources(world, 48000);
  sources.load(two_sources());
  scenes::Scene bad = two_sources();
  bad.sources[0].signal.type = scenes::Signal::Type::file;
  bad.sources[0].signal.path = "/no/such/sound.wav";
  bad.room = "none";
  EXPECT_THROW(sources.load(bad), InputError);
  EXPECT_EQ(sources.size(), 2u);
  EXPECT_EQ(sources.scene().room, "living-room");
  EXPECT_THROW(sources.set_sound(0, bad.sources[0].signal), InputError);
  EXPECT_EQ(sources.scene().sources[0].signal.type, scenes::Signal::Type::sine);
}

TEST(HostSceneSources, LiveEditsReachThePluginAndTheScene) {
  const host::WorldHandle world(params());
  host::SceneSources sources(world, 48000);
  sources.load(two_sources());
  sources.set_gain_distance(0, -20, audio::DistanceModel::exponent, 2.0, 3.0);
  float rolloff = 0;
  ASSERT_EQ(esGetSourcef(world.id(), sources.id(0), ES_ROLLOFF_FACTOR, &rolloff), ES_OK);
  EXPECT_EQ(rolloff, 2.0f);
  EXPECT_EQ(sources.scene().sources[0].gain_db, -20);
  EXPECT_EQ(sources.scene().sources[0].distance.model, audio::DistanceModel::exponent);
  sources.set_position(1, {3, 0, 0});
  EXPECT_FALSE(sources.scene().sources[1].path);
  const auto x = sources.position(1, 100.0);
  EXPECT_EQ(x[0], 3.0);
  EXPECT_EQ(position_of(world.id(), sources.id(1))[0], 3.0f);
  sources.set_room("none");
  EXPECT_EQ(sources.scene().room, "none");
  EXPECT_THROW(sources.set_room("no-such-room"), InputError);
}

TEST(HostTracker, ARefusedTrackerIsAnAlarmAndNoneIsQuiet) {
  const host::WorldHandle world(params());
  auto bad = host::attach_tracker(world.id(), "no-such-tracker");
  EXPECT_FALSE(bad.failed.empty());
  bad.refresh(world.id());
  EXPECT_EQ(bad.state, "failed");
  EXPECT_TRUE(bad.alarm);
  auto none = host::attach_tracker(world.id(), "");
  EXPECT_EQ(none.spec, "none");
  none.refresh(world.id());
  EXPECT_EQ(none.state, "none");
  EXPECT_FALSE(none.alarm);
  EXPECT_STREQ(host::tracker_state_name(ES_TRACKER_TRACKING), "tracking");
}

TEST(HostWavWriter, WritesWhatItIsGivenAndNamesAFileItCannotWrite) {
  const fs::path out = earshot::test::scratch_path("host-writer.wav");
  const std::vector<float> left{0.5f, -0.25f, 0.0f}, right{0.125f, 1.0f, -1.0f};
  {
    host::WavWriter w(out, 44100, host::WavFormat::float32);
    w.write(left, right);
    const std::vector<float> lr{0.75f, -0.75f};
    w.write_interleaved(lr);
  }
  SF_INFO info{};
  SNDFILE* f = sf_open(out.c_str(), SFM_READ, &info);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(info.samplerate, 44100);
  EXPECT_EQ(info.channels, 2);
  ASSERT_EQ(info.frames, 4);
  std::vector<float> got(8);
  EXPECT_EQ(sf_readf_float(f, got.data(), 4), 4);
  sf_close(f);
  EXPECT_EQ(got, (std::vector<float>{0.5f, 0.125f, -0.25f, 1.0f, 0.0f, -1.0f, 0.75f, -0.75f}));
  try {
    host::WavWriter w("/no/such/dir/x.wav", 48000, host::WavFormat::pcm24);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/dir/x.wav"), std::string::npos) << e.what();
  }
}

TEST(HostListener, TheScenesListenerIsTurnedByItsYaw) {
  scenes::SceneListener l;
  l.position = {1, 2, 3};
  l.yaw_deg = 90;
  const auto s = host::fixed_listener(l);
  EXPECT_EQ(s.position, (earshot::Vec3{1, 2, 3}));
  EXPECT_NEAR(std::abs(s.orientation[0]), std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(std::abs(s.orientation[2]), std::sqrt(0.5), 1e-9);
}

}  // namespace
