// The OpenAL Soft bridge on OpenAL Soft's loopback device with HRTF on: a
// recorded head turn (recorded_turn.csv, a Pose track CSV: 0 to 90 degrees
// to the left in 1 s) applied through esalBridgeUpdate moves a source that
// is ahead to the right ear, and every step sounds exactly as the same
// source placed where the pose says, head-relative, with the listener
// untouched.
#define AL_ALEXT_PROTOTYPES
#include <AL/al.h>
#include <AL/alc.h>
#include <AL/alext.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "binaural_cues.hpp"
#include "earshot/earshot_openal_bridge.h"

namespace {

constexpr int kRate = 48000;
constexpr std::size_t kSegment = 4800;  // 100 ms per recorded pose
constexpr std::size_t kSettle = 1200;   // OpenAL Soft fades HRTF changes in

struct Loopback {
  ALCdevice* device = nullptr;
  ALCcontext* context = nullptr;
  ALuint buffer = 0, source = 0;
  bool hrtf = false;

  Loopback() {
    device = alcLoopbackOpenDeviceSOFT(nullptr);
    if (!device) return;
    const ALCint attrs[] = {ALC_FORMAT_CHANNELS_SOFT, ALC_STEREO_SOFT, ALC_FORMAT_TYPE_SOFT, ALC_FLOAT_SOFT,
                            ALC_FREQUENCY, kRate, ALC_HRTF_SOFT, ALC_TRUE, 0};
    context = alcCreateContext(device, attrs);
    if (!context) return;
    alcMakeContextCurrent(context);
    ALCint status = 0;
    alcGetIntegerv(device, ALC_HRTF_STATUS_SOFT, 1, &status);
    hrtf = status == ALC_HRTF_ENABLED_SOFT;
    std::vector<float> noise(kRate);
    unsigned s = 5;
    for (auto& v : noise) {
      s = s * 1664525u + 1013904223u;
      v = 0.3f * (static_cast<float>(s >> 8) / 8388608.0f - 1.0f);
    }
    alGenBuffers(1, &buffer);
    alBufferData(buffer, AL_FORMAT_MONO_FLOAT32, noise.data(), static_cast<ALsizei>(noise.size() * sizeof(float)), kRate);
    alGenSources(1, &source);
    alSourcei(source, AL_BUFFER, static_cast<ALint>(buffer));
    alSourcei(source, AL_LOOPING, AL_TRUE);
    alSource3f(source, AL_POSITION, 0, 0, -2);
    alSourcePlay(source);
  }
  ~Loopback() {
    if (source) alDeleteSources(1, &source);
    if (buffer) alDeleteBuffers(1, &buffer);
    alcMakeContextCurrent(nullptr);
    if (context) alcDestroyContext(context);
    if (device) alcCloseDevice(device);
  }
  Loopback(const Loopback&) = delete;
  Loopback& operator=(const Loopback&) = delete;

  /// One segment; the cues of its settled part: ILD dB, ITD s.
  std::pair<double, double> cues() {
    std::vector<float> inter(2 * kSegment), l(kSegment), r(kSegment);
    alcRenderSamplesSOFT(device, inter.data(), static_cast<ALCsizei>(kSegment));
    for (std::size_t i = 0; i < kSegment; ++i) {
      l[i] = inter[2 * i];
      r[i] = inter[2 * i + 1];
    }
    const std::span<const float> ls = std::span(l).subspan(kSettle), rs = std::span(r).subspan(kSettle);
    return {earshot::analysis::ild_db(ls, rs), earshot::analysis::itd_s(ls, rs, kRate)};
  }
};

struct Pose {
  double t;
  std::array<float, 3> position;
  std::array<float, 4> orientation;
};

std::vector<Pose> read_track(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  std::vector<Pose> poses;
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream f(line);
    Pose p{};
    f >> p.t >> p.position[0] >> p.position[1] >> p.position[2] >> p.orientation[0] >> p.orientation[1] >>
        p.orientation[2] >> p.orientation[3];
    if (f) poses.push_back(p);
  }
  return poses;
}

