// SOFA files of the kinds other databases publish, written by
// tests/fixtures/make_sofa.py from an analytic head model: other rates than
// the render rate (up and down), long responses with late energy after a
// long pre-onset gap, the ITD stored in Data.Delay instead of in the
// responses, Cartesian source positions. At every measured direction the
// loaded set's filter and delay must give back the model's response at the
// render rate (arrival included) with an error energy at least 40 dB below
// the response's.
#include <gtest/gtest.h>
#include <mysofa.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "earshot/hrtf/hrtf_set.hpp"
#include "earshot/windowed_sinc.hpp"

using earshot::hrtf::Ear;
using earshot::hrtf::HrtfSet;
namespace fs = std::filesystem;

namespace {

struct Case {
  const char* name;
  const char* args;
  double render_rate;
};

// Test names and failure messages show the kind, not the struct's bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

struct SofaDeleter {
  void operator()(MYSOFA_HRTF* h) const { mysofa_free(h); }
};

/// `f` delayed by `delay` samples (band-limited), `n` samples long.
std::vector<double> delayed(std::span<const float> f, double delay, std::size_t n) {
  static const earshot::KaiserSinc kernel(64.0, 10.0);
  std::vector<double> out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double at = static_cast<double>(i) - delay;  // position in f
    const auto lo = static_cast<long>(std::floor(at)) - 63, hi = static_cast<long>(std::floor(at)) + 64;
    double acc = 0.0;
    for (long k = std::max(0L, lo); k <= std::min(hi, static_cast<long>(f.size()) - 1); ++k)
      acc += f[static_cast<std::size_t>(k)] * kernel(at - static_cast<double>(k));
    out[i] = acc;
  }
  return out;
}

class SofaVariety : public ::testing::TestWithParam<Case> {};

TEST_P(SofaVariety, EveryMeasuredDirectionGivesBackItsResponse) {
  const Case& c = GetParam();
  const fs::path dir = fs::temp_directory_path() / ("earshot_sofa_variety_" + std::string(c.name));
  fs::create_directories(dir);
  const fs::path file = dir / "set.sofa", expected = dir / "expected.sofa";
  // Debian's interpreter, which has python3-netcdf4 (not whatever python3 is first on PATH).
  const std::string cmd = std::string("/usr/bin/python3 ") + EARSHOT_MAKE_SOFA + " --out " + file.string() + " " + c.args +
                          " --expected " + expected.string() + " --expected-rate " + std::to_string(c.render_rate);
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;

  const HrtfSet set = HrtfSet::load(file, c.render_rate);
  int err = 0;
  const std::unique_ptr<MYSOFA_HRTF, SofaDeleter> want(mysofa_load(expected.c_str(), &err));
  ASSERT_TRUE(want && err == MYSOFA_OK) << expected;
  const std::size_t M = want->M, N = want->N;
  ASSERT_EQ(set.measurement_count(), M);
  ASSERT_EQ(set.measured_hrir(0, Ear::left).size(), N) << "the response length at the render rate";
  ASSERT_GE(set.filter_length(), N);

  // Rebuild each response from the set's filter and delay (the common delay
  // the set removed added back), then fit the one level the set applies.
  std::vector<std::vector<double>> rebuilt(2 * M);
  double cross = 0.0, own = 0.0;
  for (std::size_t m = 0; m < M; ++m)
    for (std::size_t ear = 0; ear < 2; ++ear) {
      const double d = ear == 0 ? set.delays(m).left_s : set.delays(m).right_s;
      auto& r = rebuilt[2 * m + ear];
      r = delayed(set.filter(m, static_cast<Ear>(ear)), (d + set.removed_delay_s()) * c.render_rate, N);
      const float* e = want->DataIR.values + (2 * m + ear) * N;
      for (std::size_t i = 0; i < N; ++i) cross += r[i] * e[i], own += r[i] * r[i];
    }
  ASSERT_GT(own, 0.0);
  const double level = cross / own;
  double worst = -300.0;
  std::size_t worst_m = 0;
  for (std::size_t m = 0; m < M; ++m)
    for (std::size_t ear = 0; ear < 2; ++ear) {
      const auto& r = rebuilt[2 * m + ear];
      const float* e = want->DataIR.values + (2 * m + ear) * N;
      double diff = 0.0, ref = 0.0;
      for (std::size_t i = 0; i < N; ++i) diff += (level * r[i] - e[i]) * (level * r[i] - e[i]), ref += double(e[i]) * e[i];
      const double db = 10.0 * std::log10(diff / ref);
      if (db > worst) worst = db, worst_m = m;
    }
  RecordProperty("worst_error_db", std::to_string(worst));
  std::printf("%s: worst error %.1f dB (measurement %zu), load at %.0f Hz\n", c.name, worst, worst_m, c.render_rate);
  EXPECT_LT(worst, -40.0) << "measurement " << worst_m;
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, SofaVariety,
    ::testing::Values(Case{"same_rate_48k", "--rate 48000 --length 256", 48000.0},
                      Case{"up_44k1_to_48k", "--rate 44100 --length 256", 48000.0},
                      Case{"down_96k_to_48k", "--rate 96000 --length 1024", 48000.0},
                      Case{"up_48k_to_96k", "--rate 48000 --length 256", 96000.0},
                      Case{"down_48k_to_44k1", "--rate 48000 --length 256", 44100.0},
                      Case{"delay_in_data_44k1_to_48k", "--rate 44100 --length 256 --delay-in-data", 48000.0},
                      Case{"delay_in_data_same_rate", "--rate 48000 --length 256 --delay-in-data", 48000.0},
                      Case{"cartesian_positions", "--rate 48000 --length 256 --cartesian", 48000.0},
                      Case{"long_late_energy_late_onset", "--rate 48000 --length 8192 --onset-ms 40 --late --grid fibonacci:40",
                           48000.0}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

}  // namespace
