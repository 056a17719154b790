// sofa_equivalence: what the renderer plays at a measured direction, against
// the file's own HRIR pair, for every kind of SOFA file that
// tests/fixtures/make_sofa.py writes (rates, lengths, late onsets, ITD in
// Data.Delay, Cartesian positions, several distances, swapped receivers,
// sparse and dense grids), at render rates 44.1, 48 and 96 kHz.
//
// Unlike sofa_variety_tests (which rebuilds each response from the loaded
// set's filter and delay), this drives the whole Renderer: a source at each
// measured direction, beyond the set's farthest shell (distance model none,
// no propagation delay, so the gain is 1 and the near field stays out), a
// unit impulse in, both ears' output recorded. The rendered pair, delayed by
// the common delay the loader removes, must equal the file's pair at the
// render rate (make_sofa.py writes that too, from the same analytic model)
// up to one level for the whole set.
//
// Per kind and render rate it prints: the worst impulse-level error energy
// (dB below the response), the worst ILD and ITD errors at measured
// directions (ILD and ITD by tests/analysis/binaural_cues.hpp), the load time
// (HrtfSet::load, wall) and the heap the loaded set plus one renderer hold.
//
//   sofa_equivalence [--kinds a,b,...] [--rates 44100,48000,96000] [--dir DIR]
//                    [--dump-worst DIR]
#include <malloc.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mysofa.h>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "binaural_cues.hpp"
#include "earshot/audio/fractional_delay.hpp"
#include "earshot/audio/real_fft.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace fs = std::filesystem;
using earshot::analysis::ild_db;
using earshot::analysis::itd_s;
using earshot::audio::Renderer;

namespace {

struct Kind {
  const char* name;
  const char* args;      ///< make_sofa.py arguments
  std::size_t stride;    ///< render every stride-th measurement
};

// The kinds of sofa_variety_tests (same make_sofa.py arguments).
const std::vector<Kind> kKinds = {
    {"48k_256", "--rate 48000 --length 256", 1},
    {"44k1_256", "--rate 44100 --length 256", 1},
    {"96k_1024", "--rate 96000 --length 1024", 1},
    {"delay_in_data_44k1", "--rate 44100 --length 256 --delay-in-data", 1},
    {"cartesian", "--rate 48000 --length 256 --cartesian", 1},
    {"8192_late_onset", "--rate 48000 --length 8192 --onset-ms 40 --late --grid fibonacci:40", 1},
    {"three_distances", "--rate 48000 --length 256 --grid fibonacci:100 --distances 0.5,1,2", 1},
    {"right_ear_first", "--rate 44100 --length 256 --grid fibonacci:100 --swap-receivers --delay-in-data", 1},
    {"32_taps", "--rate 48000 --length 32 --short --delay-in-data --grid fibonacci:100", 1},
    {"sparse_50", "--rate 48000 --length 256 --grid fibonacci:50", 1},
    {"dense_10k", "--rate 48000 --length 96 --short --grid fibonacci:10000 --compress", 97},
};

struct SofaDeleter {
  void operator()(MYSOFA_HRTF* h) const { mysofa_free(h); }
};

/// `x` delayed by `d` samples (any real d; negative: earlier, dropping the
/// leading silence of the delay line), `n` samples out: a phase ramp on the
/// spectrum of a zero-padded FFT long enough that nothing wraps. Exact for
/// the band-limited responses compared here.
class Delayer {
 public:
  explicit Delayer(std::size_t nfft) : fft_(nfft), time_(nfft), spec_(fft_.bins()) {}

  std::vector<float> operator()(const std::vector<float>& x, double d, std::size_t n) {
    std::fill(time_.begin(), time_.end(), 0.0f);
    std::copy_n(x.begin(), std::min(x.size(), time_.size()), time_.begin());
    fft_.forward(time_, spec_);
    for (std::size_t k = 0; k < spec_.size(); ++k)
      spec_[k] *= std::polar(1.0f, float(-2.0 * std::numbers::pi * double(k) / double(fft_.size()) * d));
    spec_.back() = spec_.back().real();  // the Nyquist bin of a real signal stays real
    fft_.inverse(spec_, time_);
    return {time_.begin(), time_.begin() + std::ptrdiff_t(std::min(n, time_.size()))};
  }

