// SOFA files of the kinds other databases publish, written by
// tests/fixtures/make_sofa.py from an analytic head model: other rates than
// the render rate (up and down), long responses with late energy after a
// long pre-onset gap, the ITD stored in Data.Delay instead of in the
// responses, Cartesian source positions, several measurement distances in
// one file, the right ear stored first, 32-tap responses, sparse (50) and
// dense (10,000) grids. At every measured direction the loaded set's filter
// and delay must give back the model's response at the render rate
// (arrival included) with an error energy at least 40 dB below the
// response's, and what lookup() (the renderer's path) gives there must have
// the interaural time difference of the file's own responses within 10 us.
#include "../scratch_path.hpp"
#include <gtest/gtest.h>
#include <mysofa.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <initializer_list>
#include <filesystem>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "earshot/errors.hpp"
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
  std::size_t expected_length = 0;  ///< of the expected responses; 0: the set's at the render rate
  std::size_t stride = 1;           ///< check every stride-th measurement (dense grids)
};

// Test names and failure messages show the kind, not the struct's bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

struct SofaDeleter {
  void operator()(MYSOFA_HRTF* h) const { mysofa_free(h); }
};

/// `f` delayed by `delay` samples (band-limited), `n` samples long. The
/// delay is the same for every output sample, so the 128 kernel weights are
/// too: computed once.
std::vector<double> delayed(std::span<const float> f, double delay, std::size_t n) {
  static const earshot::KaiserSinc kernel(64.0, 10.0);
  // out[i] = sum_k f[k] kernel(i - delay - k), over the 128 k nearest to
  // i - delay: k = b - j for j in [-64, 63], b = floor(i - delay) = i - shift.
  const double whole = std::floor(delay), frac = delay - whole;
  const long shift = static_cast<long>(whole) + (frac > 0.0 ? 1 : 0);
  const double g = frac > 0.0 ? 1.0 - frac : 0.0;  // (i - delay) - b
  std::array<double, 128> w{};
  for (long j = -64; j < 64; ++j) w[static_cast<std::size_t>(j + 64)] = kernel(static_cast<double>(j) + g);
  std::vector<double> out(n, 0.0);
  const long size = static_cast<long>(f.size());
  for (std::size_t i = 0; i < n; ++i) {
    const long b = static_cast<long>(i) - shift;
    double acc = 0.0;
    for (long j = std::max(-64L, b - size + 1); j <= std::min(63L, b); ++j)
      acc += f[static_cast<std::size_t>(b - j)] * w[static_cast<std::size_t>(j + 64)];
    out[i] = acc;
  }
  return out;
}

/// Right ear's arrival minus left ear's, in samples: the lag (within
/// +-max_lag) of the cross-correlation's peak, refined by a parabola
/// through it and its neighbours.
template <typename A, typename B>
double interaural_lag(const A& left, const B& right, std::size_t n, long max_lag) {
  const auto xc = [&](long lag) {
    double acc = 0.0;
    for (long i = std::max(0L, -lag); i < static_cast<long>(n) && i + lag < static_cast<long>(n); ++i)
      acc += double(left[static_cast<std::size_t>(i)]) * double(right[static_cast<std::size_t>(i + lag)]);
    return acc;
  };
  long best = -max_lag;
  double peak = xc(best);
  for (long lag = -max_lag + 1; lag <= max_lag; ++lag)
    if (const double v = xc(lag); v > peak) peak = v, best = lag;
  const double a = xc(best - 1), c = xc(best + 1), den = a - 2.0 * peak + c;
  return static_cast<double>(best) + (den < 0.0 ? 0.5 * (a - c) / den : 0.0);
}

class SofaVariety : public ::testing::TestWithParam<Case> {};

