// The plugin in a real LV2 host: lilv's lv2apply pans a noise file to each
// of a set of azimuths; `earshot render` renders the same source in a Scene
// JSON; both files' interaural cues (ITD from the cross-correlation, ILD)
// must agree. Prints the cue table docs/BENCHMARKS.md quotes.
#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "binaural_cues.hpp"

namespace fs = std::filesystem;

namespace {

constexpr int kRate = 48000;

struct Stereo {
  std::vector<float> left, right;
};

void write_mono(const fs::path& path, const std::vector<float>& x) {
  SF_INFO info{};
  info.samplerate = kRate;
  info.channels = 1;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
  ASSERT_NE(f, nullptr) << sf_strerror(nullptr);
  ASSERT_EQ(sf_writef_float(f, x.data(), static_cast<sf_count_t>(x.size())), static_cast<sf_count_t>(x.size()));
  sf_close(f);
}

Stereo read_stereo(const fs::path& path) {
  SF_INFO info{};
  SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
  if (!f) throw std::runtime_error("cannot read " + path.string());
  std::vector<float> all(static_cast<std::size_t>(info.frames * info.channels));
  sf_readf_float(f, all.data(), info.frames);
  sf_close(f);
  if (info.channels != 2) throw std::runtime_error(path.string() + ": not stereo");
  Stereo s;
  for (sf_count_t i = 0; i < info.frames; ++i) {
    s.left.push_back(all[static_cast<std::size_t>(2 * i)]);
    s.right.push_back(all[static_cast<std::size_t>(2 * i + 1)]);
  }
  return s;
}

int run(const std::string& cmd) { return std::system(cmd.c_str()); }

struct Cues {
  double itd_us, ild_db;
};

/// Cues over the settled part (from 0.1 s, past the latency and any delay).
Cues cues(const Stereo& s) {
  const std::size_t from = kRate / 10, n = s.left.size() - from - kRate / 20;
  const std::span<const float> l(s.left.data() + from, n), r(s.right.data() + from, n);
  return {earshot::analysis::itd_s(l, r, kRate) * 1e6, earshot::analysis::ild_db(l, r)};
}

}  // namespace

TEST(Lv2Hosts, Lv2applyGivesTheCuesOfEarshotRender) {
  const fs::path work = fs::path(EARSHOT_WORK) / "lv2apply";
  fs::create_directories(work);
  std::mt19937 rng(11);
  std::normal_distribution<float> d(0.0f, 0.1f);
  std::vector<float> noise(kRate);
  for (auto& x : noise) x = d(rng);
  write_mono(work / "noise.wav", noise);

  std::printf("| azimuth | lv2apply ITD us | render ITD us | lv2apply ILD dB | render ILD dB |\n|---:|---:|---:|---:|---:|\n");
  for (int az : {-150, -90, -60, -30, 0, 30, 60, 90, 150}) {
    const std::string tag = std::to_string(az);
    const fs::path plugged = work / ("lv2_" + tag + ".wav"), rendered = work / ("render_" + tag + ".wav");
    const std::string lv2 = "LV2_PATH='" EARSHOT_LV2_PATH "' lv2apply -i '" + (work / "noise.wav").string() +
                            "' -o '" + plugged.string() + "' -c azimuth " + tag + " urn:earshot:lv2:panner";
    ASSERT_EQ(run(lv2), 0) << lv2;

    const double a = az * std::numbers::pi / 180.0;
    const fs::path scene = work / ("scene_" + tag + ".json");
    std::ofstream(scene) << "{\"duration_s\": 1, \"sample_rate\": 48000, \"room\": \"none\",\n"
                         << " \"sources\": [{\"name\": \"noise\", \"signal\": {\"type\": \"file\", \"path\": \"noise.wav\"},\n"
                         << "   \"position\": [" << -std::sin(a) << ", 0, " << -std::cos(a) << "]}]}\n";
    const std::string render = std::string("'") + EARSHOT_EXE + "' render --scene '" + scene.string() + "' --out '" +
                               rendered.string() + "' > /dev/null";
    ASSERT_EQ(run(render), 0) << render;

    const Cues p = cues(read_stereo(plugged)), r = cues(read_stereo(rendered));
    std::printf("| %d | %.1f | %.1f | %.2f | %.2f |\n", az, p.itd_us, r.itd_us, p.ild_db, r.ild_db);
    EXPECT_NEAR(p.itd_us, r.itd_us, 5.0) << "azimuth " << az;
    EXPECT_NEAR(p.ild_db, r.ild_db, 0.1) << "azimuth " << az;
    // And the plugin puts positive azimuths on the left (ITD > 0: left leads).
    if (az >= 30 && az <= 150) {
      EXPECT_GT(p.itd_us, 100.0) << "azimuth " << az;
    }
    if (az <= -30) {
      EXPECT_LT(p.itd_us, -100.0) << "azimuth " << az;
    }
  }
}

