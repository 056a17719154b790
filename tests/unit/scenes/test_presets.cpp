// The shipped preset scenes: each parses, renders deterministically, and
// does what its description claims, measured on the rendered output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "binaural_cues.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/errors.hpp"
#include "earshot/scenes/presets.hpp"
#include "earshot/scenes/scene.hpp"
#include "earshot/host/scene_render.hpp"
#include "scene_test_util.hpp"

using namespace earshot::scenes;
using namespace earshot::host;  // render_scene
namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kPresets = {"manual", "circles", "traffic", "zoo", "teleconference"};

fs::path out_dir() {
  // Per process: two test runs at once (two build trees) must not overwrite
  // each other's renders between the write and the byte comparison.
  const fs::path d = fs::temp_directory_path() / ("earshot_preset_tests_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

Scene preset(const std::string& name) { return load_scene(resolve_scene_argument(name)); }

/// The scene with only the named source left in it (the room stays).
Scene alone(Scene s, const std::string& source) {
  std::erase_if(s.sources, [&](const SceneSource& x) { return x.name != source; });
  EXPECT_EQ(s.sources.size(), 1u) << source;
  return s;
}

test::Stereo render(const Scene& s, const std::string& name, double seconds) {
  RenderOptions o;
  o.out = out_dir() / (name + ".wav");
  o.duration_s = seconds;
  render_scene(s, o);
  return test::read_wav(o.out);
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::span<const float> window(const std::vector<float>& x, double rate, double t0, double t1) {
  const auto a = static_cast<std::size_t>(t0 * rate), b = static_cast<std::size_t>(t1 * rate);
  return std::span<const float>(x).subspan(a, b - a);
}

}  // namespace

TEST(Presets, EachParsesAndRendersByteIdentically) {
  for (const auto& name : kPresets) {
    SCOPED_TRACE(name);
    const Scene s = preset(name);
    EXPECT_FALSE(s.description.empty());
    EXPECT_NE(s.room, "none");
    EXPECT_GE(s.sources.size(), 2u);
    for (const auto& src : s.sources) EXPECT_GT(src.reverb_send_db, -120.0) << src.name;
    RenderOptions o;
    o.duration_s = 3.0;
    o.out = out_dir() / (name + "_a.wav");
    const auto st = render_scene(s, o);
    EXPECT_GT(st.peak, 0.01);
    EXPECT_LE(st.peak, 0.98);
    o.out = out_dir() / (name + "_b.wav");
    render_scene(s, o);
    EXPECT_EQ(bytes(out_dir() / (name + "_a.wav")), bytes(out_dir() / (name + "_b.wav")));
  }
}

TEST(Presets, NamesResolveAndUnknownNamesListThem) {
  for (const auto& name : kPresets) EXPECT_EQ(resolve_scene_argument(name).filename(), name + ".json");
  EXPECT_EQ(resolve_scene_argument("dir/mine.json"), fs::path("dir/mine.json"));  // paths stay paths
  try {
    (void)resolve_scene_argument("opera");
    ADD_FAILURE() << "no error";
  } catch (const earshot::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "opera: no such scene file or preset (presets: circles, manual, teleconference, traffic, zoo)");
  }
}

TEST(Presets, CirclesSirenIldChangesSignWithItsCircle) {
  // The siren circles in the horizontal plane (3 m, 8 s a turn, starting on
  // the right): its ILD must follow the side it is on, changing sign twice a
  // turn, at the moments the path crosses the median plane (t = 2 s ahead, 6 s behind).
  const Scene s = alone(preset("circles"), "siren");
  const auto w = render(s, "circles_siren", 8.0);
  const double rate = w.rate, win = 0.25;
  int agree = 0, counted = 0;
  std::vector<double> t_mid, ild;
  for (double t = 0.1; t + win <= 8.0; t += win) {
    const double d = earshot::analysis::ild_db(window(w.l, rate, t, t + win), window(w.r, rate, t, t + win));
    const double x = source_position(s.sources[0], t + win / 2)[0];
    t_mid.push_back(t + win / 2);
    ild.push_back(d);
    if (std::abs(x) < 1.0) continue;  // near the median plane the sign is not the point
    ++counted;
    agree += (x < 0) == (d > 0);  // left of the head (x < 0): left ear louder
  }
  EXPECT_GE(agree, counted - 1) << agree << " of " << counted;
  std::vector<double> crossings;
  for (std::size_t i = 1; i < ild.size(); ++i)
    if ((ild[i - 1] > 0) != (ild[i] > 0))
      crossings.push_back(t_mid[i - 1] + (t_mid[i] - t_mid[i - 1]) * ild[i - 1] / (ild[i - 1] - ild[i]));
  ASSERT_EQ(crossings.size(), 2u);
  EXPECT_NEAR(crossings[0], 2.0, 0.4);
  EXPECT_NEAR(crossings[1], 6.0, 0.4);
  const auto [lo, hi] = std::minmax_element(ild.begin(), ild.end());
  std::printf("circles siren: ILD %.1f to %.1f dB, sign agrees with the side in %d of %d windows, "
              "crossings at %.2f s and %.2f s\n", *lo, *hi, agree, counted, crossings[0], crossings[1]);
  EXPECT_GT(*hi, 6.0);
  EXPECT_LT(*lo, -6.0);
}

TEST(Presets, TeleconferenceTalkersSitAtTheirOwnAzimuths) {
  // Each talker alone: the ITD (below 1.5 kHz) must be ordered as the seats
  // go from left to right, each clearly apart from its neighbour; and each
  // voice's pitch its own, at least 10 % from every other.
  const Scene s = preset("teleconference");
  ASSERT_GE(s.sources.size(), 4u);
  std::vector<double> itd, pitch;
  const earshot::HeadPose listener;
  double last_az = 1e9;
  for (const auto& src : s.sources) {
    const double az = earshot::audio::head_relative(src.position, listener).azimuth;
    EXPECT_LT(az, last_az) << src.name << ": the preset lists talkers from left to right";
    last_az = az;
    const auto w = render(alone(s, src.name), "tc_" + src.name, 4.0);
    itd.push_back(earshot::analysis::itd_s(w.l, w.r, w.rate, 1.2e-3, 1500.0));
    // And a voice of their own: the pitch heard is the talker's pitch_hz.
    std::vector<float> mono(w.l.size());
    for (std::size_t i = 0; i < mono.size(); ++i) mono[i] = w.l[i] + w.r[i];
    pitch.push_back(test::median_pitch_hz(mono, w.rate));
    EXPECT_NEAR(pitch.back(), src.signal.talk.pitch_hz, 0.15 * src.signal.talk.pitch_hz) << src.name;
    std::printf("teleconference %s: azimuth %.0f deg, ITD %.0f us, pitch %.0f Hz (pitch_hz %.0f)\n",
                src.name.c_str(), az * 180 / std::numbers::pi, itd.back() * 1e6, pitch.back(),
                src.signal.talk.pitch_hz);
  }
  for (std::size_t i = 0; i < pitch.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_GT(std::abs(std::log(pitch[i] / pitch[j])), std::log(1.1)) << s.sources[i].name << " " << s.sources[j].name;
  for (std::size_t i = 1; i < itd.size(); ++i) EXPECT_LT(itd[i], itd[i - 1] - 100e-6) << s.sources[i].name;
  EXPECT_GT(itd.front(), 400e-6);   // far left
  EXPECT_LT(itd.back(), -400e-6);   // far right
}

TEST(Presets, TrafficCarPitchFallsAsItPasses) {
  // The car passes the listener at t = 4 s (7 m ahead, 15 m/s). Its engine's
  // firing frequency (80 Hz) is heard higher while it comes and lower after
  // it has passed: f c / (c + v_r), v_r the rate at which its distance grows.
  const Scene s = alone(preset("traffic"), "car");
  const auto w = render(s, "traffic_car", 8.0);
  std::vector<float> mono(w.l.size());
  for (std::size_t i = 0; i < mono.size(); ++i) mono[i] = w.l[i] + w.r[i];
  auto expected = [&](double t) {
    const auto a = source_position(s.sources[0], t - 0.01), b = source_position(s.sources[0], t + 0.01);
    const double vr = (std::hypot(b[0], b[1], b[2]) - std::hypot(a[0], a[1], a[2])) / 0.02;
    return 80.0 * s.speed_of_sound / (s.speed_of_sound + vr);
  };
  const double before = test::peak_hz(window(mono, w.rate, 1.5, 3.0), w.rate, 60, 100);
  const double after = test::peak_hz(window(mono, w.rate, 5.0, 6.5), w.rate, 60, 100);
  std::printf("traffic car: %.2f Hz approaching (expected %.2f), %.2f Hz receding (expected %.2f)\n", before,
              expected(2.25), after, expected(5.75));
  EXPECT_NEAR(before, expected(2.25), 0.01 * expected(2.25));
  EXPECT_NEAR(after, expected(5.75), 0.01 * expected(5.75));
  EXPECT_GT(before / after, 1.06);
}

TEST(Presets, ZooHasSomethingAboveAndSomethingMoving) {
  const Scene s = preset("zoo");
  const earshot::HeadPose listener;
  // Above: some source stays more than 30 degrees up all the time.
  bool above = false, moves = false;
  for (const auto& src : s.sources) {
    double min_el = 90, travel = 0;
    for (double t = 0; t < s.duration_s; t += 0.5) {
      min_el = std::min(min_el, earshot::audio::head_relative(source_position(src, t), listener).elevation * 180 /
                                    std::numbers::pi);
      const auto a = source_position(src, t), b = source_position(src, t + 0.5);
      travel += std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    }
    above = above || min_el > 30;
    moves = moves || travel > 10;
  }
  EXPECT_TRUE(above);
  EXPECT_TRUE(moves);
  // And in the output: the parrot, circling overhead, is heard on the left
  // and on the right in turn (ILD of its calls follows its side).
  const Scene parrot = alone(s, "parrot");
  const auto w = render(parrot, "zoo_parrot", 12.0);
  const double win = 0.1, loud = 0.1 * test::rms(w.l);
  int agree = 0, counted = 0;
  double lo = 0, hi = 0;
  for (double t = 0; t + win <= 12.0; t += win) {
    const auto l = window(w.l, w.rate, t, t + win), r = window(w.r, w.rate, t, t + win);
    if (test::rms(l) + test::rms(r) < loud) continue;  // between calls
    const double x = source_position(parrot.sources[0], t + win / 2)[0];
    if (std::abs(x) < 1.5) continue;
    const double d = earshot::analysis::ild_db(l, r);
    lo = std::min(lo, d), hi = std::max(hi, d);
    ++counted;
    agree += (x < 0) == (d > 0);
  }
  std::printf("zoo parrot: %d of %d loud windows heard on its side, ILD %.1f to %.1f dB\n", agree, counted, lo, hi);
  EXPECT_GE(counted, 10);
  EXPECT_GE(agree, counted * 8 / 10);
  EXPECT_GT(hi, 3.0);
  EXPECT_LT(lo, -3.0);
}