TEST_P(SofaVariety, EveryMeasuredDirectionGivesBackItsResponse) {
  const Case& c = GetParam();
  const fs::path dir = earshot::test::scratch_path("sofa_variety_" + std::string(c.name));
  fs::create_directories(dir);
  const fs::path file = dir / "set.sofa", expected = dir / "expected.sofa";
  // Debian's interpreter, which has python3-netcdf4 (not whatever python3 is first on PATH).
  const std::string cmd = std::string("/usr/bin/python3 ") + EARSHOT_MAKE_SOFA + " --out " + file.string() + " " + c.args +
                          " --expected " + expected.string() + " --expected-rate " + std::to_string(c.render_rate) +
                          (c.expected_length ? " --expected-length " + std::to_string(c.expected_length) : "");
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;

  const HrtfSet set = HrtfSet::load(file, c.render_rate);
  int err = 0;
  const std::unique_ptr<MYSOFA_HRTF, SofaDeleter> want(mysofa_load(expected.c_str(), &err));
  ASSERT_TRUE(want && err == MYSOFA_OK) << expected;
  const std::size_t M = want->M, N = want->N;
  ASSERT_EQ(set.measurement_count(), M);
  if (!c.expected_length) {
    ASSERT_EQ(set.measured_hrir(0, Ear::left).size(), N) << "the response length at the render rate";
  }
  ASSERT_GE(set.filter_length() + (c.expected_length ? N : 0), N);

  // Rebuild each response from the set's filter and delay (the common delay
  // the set removed added back), then fit the one level the set applies.
  std::vector<std::vector<double>> rebuilt(2 * M);
  double cross = 0.0, own = 0.0;
  for (std::size_t m = 0; m < M; m += c.stride)
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
  for (std::size_t m = 0; m < M; m += c.stride)
    for (std::size_t ear = 0; ear < 2; ++ear) {
      const auto& r = rebuilt[2 * m + ear];
      const float* e = want->DataIR.values + (2 * m + ear) * N;
      double diff = 0.0, ref = 0.0;
      for (std::size_t i = 0; i < N; ++i) diff += (level * r[i] - e[i]) * (level * r[i] - e[i]), ref += double(e[i]) * e[i];
      const double db = 10.0 * std::log10(diff / ref);
      if (db > worst) worst = db, worst_m = m;
    }

  // The ITD: what lookup() gives at each measured direction, rebuilt as
  // above, against the file's own responses, by the same estimator (the
  // cross-correlation peak). A swapped pair of ears would flip its sign.
  const auto max_lag = static_cast<long>(std::ceil(1.2e-3 * c.render_rate));
  std::vector<float> fl(set.filter_length()), fr(set.filter_length());
  double worst_itd_us = 0.0;
  std::size_t worst_itd_m = 0;
  for (std::size_t m = 0; m < M; m += c.stride) {
    const auto at = set.direction(m);
    const auto d = set.lookup(at.azimuth, at.elevation, fl, fr);
    const auto l = delayed(fl, d.left_s * c.render_rate, N), r = delayed(fr, d.right_s * c.render_rate, N);
    const float* e = want->DataIR.values + 2 * m * N;
    const double rendered = interaural_lag(l, r, N, max_lag);
    const double own_itd = interaural_lag(e, e + N, N, max_lag);
    const double miss_us = std::abs(rendered - own_itd) / c.render_rate * 1e6;
    if (miss_us > worst_itd_us) worst_itd_us = miss_us, worst_itd_m = m;
  }
  RecordProperty("worst_error_db", std::to_string(worst));
  RecordProperty("worst_itd_error_us", std::to_string(worst_itd_us));
  std::printf("%s: worst error %.1f dB (measurement %zu), worst ITD error %.2f us (measurement %zu), load at %.0f Hz\n",
              c.name, worst, worst_m, worst_itd_us, worst_itd_m, c.render_rate);
  EXPECT_LT(worst, -40.0) << "measurement " << worst_m;
  EXPECT_LT(worst_itd_us, 10.0) << "measurement " << worst_itd_m;
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
                           48000.0},
                      // The farthest of three shells (nearer shells have a larger ILD).
                      Case{"three_distances", "--rate 48000 --length 256 --grid fibonacci:100 --distances 0.5,1,2", 48000.0},
                      Case{"right_ear_first", "--rate 48000 --length 256 --grid fibonacci:100 --swap-receivers", 48000.0},
                      Case{"right_ear_first_delay_in_data_44k1_to_48k",
                           "--rate 44100 --length 256 --grid fibonacci:100 --swap-receivers --delay-in-data", 48000.0},
                      // 32 taps hold the responses; the ITD is in Data.Delay, as in real 32-tap sets.
                      Case{"taps_32", "--rate 48000 --length 32 --short --delay-in-data --grid fibonacci:100", 48000.0, 128},
                      Case{"taps_32_44k1_to_48k", "--rate 44100 --length 32 --short --delay-in-data --grid fibonacci:100",
                           48000.0, 128},
                      Case{"sparse_50", "--rate 48000 --length 256 --grid fibonacci:50", 48000.0},
                      Case{"dense_10k", "--rate 48000 --length 96 --short --grid fibonacci:10000 --compress", 48000.0, 0, 47}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

}  // namespace