// Debian's lv2file: its feature array holds an entry whose URI is NULL (the
// plugin used to crash at instantiate, exit 139). It must run the plugin to
// the end with the cues of a source on the left, list the presets, apply
// one, and with the bypass (lv2:enabled) off give the input back, delayed
// by the latency, on both channels.
TEST(Lv2Hosts, Lv2fileRunsThePluginListsAndAppliesPresetsAndBypasses) {
  ASSERT_EQ(run("command -v lv2file > /dev/null"), 0) << "lv2file not found: install it (scripts/install-deps.sh)";
  const fs::path work = fs::path(EARSHOT_WORK) / "lv2file";
  fs::create_directories(work);
  std::mt19937 rng(12);
  std::normal_distribution<float> d(0.0f, 0.1f);
  std::vector<float> noise(kRate);
  for (auto& x : noise) x = d(rng);
  write_mono(work / "noise.wav", noise);
  const std::string env = "LV2_PATH='" EARSHOT_LV2_PATH "' ";
  const std::string in = " -i '" + (work / "noise.wav").string() + "'";

  const fs::path left = work / "left.wav";
  std::string cmd = env + "lv2file" + in + " -o '" + left.string() + "' -p azimuth:60 urn:earshot:lv2:panner";
  ASSERT_EQ(run(cmd), 0) << cmd;
  const Cues c = cues(read_stereo(left));
  EXPECT_GT(c.ild_db, 6.0) << "azimuth 60 is on the left";
  EXPECT_GT(c.itd_us, 100.0);

  const fs::path listed = work / "presets.txt";
  cmd = env + "lv2file -L urn:earshot:lv2:panner > '" + listed.string() + "' 2>&1";
  ASSERT_EQ(run(cmd), 0) << cmd;
  std::ifstream f(listed);
  const std::string list((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  for (const char* p : {"Straight ahead", "OSC head tracking", "opentrack head tracking", "Webcam tag"})
    EXPECT_NE(list.find(p), std::string::npos) << p << " not in lv2file's list:\n" << list;

  const fs::path ahead = work / "ahead.wav";
  cmd = env + "lv2file" + in + " -o '" + ahead.string() + "' -P 'Straight ahead' urn:earshot:lv2:panner";
  ASSERT_EQ(run(cmd), 0) << cmd;
  EXPECT_LT(std::abs(cues(read_stereo(ahead)).ild_db), 1.0) << "the straight-ahead preset";

  const fs::path dry = work / "bypassed.wav";
  cmd = env + "lv2file" + in + " -o '" + dry.string() + "' -p azimuth:60 -p enabled:0 urn:earshot:lv2:panner";
  ASSERT_EQ(run(cmd), 0) << cmd;
  const Stereo b = read_stereo(dry);
  ASSERT_EQ(b.left.size(), noise.size());
  double worst = 0;
  for (std::size_t i = 128; i < noise.size(); ++i)
    worst = std::max({worst, std::abs(double(b.left[i]) - noise[i - 128]), std::abs(double(b.right[i]) - noise[i - 128])});
  EXPECT_LT(worst, 1e-6) << "bypassed: the input, 128 frames later, on both channels";
}

namespace {

/// A plane wave of `x` from azimuth `az_deg` (ambiX: counter-clockwise, 90 =
/// left) at order `order`, ACN/SN3D, as a (N+1)^2-channel float WAV.
void write_plane_wave(const fs::path& path, const std::vector<float>& x, int order, double az_deg) {
  const int C = (order + 1) * (order + 1);
  // Horizontal SN3D gains: degree l, index m: cos(m az) for m >= 0, sin(|m| az)
  // for m < 0, times N_l^|m| P_l^|m|(0) (the sectoral and zero entries are
  // all the horizontal plane needs up to order 3).
  const double az = az_deg * std::numbers::pi / 180.0;
  std::vector<double> g(static_cast<std::size_t>(C), 0.0);
  const auto set = [&](int l, int m, double v) { g[static_cast<std::size_t>(l * l + l + m)] = v; };
  set(0, 0, 1.0);
  if (order >= 1) set(1, -1, std::sin(az)), set(1, 1, std::cos(az));
  if (order >= 2) set(2, -2, std::sqrt(3.0) / 2 * std::sin(2 * az)), set(2, 0, -0.5), set(2, 2, std::sqrt(3.0) / 2 * std::cos(2 * az));
  if (order >= 3) {
    set(3, -3, std::sqrt(5.0 / 8.0) * std::sin(3 * az)), set(3, 3, std::sqrt(5.0 / 8.0) * std::cos(3 * az));
    set(3, -1, -std::sqrt(3.0 / 8.0) * std::sin(az)), set(3, 1, -std::sqrt(3.0 / 8.0) * std::cos(az));
  }
  SF_INFO info{};
  info.samplerate = kRate;
  info.channels = C;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
  ASSERT_NE(f, nullptr) << sf_strerror(nullptr);
  std::vector<float> inter(x.size() * static_cast<std::size_t>(C));
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int c = 0; c < C; ++c) inter[i * static_cast<std::size_t>(C) + static_cast<std::size_t>(c)] = static_cast<float>(g[static_cast<std::size_t>(c)]) * x[i];
  ASSERT_EQ(sf_writef_float(f, inter.data(), static_cast<sf_count_t>(x.size())), static_cast<sf_count_t>(x.size()));
  sf_close(f);
}

/// Cues over the settled part, the ITD below 1.5 kHz: a MagLS decoder keeps
/// the HRTF's phase only below its transition (the ITD is heard there).
Cues low_band_cues(const Stereo& s) {
  const std::size_t from = kRate / 10, n = s.left.size() - from - kRate / 20;
  const std::span<const float> l(s.left.data() + from, n), r(s.right.data() + from, n);
  return {earshot::analysis::itd_s(l, r, kRate, 1.2e-3, 1500.0) * 1e6, earshot::analysis::ild_db(l, r)};
}

}  // namespace

// The Ambisonic decoders in lilv's lv2apply against `earshot render --ambix`
// (the same decoder, designed once and cached, through the world): the same
// cues for a plane wave from each azimuth, order 3; orders 1 and 5 load and
// put a wave from the left on the left.
TEST(Lv2Hosts, Lv2applyAmbisonicDecoderGivesTheCuesOfEarshotRender) {
  const fs::path work = fs::path(EARSHOT_WORK) / "lv2apply_ambi";
  fs::create_directories(work);
  std::mt19937 rng(12);
  std::normal_distribution<float> d(0.0f, 0.1f);
  std::vector<float> noise(kRate);
  for (auto& x : noise) x = d(rng);
  std::printf("| azimuth | lv2apply ITD < 1.5 kHz us | render --ambix ITD < 1.5 kHz us | lv2apply ILD dB | render --ambix ILD dB |\n"
              "|---:|---:|---:|---:|---:|\n");
  for (int az : {-120, -90, -45, 0, 45, 90, 120}) {
    const std::string tag = std::to_string(az);
    const fs::path field = work / ("field_" + tag + ".wav"), plugged = work / ("lv2_" + tag + ".wav"),
                   rendered = work / ("render_" + tag + ".wav");
    write_plane_wave(field, noise, 3, az);
    const std::string lv2 = "LV2_PATH='" EARSHOT_LV2_PATH "' lv2apply -i '" + field.string() + "' -o '" +
                            plugged.string() + "' urn:earshot:lv2:ambi-binaural-o3";
    ASSERT_EQ(run(lv2), 0) << lv2;
    const std::string render = std::string("'") + EARSHOT_EXE + "' render --ambix '" + field.string() + "' --out '" +
                               rendered.string() + "' > /dev/null";
    ASSERT_EQ(run(render), 0) << render;
    const Cues p = low_band_cues(read_stereo(plugged)), r = low_band_cues(read_stereo(rendered));
    std::printf("| %d | %.1f | %.1f | %.2f | %.2f |\n", az, p.itd_us, r.itd_us, p.ild_db, r.ild_db);
    EXPECT_NEAR(p.itd_us, r.itd_us, 5.0) << "azimuth " << az;
    EXPECT_NEAR(p.ild_db, r.ild_db, 0.1) << "azimuth " << az;
    if (az >= 45) {
      EXPECT_GT(p.ild_db, 3.0) << "azimuth " << az;
      EXPECT_GT(p.itd_us, 200.0) << "azimuth " << az;  // the left ear leads
    }
    if (az <= -45) {
      EXPECT_LT(p.ild_db, -3.0) << "azimuth " << az;
      EXPECT_LT(p.itd_us, -200.0) << "azimuth " << az;
    }
  }
  for (int order : {1, 5}) {
    const fs::path field = work / ("left_o" + std::to_string(order) + ".wav"),
                   plugged = work / ("lv2_left_o" + std::to_string(order) + ".wav");
    write_plane_wave(field, noise, std::min(order, 3), 90);  // order 5: the first three orders, the rest silent
    if (order == 5) {
      // Pad to 36 channels.
      SF_INFO in_info{};
      SNDFILE* in = sf_open(field.c_str(), SFM_READ, &in_info);
      ASSERT_NE(in, nullptr);
      std::vector<float> x(static_cast<std::size_t>(in_info.frames * in_info.channels));
      sf_readf_float(in, x.data(), in_info.frames);
      sf_close(in);
      std::vector<float> y(static_cast<std::size_t>(in_info.frames) * 36, 0.0f);
      for (sf_count_t i = 0; i < in_info.frames; ++i)
        for (int c = 0; c < in_info.channels; ++c)
          y[static_cast<std::size_t>(i) * 36 + static_cast<std::size_t>(c)] = x[static_cast<std::size_t>(i * in_info.channels + c)];
      SF_INFO out_info{};
      out_info.samplerate = kRate;
      out_info.channels = 36;
      out_info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
      SNDFILE* out = sf_open(field.c_str(), SFM_WRITE, &out_info);
      ASSERT_NE(out, nullptr);
      sf_writef_float(out, y.data(), in_info.frames);
      sf_close(out);
    }
    const std::string lv2 = "LV2_PATH='" EARSHOT_LV2_PATH "' lv2apply -i '" + field.string() + "' -o '" +
                            plugged.string() + "' urn:earshot:lv2:ambi-binaural-o" + std::to_string(order);
    ASSERT_EQ(run(lv2), 0) << lv2;
    EXPECT_GT(cues(read_stereo(plugged)).ild_db, 6.0) << "order " << order;
  }
}