 private:
  earshot::audio::RealFft fft_;
  std::vector<float> time_;
  std::vector<std::complex<float>> spec_;
};

// Small enough that no response reaches the renderer's output limiter
// (its ceiling is below full scale; a unit impulse at a lateral direction
// of some sets peaks above it, and the limiter's gain is the same for both
// ears and would show as a level error at that direction).
constexpr float kImpulse = 1.0f / 32.0f;

std::size_t pow2_at_least(std::size_t n) {
  std::size_t p = 1;
  while (p < n) p <<= 1;
  return p;
}

std::size_t heap_in_use() { return mallinfo2().uordblks + mallinfo2().hblkhd; }

struct Row {
  std::size_t worst_m = 0, worst_ear = 0;
  double worst_db = -300.0, worst_ild_db = 0.0, worst_itd_us = 0.0, load_ms = 0.0;
  double heap_mb = 0.0;
  std::size_t measurements = 0, rendered = 0, taps_at_rate = 0;
};

Row measure(const Kind& kind, double rate, const fs::path& dir, const std::string& make_sofa, const std::string& dump) {
  const fs::path file = dir / (std::string(kind.name) + ".sofa");
  const fs::path expected = dir / (std::string(kind.name) + "_expected_" + std::to_string(int(rate)) + ".sofa");
  const std::string cmd = "/usr/bin/python3 " + make_sofa + " --out " + file.string() + " " + kind.args + " --expected " +
                          expected.string() + " --expected-rate " + std::to_string(rate) +
                          (std::string(kind.name) == "32_taps" ? " --expected-length 128" : "");
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("failed: " + cmd);

  Row row;
  const std::size_t heap0 = heap_in_use();
  const auto t0 = std::chrono::steady_clock::now();
  auto set = std::make_shared<const earshot::hrtf::HrtfSet>(earshot::hrtf::HrtfSet::load(file, rate));
  row.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  earshot::audio::RendererConfig cfg;
  cfg.sample_rate = rate;
  cfg.block = 128;
  cfg.max_sources = 1;
  cfg.doppler_factor = 0.0;  // no propagation delay: the pair starts where the file's does
  Renderer renderer(set, cfg);
  row.heap_mb = double(heap_in_use() - heap0) / 1e6;

  int err = 0;
  const std::unique_ptr<MYSOFA_HRTF, SofaDeleter> want(mysofa_load(expected.c_str(), &err));
  if (!want || err != MYSOFA_OK) throw std::runtime_error("cannot read " + expected.string());
  const std::size_t M = want->M, N = want->N;
  row.measurements = M;
  row.taps_at_rate = N;

  // Long enough for the removed common delay, each ear's own delay and the filter.
  // The renderer plays each ear through a fractional delay line of at least
  // FractionalDelay::kMinDelay samples; the file's pair starts the removed
  // common delay later than the set's filters.
  const double removed = set->removed_delay_s() * rate;
  const double shift = removed - earshot::audio::FractionalDelay::kMinDelay;
  const std::size_t record = N + set->filter_length() + std::size_t(std::ceil(removed)) + 4 * cfg.block;
  const std::size_t blocks = (record + cfg.block - 1) / cfg.block;
  Delayer delay(pow2_at_least(2 * (blocks * cfg.block + N)));

  earshot::audio::SourceState s;
  s.distance.model = earshot::audio::DistanceModel::none;
  const int src = renderer.add_source(s);
  std::vector<float> l(cfg.block), r(cfg.block), out_l, out_r;
  const double far = 50.0;  // beyond every fixture's shells: no near-field path
  std::vector<std::vector<float>> got_l(M), got_r(M);
  double cross = 0.0, own = 0.0;
  for (std::size_t m = 0; m < M; m += kind.stride) {
    const auto at = set->direction(m);
    s.position = {-far * std::sin(at.azimuth) * std::cos(at.elevation), far * std::sin(at.elevation),
                  -far * std::cos(at.azimuth) * std::cos(at.elevation)};
    renderer.set_source(src, s);
    // Silence until the move's crossfade and the previous impulse are gone.
    for (std::size_t b = 0; b < blocks; ++b) {
      std::fill(renderer.source_input(src).begin(), renderer.source_input(src).end(), 0.0f);
      renderer.render(l, r);
    }
    out_l.clear();
    out_r.clear();
    for (std::size_t b = 0; b < blocks; ++b) {
      auto in = renderer.source_input(src);
      std::fill(in.begin(), in.end(), 0.0f);
      if (b == 0) in[0] = kImpulse;
      renderer.render(l, r);
      out_l.insert(out_l.end(), l.begin(), l.end());
      out_r.insert(out_r.end(), r.begin(), r.end());
    }
    got_l[m] = delay(out_l, shift, N);
    got_r[m] = delay(out_r, shift, N);
    const float* e = want->DataIR.values + 2 * m * N;
    for (std::size_t i = 0; i < N; ++i) {
      cross += double(got_l[m][i]) * e[i] + double(got_r[m][i]) * e[N + i];
      own += double(got_l[m][i]) * got_l[m][i] + double(got_r[m][i]) * got_r[m][i];
    }
    ++row.rendered;
  }
  const double level = cross / own;  // the one level the loader applies to the whole set (and kImpulse)
  for (std::size_t m = 0; m < M; m += kind.stride) {
    const float* e = want->DataIR.values + 2 * m * N;
    for (std::size_t ear = 0; ear < 2; ++ear) {
      const auto& g = ear == 0 ? got_l[m] : got_r[m];
      double diff = 0.0, ref = 0.0;
      for (std::size_t i = 0; i < N; ++i) {
        const double x = e[ear * N + i];
        diff += (level * g[i] - x) * (level * g[i] - x);
        ref += x * x;
      }
      if (const double db = 10.0 * std::log10(diff / ref); db > row.worst_db) row.worst_db = db, row.worst_m = m, row.worst_ear = ear;
    }
    // The cues by the project's analysis (tests/analysis): the same estimators for both pairs.
    const std::span<const float> fl(e, N), fr(e + N, N);
    row.worst_ild_db = std::max(row.worst_ild_db, std::abs(ild_db(got_l[m], got_r[m]) - ild_db(fl, fr)));
    row.worst_itd_us = std::max(row.worst_itd_us, std::abs(itd_s(got_l[m], got_r[m], rate) - itd_s(fl, fr, rate)) * 1e6);
  }
  if (!dump.empty()) {  // the worst response: rendered (level fitted) and the file's, sample by sample
    const fs::path out = fs::path(dump) / (std::string(kind.name) + "_" + std::to_string(int(rate)) + ".csv");
    FILE* f = std::fopen(out.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + out.string());
    std::fprintf(f, "# measurement %zu, ear %zu\nsample,rendered,file\n", row.worst_m, row.worst_ear);
    const auto& g = row.worst_ear == 0 ? got_l[row.worst_m] : got_r[row.worst_m];
    const float* e = want->DataIR.values + (2 * row.worst_m + row.worst_ear) * N;
    for (std::size_t i = 0; i < N; ++i) std::fprintf(f, "%zu,%.9g,%.9g\n", i, level * g[i], double(e[i]));
    std::fclose(f);
  }
  return row;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t a = 0;
  while (a <= s.size()) {
    const std::size_t b = std::min(s.find(',', a), s.size());
    if (b > a) out.push_back(s.substr(a, b - a));
    a = b + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The rendered impulse response at every measured direction against the SOFA file's own"};
  std::string kinds = "all", rates = "44100,48000,96000";
  std::string dir = (fs::temp_directory_path() / "earshot_sofa_equivalence").string();
  std::string make_sofa = EARSHOT_MAKE_SOFA;
  app.add_option("--kinds", kinds, "comma-separated kind names, or all");
  app.add_option("--rates", rates, "render rates, Hz");
  app.add_option("--dir", dir, "where the fixtures are written");
  std::string dump;
  app.add_option("--dump-worst", dump, "a directory: each kind and rate's worst response, rendered and the file's, as CSV");
  CLI11_PARSE(app, argc, argv);
  fs::create_directories(dir);

  std::printf("| kind | render rate | directions rendered | taps at the rate | worst error (dB) | worst ILD error (dB) | "
              "worst ITD error (us) | load (ms) | heap (MB) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  bool all_pass = true;
  for (const Kind& k : kKinds) {
    if (kinds != "all") {
      const auto want = split(kinds);
      if (std::find(want.begin(), want.end(), k.name) == want.end()) continue;
    }
    for (const std::string& rs : split(rates)) {
      const double rate = std::stod(rs);
      const Row row = measure(k, rate, dir, make_sofa, dump);
      std::printf("| %s | %.1f kHz | %zu of %zu | %zu | %.1f | %.3f | %.2f | %.0f | %.1f |\n", k.name, rate / 1000.0, row.rendered,
                  row.measurements, row.taps_at_rate, row.worst_db, row.worst_ild_db, row.worst_itd_us, row.load_ms, row.heap_mb);
      std::fflush(stdout);
      all_pass = all_pass && row.worst_db < -40.0 && row.worst_itd_us < 10.0 && row.worst_ild_db < 0.1;
    }
  }
  std::printf("\n%s: every kind at every rate %s -40 dB, 0.1 dB ILD and 10 us ITD\n", all_pass ? "PASS" : "FAIL",
              all_pass ? "within" : "NOT within");
  return all_pass ? 0 : 1;
}