// The loader's size limits (HrtfSet::kMax*): a file just over each gets an
// error naming the file and the dimension, before any work that grows with
// it; one just under loads.
namespace {

/// Writes a set with make_sofa.py `args` into a fresh file named `name`.
fs::path make_set(const std::string& name, const std::string& args) {
  const fs::path dir = earshot::test::scratch_path("sofa_limits");
  fs::create_directories(dir);
  const fs::path file = dir / (name + ".sofa");
  const std::string cmd = std::string("/usr/bin/python3 ") + EARSHOT_MAKE_SOFA + " --out " + file.string() + " " + args;
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("failed: " + cmd);
  return file;
}

/// The error HrtfSet::load gives (empty when it loads).
std::string load_error(const fs::path& file, double rate) {
  try {
    (void)HrtfSet::load(file, rate);
  } catch (const earshot::InputError& e) {
    return e.what();
  }
  return {};
}

TEST(SofaLimits, MeasurementsJustOverAreRefusedJustUnderLoad) {
  // 8 directions measured 2500 times (repeats are legal and cheap to triangulate).
  const fs::path under = make_set("m_under", "--length 8 --grid fibonacci:8 --repeat 2500 --compress");
  ASSERT_EQ(HrtfSet::kMaxMeasurements, 20000u);
  EXPECT_EQ(load_error(under, 48000.0), "");
  EXPECT_EQ(HrtfSet::load(under, 48000.0).measurement_count(), 20000u);
  const fs::path over = make_set("m_over", "--length 8 --grid fibonacci:3 --repeat 6667 --compress");  // 20001
  const std::string e = load_error(over, 48000.0);
  EXPECT_NE(e.find(over.string()), std::string::npos) << e;
  EXPECT_NE(e.find("dimension M (measurements) is 20001, more than 20000"), std::string::npos) << e;
}

TEST(SofaLimits, LengthJustOverIsRefusedJustUnderLoads) {
  ASSERT_EQ(HrtfSet::kMaxLength, 65536u);
  const fs::path under = make_set("n_under", "--rate 192000 --length 65536 --grid fibonacci:6 --compress");
  EXPECT_EQ(load_error(under, 192000.0), "");
  const fs::path over = make_set("n_over", "--rate 192000 --length 65537 --grid fibonacci:6 --compress");
  const std::string e = load_error(over, 192000.0);
  EXPECT_NE(e.find(over.string()), std::string::npos) << e;
  EXPECT_NE(e.find("dimension N (taps) is 65537, more than 65536"), std::string::npos) << e;
}

TEST(SofaLimits, SamplesAtTheRenderRateJustOverAreRefused) {
  // 11 x 2 x 65536 taps at 8 kHz are 1.4M samples; at 192 kHz 24 times as
  // many, just over 2^25 (10 directions would be just under).
  const fs::path file = make_set("total", "--rate 8000 --length 65536 --grid fibonacci:11 --compress");
  const std::string e = load_error(file, 192000.0);
  EXPECT_NE(e.find(file.string()), std::string::npos) << e;
  EXPECT_NE(e.find("M x R x N at the render rate"), std::string::npos) << e;
  EXPECT_NE(e.find("more than 33554432"), std::string::npos) << e;
  EXPECT_EQ(load_error(file, 8000.0), "");
}

TEST(SofaLimits, ThreeReceiversAreRefused) {
  const fs::path file = make_set("r3", "--length 16 --grid fibonacci:8 --extra-receiver");
  const std::string e = load_error(file, 48000.0);
  EXPECT_NE(e.find(file.string()), std::string::npos) << e;
  EXPECT_NE(e.find("dimension R (receivers) is 3, expected 2"), std::string::npos) << e;
}

}  // namespace

// What made one fuzz input load for minutes: an attribute whose dataspace
// declares ~7e13 elements, which libmysofa reads one by one (seeking past
// the end of the file each time). The look at the headers before libmysofa
// (hrtf/src/sofa_precheck.hpp) refuses it; here on a minimal HDF5 file laid
// out by the specification: superblock v2, one object header holding one
// message (an attribute of a 1-byte integer, or a dataset's dataspace).
#include "../../../hrtf/src/sofa_precheck.hpp"

