// cue_accuracy: are the interaural cues Earshot renders those of the HRTF?
//
//   cue_accuracy [--hrtf FILE.sofa] [--elevations 0,30,-30] [--segment 0.25]
//                [--csv cues.csv] [--keep DIR] [--quality direct,ambisonic:3]
//
// For each elevation, one scene is rendered through the same path as
// `earshot render` (Scene JSON + Pose track CSV -> WAV): white noise 1.4 m
// away (the MIT KEMAR measurement distance) while the listener's yaw steps
// through every whole degree, holding each for one segment. The noise is the
// same burst in every segment (a WAV the scene plays), so the change between
// two segments is the renderer's alone, not the noise's. The WAV is read back
// and, per segment (after the crossfade and delay glide settle), the ITD
// (cross-correlation peak, sub-sample; broadband and below 1.5 kHz) and the
// broadband ILD are measured. At the azimuths the SOFA file measured, the
// same noise is convolved directly with the measured HRIR pair and measured
// by the same estimators.
//
// Reported per elevation: the largest difference from the SOFA cues at the
// measured azimuths; the largest change between neighbouring 1-degree steps;
// and the steepest the measured data itself changes between two neighbouring
// measurements (per degree): no interpolation can step less than that
// somewhere in that gap. --csv writes every segment for tools/plot_cues.py.
//
// --quality renders each elevation once per renderer tier (Scene JSON's
// "quality": direct, ambisonic:N) and prints one table with a row per tier
// and elevation, the ITD below 1.5 kHz against the SOFA data's below 1.5 kHz
// beside it (an Ambisonic decoder keeps the HRTF's phase only below its
// transition; the ITD is heard there). The pass line is the direct tier's.
#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "binaural_cues.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/host/scene_render.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "earshot/scenes/scene.hpp"
#include "earshot/scenes/signal_source.hpp"

namespace fs = std::filesystem;
using namespace earshot;