/// v rotated by the inverse of unit quaternion q: the world point as the head sees it.
std::array<double, 3> to_head(const std::array<float, 4>& q, std::array<double, 3> v) {
  const double w = q[0], x = -q[1], y = -q[2], z = -q[3];
  const double tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  return {v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)};
}

TEST(OpenAlBridge, RecordedHeadTurnMovesTheCuesAsThePoseSays) {
  const auto track = read_track(EARSHOT_RECORDED_TURN);
  ASSERT_EQ(track.size(), 11u);
  std::vector<std::pair<double, double>> bridged, placed;
  {
    Loopback al;
    ASSERT_TRUE(al.context) << "no OpenAL Soft loopback context";
    ASSERT_TRUE(al.hrtf) << "OpenAL Soft did not enable HRTF (libopenal-data installed?)";
    ESALbridge* bridge = nullptr;
    ASSERT_EQ(esalCreateBridge(nullptr, &bridge), ES_OK);
    const ESfloat origin[3] = {0, 0, 0}, ahead[6] = {0, 0, -1, 0, 1, 0};
    ASSERT_EQ(esalBridgeSetListener(bridge, origin, ahead), ES_OK);
    for (const Pose& p : track) {
      ASSERT_EQ(esalBridgeSetHeadPose(bridge, p.position.data(), p.orientation.data()), ES_OK);
      ASSERT_EQ(esalBridgeUpdate(bridge), ES_OK);
      bridged.push_back(al.cues());
    }
    const ESfloat nan_pose[4] = {NAN, 0, 0, 0};
    EXPECT_EQ(esalBridgeSetHeadPose(bridge, origin, nan_pose), ES_INVALID_VALUE);
    esalDestroyBridge(bridge);
  }
  {
    // The reference: the listener as OpenAL's default, the source moved to
    // where the recorded pose puts it relative to the head.
    Loopback al;
    ASSERT_TRUE(al.hrtf);
    for (const Pose& p : track) {
      const auto h = to_head(p.orientation, {0, 0, -2});
      alSource3f(al.source, AL_POSITION, static_cast<ALfloat>(h[0]), static_cast<ALfloat>(h[1]), static_cast<ALfloat>(h[2]));
      placed.push_back(al.cues());
    }
  }
  for (std::size_t i = 0; i < track.size(); ++i) {
    SCOPED_TRACE("pose " + std::to_string(i) + ", yaw " + std::to_string(9 * i) + " deg");
    EXPECT_NEAR(bridged[i].first, placed[i].first, 0.2);
    EXPECT_NEAR(bridged[i].second, placed[i].second, 10e-6);
    std::printf("yaw %3zu deg: ILD %+6.2f dB (placed %+6.2f), ITD %+7.1f us (placed %+7.1f)\n", 9 * i,
                bridged[i].first, placed[i].first, bridged[i].second * 1e6, placed[i].second * 1e6);
  }
  // Ahead at the start; turning left puts the source at the right ear:
  // the right ear leads (ITD < 0) and is louder (ILD < 0), more so with the turn.
  EXPECT_NEAR(bridged.front().first, 0.0, 1.5);
  EXPECT_NEAR(bridged.front().second, 0.0, 30e-6);
  EXPECT_LT(bridged.back().first, -8.0);
  EXPECT_LT(bridged.back().second, -500e-6);
  EXPECT_LT(bridged[5].second, -200e-6);
  EXPECT_LT(bridged.back().second, bridged[5].second);
}

TEST(OpenAlBridge, UpdateWithoutAContextIsAnError) {
  alcMakeContextCurrent(nullptr);
  ESALbridge* bridge = nullptr;
  ASSERT_EQ(esalCreateBridge(nullptr, &bridge), ES_OK);
  EXPECT_EQ(esalBridgeUpdate(bridge), ES_INVALID_OPERATION);
  EXPECT_EQ(esalBridgeUpdate(nullptr), ES_INVALID_VALUE);
  esalDestroyBridge(bridge);
  EXPECT_EQ(esalCreateBridge("carrier-pigeon", &bridge), ES_TRACKER_ERROR);
  EXPECT_EQ(bridge, nullptr);
}

}  // namespace