namespace {

/// `v1`: the attribute message and its dataspace in their version 1 layouts
/// (8-byte padding; reserved bytes in the dataspace), which libmysofa reads too.
std::vector<std::uint8_t> one_message_file(bool attribute, std::uint64_t dim, bool v1 = false) {
  // Signature, superblock version 2, 8-byte offsets and lengths, flags; then
  // the base, extension, end-of-file and root addresses and the checksum.
  std::vector<std::uint8_t> f(48, 0);
  const std::array<int, 12> head{0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n', 2, 8, 8, 0};
  for (std::size_t i = 0; i < head.size(); ++i) f[i] = static_cast<std::uint8_t>(head[i]);
  const auto put = [&](std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) f.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  std::vector<std::uint8_t> body;
  const auto add = [&body](std::initializer_list<int> bytes) {
    for (int v : bytes) body.push_back(static_cast<std::uint8_t>(v));
  };
  if (attribute && !v1) {
    add({3, 0, 2, 0, 12, 0, 12, 0, 0, 'a', 0});             // version 3, name "a", encoding
    add({0x10, 0, 0, 0, 1, 0, 0, 0, 0, 0, 8, 0});           // an 8-bit integer
  } else if (attribute) {
    add({1, 0, 2, 0, 12, 0, 16, 0, 'a', 0, 0, 0, 0, 0, 0, 0});  // version 1, name "a" padded to 8
    add({0x10, 0, 0, 0, 1, 0, 0, 0, 0, 0, 8, 0, 0, 0, 0, 0});   // an 8-bit integer, padded to 16
  }
  if (v1)
    add({1, 1, 0, 0, 0, 0, 0, 0});  // dataspace version 1, rank 1, no maximum sizes, reserved
  else
    add({2, 1, 0, 1});  // dataspace version 2, rank 1, no maximum sizes, simple
  for (int i = 0; i < 8; ++i) body.push_back(static_cast<std::uint8_t>(dim >> (8 * i)));
  for (char c : {'O', 'H', 'D', 'R'}) f.push_back(static_cast<std::uint8_t>(c));
  put(2, 1), put(0, 1), put(body.size() + 4 + 4, 1);  // version, flags, chunk size
  put(attribute ? 12 : 1, 1), put(body.size(), 2), put(0, 1);
  for (std::uint8_t v : body) f.push_back(v);
  put(0, 4), put(0, 4);  // gap, checksum
  return f;
}

TEST(SofaHeaderCheck, AttributeDeclaringHugeDataspaceIsRefused) {
  using earshot::hrtf::detail::sofa_header_problem;
  EXPECT_EQ(sofa_header_problem(one_message_file(true, 4), 1000), "");
  const std::string p = sofa_header_problem(one_message_file(true, std::uint64_t{1} << 40), 1000);
  EXPECT_NE(p.find("an attribute's dataspace"), std::string::npos) << p;
  EXPECT_NE(p.find("1099511627776 elements, more than 4096"), std::string::npos) << p;
}

TEST(SofaHeaderCheck, VersionOneAttributeDeclaringHugeDataspaceIsRefused) {
  // libmysofa reads attribute and dataspace messages of version 1 too.
  using earshot::hrtf::detail::sofa_header_problem;
  EXPECT_EQ(sofa_header_problem(one_message_file(true, 4, true), 1000), "");
  const std::string p = sofa_header_problem(one_message_file(true, std::uint64_t{1} << 40, true), 1000);
  EXPECT_NE(p.find("an attribute's dataspace"), std::string::npos) << p;
  EXPECT_NE(p.find("1099511627776 elements, more than 4096"), std::string::npos) << p;
}

TEST(SofaHeaderCheck, AFileFuzzSofaFoundLibmysofaReadingForMinutesIsRefused) {
  // An attribute whose compound type has a version 1 member (which this
  // check did not parse, and stopped), then a dataspace of 1.4e18 elements.
  std::ifstream in(EARSHOT_FUZZ_CORPUS "/sofa/compound_v1_member.sofa", std::ios::binary);
  ASSERT_TRUE(in) << "missing seed";
  const std::vector<std::uint8_t> f((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string p = earshot::hrtf::detail::sofa_header_problem(f, std::uint64_t{1} << 25);
  EXPECT_NE(p.find("an attribute's dataspace"), std::string::npos) << p;
}

TEST(SofaHeaderCheck, DatasetOverTheSampleLimitIsRefused) {
  using earshot::hrtf::detail::sofa_header_problem;
  EXPECT_EQ(sofa_header_problem(one_message_file(false, 1000), 1000), "");
  const std::string p = sofa_header_problem(one_message_file(false, 1001), 1000);
  EXPECT_NE(p.find("a dataset's dataspace"), std::string::npos) << p;
  EXPECT_NE(p.find("1001 elements, more than 1000"), std::string::npos) << p;
}

TEST(SofaHeaderCheck, DataspaceCutByTheEndOfTheFileIsRefused) {
  auto f = one_message_file(true, 4);
  f.resize(f.size() - 12);  // the dimension's last bytes, the gap and checksum
  EXPECT_NE(earshot::hrtf::detail::sofa_header_problem(f, 1000).find("runs past the end"), std::string::npos);
}

}  // namespace