namespace {

constexpr double kRate = 48000.0;
constexpr double kDistance = 1.4;
constexpr double kDeg = std::numbers::pi / 180.0;

struct Args {
  std::string hrtf = hrtf::HrtfSet::kDefaultPath;
  std::vector<double> elevations{0, 30, -30};
  double segment = 0.25;
  std::string csv, keep;
  std::vector<std::string> qualities;  // empty: the direct tier alone, the table as before
};

std::vector<float> read_wav(const fs::path& p, std::vector<float>& right) {
  SF_INFO info{};
  SNDFILE* f = sf_open(p.c_str(), SFM_READ, &info);
  if (!f || info.channels != 2) throw std::runtime_error("cannot read " + p.string());
  std::vector<float> inter(static_cast<std::size_t>(info.frames) * 2);
  sf_readf_float(f, inter.data(), info.frames);
  sf_close(f);
  std::vector<float> left(static_cast<std::size_t>(info.frames));
  right.resize(left.size());
  for (std::size_t i = 0; i < left.size(); ++i) left[i] = inter[2 * i], right[i] = inter[2 * i + 1];
  return left;
}

struct Segment {
  double elevation, azimuth, itd_us, low_itd_us, ild_db;
  std::optional<double> sofa_itd_us, sofa_ild_db, sofa_low_itd_us;
};

constexpr double kLowBandHz = 1500.0;

std::optional<std::size_t> measured_at(const hrtf::HrtfSet& set, double az_deg, double el_deg) {
  for (std::size_t m = 0; m < set.measurement_count(); ++m) {
    const auto d = set.direction(m);
    double da = std::remainder(d.azimuth / kDeg - az_deg, 360.0);
    if (std::abs(da) < 0.01 && std::abs(d.elevation / kDeg - el_deg) < 0.01) return m;
  }
  return std::nullopt;
}

/// y[n] = sum_k h[k] x[n - k - latency] for n in [from, to).
std::vector<float> convolve(std::span<const float> x, std::span<const float> h, std::size_t from, std::size_t to,
                            std::size_t latency) {
  std::vector<float> y(to - from, 0.0f);
  for (std::size_t n = from; n < to; ++n) {
    double acc = 0.0;
    for (std::size_t k = 0; k < h.size() && k + latency <= n; ++k) acc += double(h[k]) * x[n - k - latency];
    y[n - from] = static_cast<float>(acc);
  }
  return y;
}

std::vector<Segment> measure_elevation(const Args& a, const hrtf::HrtfSet& set, double el, const fs::path& dir,
                                       const std::string& quality) {
  // The source sits ahead at elevation `el`; yawing the listener by -az puts
  // it at azimuth az and leaves its elevation alone.
  const fs::path track = dir / "track.csv", scene_file = dir / "scene.json", noise_file = dir / "noise.wav";
  const auto seg = static_cast<std::size_t>(std::lround(a.segment * kRate));
  std::vector<float> input(361 * seg);
  {
    scenes::Signal noise;
    noise.seed = 7;
    scenes::SignalSource gen(noise, kRate);
    gen.generate(std::span(input).first(seg));
    for (float& x : std::span(input).first(seg)) x *= 0.25f;
    for (std::size_t k = 1; k < 361; ++k) std::copy_n(input.begin(), seg, input.begin() + static_cast<long>(k * seg));
    SF_INFO info{};
    info.samplerate = static_cast<int>(kRate);
    info.channels = 1;
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    SNDFILE* f = sf_open(noise_file.c_str(), SFM_WRITE, &info);
    if (!f) throw std::runtime_error("cannot write " + noise_file.string());
    sf_writef_float(f, input.data(), static_cast<sf_count_t>(input.size()));
    sf_close(f);
  }
  const fs::path wav = dir / ("cues_el" + std::to_string(static_cast<int>(el)) + "_" + quality + ".wav");
  {
    std::ofstream t(track);
    t << "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
    t.precision(10);
    for (int az = -180; az <= 180; ++az) {
      const double t0 = (az + 180) * a.segment, t1 = t0 + a.segment - 1e-6;
      const Quat q = quat_from_ypr(-az * kDeg, 0, 0);
      for (double tt : {t0, t1}) t << tt << ",0,0,0," << q[0] << ',' << q[1] << ',' << q[2] << ',' << q[3] << '\n';
    }
  }
  {
    std::ofstream s(scene_file);
    s.precision(12);
    s << "{\"duration_s\": " << 361 * a.segment << ", \"sample_rate\": " << kRate << ", \"room\": \"none\",\n"
      << " \"sources\": [{\"name\": \"noise\", \"signal\": {\"type\": \"file\", \"path\": \"noise.wav\"},\n"
      << "   \"position\": [0, " << kDistance * std::sin(el * kDeg) << ", " << -kDistance * std::cos(el * kDeg)
      << "], \"gain_db\": 0, \"distance_model\": \"none\"}]}\n";
  }
  host::RenderOptions o;
  o.out = wav;
  o.hrtf = a.hrtf;
  o.pose_track = track;
  o.quality = quality;
  host::render_scene(scenes::load_scene(scene_file), o);
  std::vector<float> right;
  const std::vector<float> left = read_wav(wav, right);

  // Skip the start of each segment: one block of crossfade, the HRIR's
  // length and the delay glide must pass before the new direction is steady.
  // The ambisonic tiers' decoders are 1024 taps long at 48 kHz.
  const std::size_t skip = 128 + (quality == "direct" ? set.filter_length() : std::max<std::size_t>(set.filter_length(), 1024)) +
                           2 * 128 + 64;
  const std::size_t lag = static_cast<std::size_t>(kDistance / 343.3 * kRate) + 64;  // propagation
  std::vector<Segment> out;
  for (int az = -180; az <= 180; ++az) {
    const std::size_t from = static_cast<std::size_t>(az + 180) * seg + skip + lag;
    const std::size_t to = static_cast<std::size_t>(az + 181) * seg;
    if (to > left.size() || from >= to) break;
    const std::span<const float> l(left.data() + from, to - from), r(right.data() + from, to - from);
    Segment s{el, double(az), analysis::itd_s(l, r, kRate) * 1e6, analysis::itd_s(l, r, kRate, 1.2e-3, kLowBandHz) * 1e6,
              analysis::ild_db(l, r), {}, {}, {}};
    if (auto m = measured_at(set, az, el)) {
      const auto hl = set.measured_hrir(*m, hrtf::Ear::left), hr = set.measured_hrir(*m, hrtf::Ear::right);
      const std::size_t latency = lag - 64;  // about the renderer's; only the window's noise must match
      const auto yl = convolve(input, hl, from, to, latency), yr = convolve(input, hr, from, to, latency);
      s.sofa_itd_us = analysis::itd_s(yl, yr, kRate) * 1e6;
      s.sofa_ild_db = analysis::ild_db(yl, yr);
      s.sofa_low_itd_us = analysis::itd_s(yl, yr, kRate, 1.2e-3, kLowBandHz) * 1e6;
    }
    out.push_back(s);
  }
  if (a.keep.empty()) fs::remove(wav);
  return out;
}

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) v.push_back(std::stod(item));
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--hrtf") a.hrtf = v;
    else if (k == "--elevations") a.elevations = parse_list(v);
    else if (k == "--segment") a.segment = std::stod(v);
    else if (k == "--csv") a.csv = v;
    else if (k == "--keep") a.keep = v;
    else if (k == "--quality") {
      std::stringstream in(v);
      for (std::string q; std::getline(in, q, ',');) {
        if (!scenes::quality_order(q)) {
          std::fprintf(stderr, "cue_accuracy: unknown quality '%s' (direct, ambisonic:1 to ambisonic:7)\n", q.c_str());
          return 2;
        }
        a.qualities.push_back(q);
      }
    }
    else {
      std::fprintf(stderr, "cue_accuracy: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  const fs::path dir = a.keep.empty() ? fs::temp_directory_path() / "earshot_cue_accuracy" : fs::path(a.keep);
  fs::create_directories(dir);
  const auto set = hrtf::HrtfSet::load(a.hrtf, kRate);

  std::ofstream csv;
  if (!a.csv.empty()) {
    csv.open(a.csv);
    if (!a.qualities.empty()) csv << "quality,";
    csv << "elevation_deg,azimuth_deg,itd_us,itd_below_1500hz_us,ild_db,sofa_itd_us,sofa_ild_db\n";
  }
  const bool tiers = !a.qualities.empty();
  const std::vector<std::string> qualities = tiers ? a.qualities : std::vector<std::string>{"direct"};
  if (tiers)
    std::printf("| tier | elevation | measured azimuths | max ITD error (us) | max ITD error < 1.5 kHz (us) | "
                "mean ITD error < 1.5 kHz (us) | max ILD error (dB) | mean ILD error (dB) | max 1-deg ITD step < 1.5 kHz (us) | "
                "max 1-deg ILD step (dB) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  else
    std::printf("| elevation | measured azimuths | max ITD error (us) | max ILD error (dB) | "
                "max 1-deg ITD step (us) | max 1-deg ITD step < 1.5 kHz (us) | max 1-deg ILD step (dB) | "
                "steepest measured ITD change (us/deg) | steepest measured ILD change (dB/deg) | "
                "max step beyond the measured slope (us, dB) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  bool ok = true;
  for (const std::string& quality : qualities)
  for (double el : a.elevations) {
    const auto segs = measure_elevation(a, set, el, dir, quality);
    double e_itd = 0, e_ild = 0, s_itd = 0, s_low = 0, s_ild = 0, d_itd = 0, d_ild = 0, x_itd = 0, x_ild = 0;
    int measured = 0;
    // The measured data's change per degree across the gap holding each step.
    std::vector<std::size_t> marks;
    for (std::size_t i = 0; i < segs.size(); ++i)
      if (segs[i].sofa_itd_us) marks.push_back(i);
    for (std::size_t k = 0; k + 1 < marks.size(); ++k) {
      const auto& p = segs[marks[k]];
      const auto& q = segs[marks[k + 1]];
      const double width = q.azimuth - p.azimuth;
      const double slope_itd = std::abs(*q.sofa_itd_us - *p.sofa_itd_us) / width;
      const double slope_ild = std::abs(*q.sofa_ild_db - *p.sofa_ild_db) / width;
      d_itd = std::max(d_itd, slope_itd);
      d_ild = std::max(d_ild, slope_ild);
      for (std::size_t i = marks[k] + 1; i <= marks[k + 1]; ++i) {
        x_itd = std::max(x_itd, std::abs(segs[i].itd_us - segs[i - 1].itd_us) - std::max(10.0, slope_itd));
        x_ild = std::max(x_ild, std::abs(segs[i].ild_db - segs[i - 1].ild_db) - std::max(0.5, slope_ild));
      }
    }
    double e_low = 0, m_low = 0, m_ild = 0;
    for (std::size_t i = 0; i < segs.size(); ++i) {
      const auto& s = segs[i];
      if (s.sofa_itd_us) {
        ++measured;
        e_itd = std::max(e_itd, std::abs(s.itd_us - *s.sofa_itd_us));
        e_ild = std::max(e_ild, std::abs(s.ild_db - *s.sofa_ild_db));
        e_low = std::max(e_low, std::abs(s.low_itd_us - *s.sofa_low_itd_us));
        m_low += std::abs(s.low_itd_us - *s.sofa_low_itd_us);
        m_ild += std::abs(s.ild_db - *s.sofa_ild_db);
      }
      if (i > 0) {
        s_itd = std::max(s_itd, std::abs(s.itd_us - segs[i - 1].itd_us));
        s_low = std::max(s_low, std::abs(s.low_itd_us - segs[i - 1].low_itd_us));
        s_ild = std::max(s_ild, std::abs(s.ild_db - segs[i - 1].ild_db));
      }
      if (csv.is_open()) {
        if (tiers) csv << quality << ',';
        csv << s.elevation << ',' << s.azimuth << ',' << s.itd_us << ',' << s.low_itd_us << ',' << s.ild_db << ',';
        if (s.sofa_itd_us) csv << *s.sofa_itd_us << ',' << *s.sofa_ild_db;
        else csv << ',';
        csv << '\n';
      }
    }
    if (tiers) {
      std::printf("| %s | %+.0f deg | %d | %.1f | %.1f | %.1f | %.2f | %.2f | %.1f | %.2f |\n", quality.c_str(), el,
                  measured, e_itd, e_low, measured ? m_low / measured : 0.0, e_ild, measured ? m_ild / measured : 0.0,
                  s_low, s_ild);
    } else {
      std::printf("| %+.0f deg | %d | %.2f | %.3f | %.2f | %.2f | %.3f | %.1f | %.3f | %.2f, %.3f |\n", el, measured,
                  e_itd, e_ild, s_itd, s_low, s_ild, d_itd, d_ild, std::max(0.0, x_itd), std::max(0.0, x_ild));
    }
    if (quality == "direct") ok = ok && e_itd <= 10.0 && e_ild <= 0.5 && x_itd <= 0.0 && x_ild <= 0.0;
  }
  std::printf("\n%sat measured directions within 10 us and 0.5 dB, and no 1-degree step beyond max(10 us, 0.5 dB; "
              "the measured data's own slope there): %s\n", tiers ? "direct tier: " : "", ok ? "met" : "NOT met");
  return ok ? 0 : 1;
}
