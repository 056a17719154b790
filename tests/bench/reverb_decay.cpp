// Decay of every room preset's reverb: Earshot's FDN and Schroeder reverbs
// and OpenAL Soft's EFX (EAX) reverb, measured the same way on their impulse
// responses, printed as one markdown table (docs/BENCHMARKS.md, "Rooms").
//
//   reverb_decay [--preset NAME]... [--wav-dir DIR] [--no-openal]
//
// Per preset and reverb: RT60 (T30, Schroeder backward integration) in the
// 500 Hz and 1 kHz octave bands against decay_time_s (target +-5%), the high
// band's decay ratio (third octave at hf_reference_hz over the mean of the two
// mid bands) against decay_hf_ratio (+-10%), and when the normalised echo
// density first reaches 1 after the first arrival (target <= 100 ms).
// gain_hf is set to 1 for all three: it only shapes the level of the high band,
// and a -60 dB high band would leave nothing above the filters' leakage.
// A high-band RT60 target under 0.1 s is too short to measure: marked "n/m".
#include <sndfile.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "earshot/audio/room_reverb.hpp"
#include "reverb_measure.hpp"
#include "reverb_openal.hpp"

using namespace earshot;

namespace {

constexpr double kFs = 48000.0;

struct Ir {
  std::vector<float> left, right;
};

Ir render_ours(const audio::RoomParams& p, audio::LateReverbType type, std::size_t frames) {
  constexpr std::size_t block = 128;
  audio::RoomReverb reverb(kFs, block, p, type);
  Ir ir{std::vector<float>(frames), std::vector<float>(frames)};
  std::vector<float> in(block, 0.0f), l(block), r(block);
  in[0] = 1.0f;
  for (std::size_t done = 0; done < frames; done += block) {
    reverb.process(in, l, r);
    in[0] = 0.0f;
    const std::size_t n = std::min(block, frames - done);
    std::copy_n(l.begin(), n, ir.left.begin() + static_cast<long>(done));
    std::copy_n(r.begin(), n, ir.right.begin() + static_cast<long>(done));
  }
  return ir;
}

void write_wav(const std::filesystem::path& path, const Ir& ir) {
  SF_INFO info{};
  info.samplerate = static_cast<int>(kFs);
  info.channels = 2;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  sf_command(f, SFC_SET_ADD_PEAK_CHUNK, nullptr, SF_FALSE);
  std::vector<float> inter(2 * ir.left.size());
  for (std::size_t i = 0; i < ir.left.size(); ++i) inter[2 * i] = ir.left[i], inter[2 * i + 1] = ir.right[i];
  sf_writef_float(f, inter.data(), static_cast<sf_count_t>(ir.left.size()));
  sf_close(f);
}

struct Result {
  std::optional<double> t500, t1k, ratio, ed_time;
  bool hf_measurable = true;
};

Result measure(const Ir& ir, const audio::RoomParams& p) {
  Result r;
  r.t500 = analysis::band_rt60(ir.left, ir.right, analysis::octave(500.0), kFs);
  r.t1k = analysis::band_rt60(ir.left, ir.right, analysis::octave(1000.0), kFs);
  r.hf_measurable = p.decay_time_s * p.decay_hf_ratio >= 0.1;
  const auto thf = analysis::band_rt60(ir.left, ir.right, analysis::third_octave(p.hf_reference_hz), kFs);
  if (r.t500 && r.t1k && thf) r.ratio = *thf / (0.5 * (*r.t500 + *r.t1k));
  r.ed_time = analysis::echo_density_time(ir.left, kFs);
  return r;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

struct Tally {
  int mid_ok = 0, mid_n = 0, hf_ok = 0, hf_n = 0, ed_ok = 0, ed_n = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"RT60, high-band decay ratio and echo density of every room preset's reverb"};
  std::vector<std::string> only;
  std::string wav_dir;
  bool no_openal = false;
  app.add_option("--preset", only, "measure only these presets (repeatable)");
  app.add_option("--wav-dir", wav_dir, "also write each impulse response as DIR/<reverb>_<preset>.wav");
  app.add_flag("--no-openal", no_openal, "skip OpenAL Soft");
  CLI11_PARSE(app, argc, argv);

  std::optional<bench::OpenAlReverb> openal;
  if (!no_openal) openal.emplace(static_cast<int>(kFs));
  if (!wav_dir.empty()) std::filesystem::create_directories(wav_dir);

  std::printf("| preset | reverb | RT60 target (s) | T30 500 Hz (s) | T30 1 kHz (s) | HF ratio target | HF ratio | echo density 1 at (ms) |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  std::map<std::string, Tally> tally;
  const char* names[] = {"fdn", "schroeder", "openal-soft"};
  for (const auto& preset : audio::room_presets()) {
    if (!only.empty() && std::find(only.begin(), only.end(), preset.name) == only.end()) continue;
    audio::RoomParams p = preset.params;
    p.gain_hf = 1.0;
    const double hf_t60 = p.decay_time_s * std::max(1.0, p.decay_hf_ratio);
    const auto frames = static_cast<std::size_t>(
        (p.reflections_delay_s + p.late_reverb_delay_s + 1.3 * hf_t60 + 0.4) * kFs);
    for (int k = 0; k < 3; ++k) {
      if (k == 2 && !openal) continue;
      Ir ir;
      if (k == 2) {
        auto s = openal->impulse_response(p, frames);
        ir = {std::move(s.left), std::move(s.right)};
      } else {
        ir = render_ours(p, k == 0 ? audio::LateReverbType::fdn : audio::LateReverbType::schroeder, frames);
      }
      if (!wav_dir.empty())
        write_wav(std::filesystem::path(wav_dir) / (std::string(names[k]) + "_" + std::string(preset.name) + ".wav"), ir);
      const Result r = measure(ir, p);
      auto& t = tally[names[k]];
      auto band = [&](const std::optional<double>& v) {
        if (!v) return std::string("—");
        const double err = (*v / p.decay_time_s - 1.0) * 100.0;
        return fmt("%.3f", *v) + fmt(" (%+.1f%%", err) + (std::abs(err) <= 5.0 ? " ✓)" : " ✗)");
      };
      const bool mid_ok = r.t500 && r.t1k && std::abs(*r.t500 / p.decay_time_s - 1) <= 0.05 &&
                          std::abs(*r.t1k / p.decay_time_s - 1) <= 0.05;
      ++t.mid_n;
      t.mid_ok += mid_ok;
      std::string ratio = "n/m";
      if (r.hf_measurable) {
        ++t.hf_n;
        if (r.ratio) {
          const double err = (*r.ratio / p.decay_hf_ratio - 1.0) * 100.0;
          const bool ok = std::abs(err) <= 10.0;
          t.hf_ok += ok;
          ratio = fmt("%.2f", *r.ratio) + fmt(" (%+.0f%%", err) + (ok ? " ✓)" : " ✗)");
        } else {
          ratio = "—";
        }
      }
      ++t.ed_n;
      std::string ed = "never";
      if (r.ed_time) {
        const bool ok = *r.ed_time <= 0.1;
        t.ed_ok += ok;
        ed = fmt("%.0f", *r.ed_time * 1e3) + (ok ? " ✓" : " ✗");
      }
      std::printf("| %s | %s | %.2f | %s | %s | %.2f | %s | %s |\n", std::string(preset.name).c_str(), names[k],
                  p.decay_time_s, band(r.t500).c_str(), band(r.t1k).c_str(), p.decay_hf_ratio, ratio.c_str(),
                  ed.c_str());
      std::fflush(stdout);
    }
  }
  std::printf("\n| reverb | RT60 within ±5%% (500 Hz and 1 kHz) | HF ratio within ±10%% | echo density 1 by 100 ms |\n");
  std::printf("|---|---|---|---|\n");
  for (const char* n : names) {
    if (!tally.count(n)) continue;
    const auto& t = tally[n];
    std::printf("| %s | %d / %d | %d / %d measurable | %d / %d |\n", n, t.mid_ok, t.mid_n, t.hf_ok, t.hf_n, t.ed_ok,
                t.ed_n);
  }
  return 0;
}
