#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <numbers>
#include <random>
#include <vector>

#include "earshot/errors.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "../scratch_path.hpp"

using namespace earshot::hrtf;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

const HrtfSet& kemar48() {
  static const HrtfSet set = HrtfSet::load_default(48000.0);
  return set;
}

double energy(std::span<const float> x) {
  double e = 0;
  for (float v : x) e += double(v) * v;
  return e;
}

/// Broadband ILD (dB, left over right) of a filter pair.
double ild_db(std::span<const float> l, std::span<const float> r) { return 10.0 * std::log10(energy(l) / energy(r)); }

std::string load_error(const fs::path& p, double rate = 48000.0) {
  try {
    (void)HrtfSet::load(p, rate);
  } catch (const earshot::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(HrtfSet, LoadsTheDefaultKemarSet) {
  const auto& s = kemar48();
  EXPECT_EQ(s.measurement_count(), 710u);
  EXPECT_EQ(s.sample_rate(), 48000.0);
  EXPECT_GE(s.filter_length(), 512u);
  EXPECT_LE(s.filter_length(), 600u);
  const auto s44 = HrtfSet::load_default(44100.0);
  EXPECT_EQ(s44.measured_hrir(0, Ear::left).size(), 512u) << "the file's own length at its own rate";
  // The filters add the margin kept before the onsets (KEMAR rings about
  // twenty samples ahead of its -20 dB onsets).
  EXPECT_GE(s44.filter_length(), 512u);
  EXPECT_LE(s44.filter_length(), 560u);
}

/// x delayed by d samples, band-limited (the split's delays are fractional):
/// a Kaiser-windowed sinc of 64 taps, independent of the loader's own.
std::vector<float> delayed(std::span<const float> x, double d, std::size_t n) {
  std::vector<float> y(n, 0.0f);
  constexpr int kHalf = 32;
  auto i0 = [](double v) {
    double sum = 1, term = 1;
    for (int k = 1; k < 40; ++k) sum += (term *= (v / (2.0 * k)) * (v / (2.0 * k)));
    return sum;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const double t = double(i) - d;
    double acc = 0;
    for (long k = long(std::floor(t)) - kHalf + 1; k <= long(std::floor(t)) + kHalf; ++k) {
      if (k < 0 || k >= long(x.size())) continue;
      const double u = t - double(k), r = u / kHalf;
      const double sinc = u == 0 ? 1.0 : std::sin(std::numbers::pi * u) / (std::numbers::pi * u);
      if (std::abs(r) < 1) acc += x[std::size_t(k)] * sinc * i0(8 * std::sqrt(1 - r * r)) / i0(8);
    }
    y[i] = static_cast<float>(acc);
  }
  return y;
}

TEST(HrtfSet, OnsetSplitReproducesEveryMeasuredHrir) {
  // Filter delayed by its delay (plus the flight time removed at load), per
  // ear, must be the measured HRIR but for the faint pre-ringing before the
  // onset (energy below -40 dB), so its interaural time difference is kept,
  // and its broadband ILD within 0.01 dB.
  const auto& s = kemar48();
  const double rate = s.sample_rate();
  double worst_ild = 0;
  for (std::size_t m = 0; m < s.measurement_count(); m += 3) {
    const auto hl = s.measured_hrir(m, Ear::left), hr = s.measured_hrir(m, Ear::right);
    const std::size_t n = hl.size();
    const double common = s.removed_delay_s();
    const auto rl = delayed(s.filter(m, Ear::left), (s.delays(m).left_s + common) * rate, n);
    const auto rr = delayed(s.filter(m, Ear::right), (s.delays(m).right_s + common) * rate, n);
    worst_ild = std::max(worst_ild, std::abs(ild_db(rl, rr) - ild_db(hl, hr)));
    for (Ear ear : {Ear::left, Ear::right}) {
      const auto h = s.measured_hrir(m, ear);
      const auto& rec = ear == Ear::left ? rl : rr;
      double err = 0;
      for (std::size_t i = 0; i < h.size(); ++i) err += (h[i] - rec[i]) * (h[i] - rec[i]);
      EXPECT_LT(err, 1e-4 * energy(h)) << "measurement " << m;
    }
  }
  EXPECT_LT(worst_ild, 0.01);
}

TEST(HrtfSet, LookupAtAMeasuredDirectionReturnsThatMeasurement) {
  const auto& s = kemar48();
  std::vector<float> l(s.filter_length()), r(s.filter_length());
  for (std::size_t m = 0; m < s.measurement_count(); m += 7) {
    const auto d = s.direction(m);
    const Delays del = s.lookup(d.azimuth, d.elevation, l, r);
    EXPECT_NEAR(del.left_s, s.delays(m).left_s, 1e-9) << m;
    EXPECT_NEAR(del.right_s, s.delays(m).right_s, 1e-9) << m;
    const auto fl = s.filter(m, Ear::left);
    for (std::size_t i = 0; i < l.size(); ++i) ASSERT_NEAR(l[i], fl[i], 1e-5) << m;
  }
}

TEST(HrtfSet, BlendEnergyAndEarGainMatchTheBlendedFilters) {
  // interpolate() gives the energy of the plain weighted sum from each
  // triangle's table of inner products; check it against summing the
  // filters, and that the ear gain brings that sum to the interpolated energy.
  const auto& s = kemar48();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> az(-180, 180), el(-90, 90);
  std::vector<double> sum(s.filter_length());
  for (int k = 0; k < 300; ++k) {
    const Interpolation in = s.interpolate(az(rng) * kDeg, el(rng) * kDeg);
    for (std::size_t ear = 0; ear < 2; ++ear) {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (std::size_t v = 0; v < 3; ++v) {
        const auto f = s.filter(in.blend.index[v], static_cast<Ear>(ear));
        for (std::size_t i = 0; i < f.size(); ++i) sum[i] += in.blend.weight[v] * f[i];
      }
      double e = 0;
      for (double x : sum) e += x * x;
      ASSERT_NEAR(in.blend_energy[ear], e, 1e-9 * e + 1e-15) << k;
      const double g = in.ear_gain(ear);
      EXPECT_NEAR(g * g * e, in.energy[ear], 1e-9 * in.energy[ear]) << k;
    }
  }
}

TEST(HrtfSet, CuesMoveSmoothlyBetweenMeasuredDirections) {
  // In 1-degree steps the interpolated delays and filter energies change by
  // no more than the measured data changes between neighbouring measurements
  // spread over the gap (the interpolation is exact at the measurements and
  // linear between them). Measured with MIT KEMAR at 48 kHz; the rendered
  // cues are checked by tests/bench/cue_accuracy on WAVs.
  const auto& s = kemar48();
  std::vector<float> l(s.filter_length()), r(s.filter_length());
  for (double el : {-30.0, 0.0, 30.0}) {
    double prev_itd = 0, prev_ild = 0, worst_itd = 0, worst_ild = 0;
    for (int az = -180; az <= 180; ++az) {
      const Delays d = s.lookup(az * kDeg, el * kDeg, l, r);
      const double itd = d.right_s - d.left_s, ild = ild_db(l, r);
      if (az > -180) {
        worst_itd = std::max(worst_itd, std::abs(itd - prev_itd));
        worst_ild = std::max(worst_ild, std::abs(ild - prev_ild));
      }
      prev_itd = itd;
      prev_ild = ild;
    }
    EXPECT_LT(worst_itd, 11e-6) << "elevation " << el;
    EXPECT_LT(worst_ild, 0.45) << "elevation " << el;
  }
}

TEST(HrtfSet, LeftIsLeft) {
  const auto& s = kemar48();
  std::vector<float> l(s.filter_length()), r(s.filter_length());
  const Delays d = s.lookup(90 * kDeg, 0, l, r);  // SOFA: +90 deg azimuth = left
  EXPECT_LT(d.left_s, d.right_s - 400e-6);
  EXPECT_GT(ild_db(l, r), 6.0);
}

TEST(HrtfSet, EveryDirectionGivesFiniteOutput) {
  const auto& s = kemar48();
  std::vector<float> l(s.filter_length()), r(s.filter_length());
  for (int el = -90; el <= 90; el += 5)
    for (int az = -180; az < 180; az += 5) {
      const Delays d = s.lookup(az * kDeg, el * kDeg, l, r);
      ASSERT_TRUE(std::isfinite(d.left_s) && std::isfinite(d.right_s));
      ASSERT_GT(energy(l), 0.0) << az << "," << el;
      for (float v : l) ASSERT_TRUE(std::isfinite(v));
    }
}

TEST(HrtfSet, ParametricItd) {
  EXPECT_NEAR(woodworth_itd(0, 0, 0.0875), 0.0, 1e-12);
  EXPECT_NEAR(woodworth_itd(90 * kDeg, 0, 0.0875), 0.0875 / 343.0 * (std::numbers::pi / 2 + 1), 1e-12);
  EXPECT_NEAR(woodworth_itd(90 * kDeg, 0, 0.0875), 0.656e-3, 0.01e-3);
  EXPECT_LT(woodworth_itd(-90 * kDeg, 0, 0.0875), 0.0);
  EXPECT_LT(head_radius_m(HeadSize::small), head_radius_m(HeadSize::large));
  HrtfSet s = HrtfSet::load_default(48000.0);
  s.set_parametric_itd(head_radius_m(HeadSize::large));
  std::vector<float> l(s.filter_length()), r(s.filter_length());
  const Delays d = s.lookup(90 * kDeg, 0, l, r);
  EXPECT_NEAR(d.right_s - d.left_s, woodworth_itd(90 * kDeg, 0, 0.10), 1e-12);
}

TEST(HrtfSet, BadFilesGetOneClearError) {
  const fs::path dir = earshot::test::scratch_path("hrtf_test");
  fs::create_directories(dir);
  EXPECT_EQ(load_error(dir / "missing.sofa"), (dir / "missing.sofa").string() + ": file not found");
  std::ofstream(dir / "empty.sofa").close();
  EXPECT_EQ(load_error(dir / "empty.sofa"), (dir / "empty.sofa").string() + ": empty file");
  std::ofstream(dir / "text.sofa") << "this is not a SOFA file\n";
  EXPECT_EQ(load_error(dir / "text.sofa"), (dir / "text.sofa").string() + ": not a SOFA file (no HDF5 signature)");
  {  // the first 10 kB of the real file
    std::ifstream in(HrtfSet::kDefaultPath, std::ios::binary);
    std::vector<char> head(10240);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(dir / "truncated.sofa", std::ios::binary).write(head.data(), in.gcount());
  }
  const std::string trunc = load_error(dir / "truncated.sofa");
  EXPECT_EQ(trunc.rfind((dir / "truncated.sofa").string() + ": ", 0), 0u) << trunc;
  EXPECT_NE(load_error(HrtfSet::kDefaultPath, 1000.0).find("unsupported render rate"), std::string::npos);
  {  // another convention: patch the convention attribute's value in a copy
    std::ifstream in(HrtfSet::kDefaultPath, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string from = "SimpleFreeFieldHRIR", to = "SimpleFreeFieldHRXX";
    std::size_t n = 0;
    for (auto at = bytes.find(from); at != std::string::npos; at = bytes.find(from, at + 1), ++n)
      bytes.replace(at, from.size(), to);
    ASSERT_GT(n, 0u);
    std::ofstream(dir / "other.sofa", std::ios::binary) << bytes;
  }
  const std::string other = load_error(dir / "other.sofa");
  EXPECT_NE(other.find("SimpleFreeFieldHRXX"), std::string::npos) << other;
}

TEST(HrtfSet, CorruptedCopiesOfTheDefaultFileGetAnErrorOrLoadCleanly) {
  // Outside bytes reach libmysofa here: flipped bytes, zeroed runs and
  // truncations of the real file must give an InputError naming the file,
  // or a set whose every filter is finite; never a crash.
  std::ifstream in(HrtfSet::kDefaultPath, std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(good.size(), 10000u);
  const fs::path file = earshot::test::scratch_path("hrtf_test") / "corrupt.sofa";
  fs::create_directories(file.parent_path());
  std::mt19937 rng(20261123);
  int errors = 0, loaded = 0;
  for (int k = 0; k < 60; ++k) {
    std::string bytes = good;
    std::uniform_int_distribution<std::size_t> at(0, bytes.size() - 1);
    switch (k % 3) {
      case 0:  // a few flipped bytes
        for (int i = 0; i < 1 + k % 16; ++i) bytes[at(rng)] ^= static_cast<char>(1 + rng() % 255);
        break;
      case 1: {  // a zeroed run
        const std::size_t from = at(rng), n = std::min<std::size_t>(bytes.size() - from, 1 + rng() % 4096);
        std::fill_n(bytes.begin() + static_cast<long>(from), n, '\0');
        break;
      }
      default:  // truncated
        bytes.resize(at(rng));
    }
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    try {
      const HrtfSet s = HrtfSet::load(file, 48000.0);
      ++loaded;
      for (std::size_t m = 0; m < s.measurement_count(); ++m)
        for (float v : s.filter(m, Ear::left)) ASSERT_TRUE(std::isfinite(v)) << "copy " << k;
    } catch (const earshot::InputError& e) {
      ++errors;
      EXPECT_EQ(std::string(e.what()).rfind(file.string() + ": ", 0), 0u) << e.what();
    }
  }
  EXPECT_GT(errors, 10);
  std::printf("corrupted copies: %d rejected with an error, %d loaded\n", errors, loaded);
}

namespace {

earshot::Vec3 unit_vector(const Direction& d) {
  return {std::cos(d.elevation) * std::cos(d.azimuth), std::cos(d.elevation) * std::sin(d.azimuth), std::sin(d.elevation)};
}

/// The point on the sphere that weights w give the triangle's measurements.
earshot::Vec3 blend_point(const HrtfSet& s, const std::array<std::uint32_t, 3>& index, const std::array<double, 3>& w) {
  earshot::Vec3 p{0, 0, 0};
  for (std::size_t k = 0; k < 3; ++k) {
    const earshot::Vec3 u = unit_vector(s.direction(index[k]));
    for (std::size_t i = 0; i < 3; ++i) p[i] += w[k] * u[i];
  }
  const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  return {p[0] / n, p[1] / n, p[2] / n};
}

double angle_deg(const earshot::Vec3& a, const earshot::Vec3& b) {
  return std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0)) / kDeg;
}

}  // namespace

TEST(HrtfSet, BlendFloorMovesOnlyTheSpectralDetailAndByAtMostItsAngle) {
  // The filter weights fade out below each triangle's floor; the delays and
  // the energies keep the plain barycentric weights, so the ITD and each
  // ear's broadband level do not move, and the filter blend's point stays
  // within kSpectralShiftDeg of the barycentric one.
  const auto& s = kemar48();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> az(-180, 180), el(-90, 90);
  double worst = 0, nonzero = 0;
  const int n = 3000;
  for (int k = 0; k < n; ++k) {
    const Interpolation in = s.interpolate(az(rng) * kDeg, el(rng) * kDeg);
    double sum = 0, bsum = 0, left = 0, right = 0;
    for (std::size_t v = 0; v < 3; ++v) {
      ASSERT_GE(in.blend.weight[v], 0.0);
      ASSERT_GE(in.barycentric[v], 0.0);
      sum += in.blend.weight[v];
      bsum += in.barycentric[v];
      nonzero += in.blend.weight[v] > 0.0 ? 1.0 : 0.0;
      const std::size_t m = in.blend.index[v];
      left += in.barycentric[v] * s.delays(m).left_s;
      right += in.barycentric[v] * s.delays(m).right_s;
    }
    ASSERT_NEAR(sum, 1.0, 1e-12);
    ASSERT_NEAR(bsum, 1.0, 1e-12);
    EXPECT_NEAR(in.delays.left_s, left, 1e-12) << k;
    EXPECT_NEAR(in.delays.right_s, right, 1e-12) << k;
    worst = std::max(worst, angle_deg(blend_point(s, in.blend.index, in.blend.weight),
                                      blend_point(s, in.blend.index, in.barycentric)));
  }
  std::printf("blend floor: %.2f filters per direction, spectral blend moved by up to %.2f degrees\n", nonzero / n, worst);
  EXPECT_LE(worst, HrtfSet::kSpectralShiftDeg * 1.01);
  // MIT KEMAR's grid (5 degrees in azimuth on the horizon, 10 in elevation)
  // is dense enough that most directions mix fewer than three filters.
  EXPECT_LT(nonzero / n, 2.5);
  EXPECT_GT(worst, 0.5 * HrtfSet::kSpectralShiftDeg);  // the floor is in use
}

TEST(HrtfSet, PlainBlendKeepsTheBarycentricWeights) {
  HrtfSet s = kemar48();
  s.set_filter_blend(HrtfSet::FilterBlend::plain);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> az(-180, 180), el(-90, 90);
  for (int k = 0; k < 500; ++k) {
    const Interpolation in = s.interpolate(az(rng) * kDeg, el(rng) * kDeg);
    for (std::size_t v = 0; v < 3; ++v) ASSERT_EQ(in.blend.weight[v], in.barycentric[v]) << k;
  }
}

TEST(HrtfSet, NearestBlendTakesTheMeasurementWithTheLargestWeightAlone) {
  HrtfSet s = kemar48();
  const HrtfSet& floored = kemar48();
  s.set_filter_blend(HrtfSet::FilterBlend::nearest);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> az(-180, 180), el(-40, 90);
  for (int k = 0; k < 500; ++k) {
    const double a = az(rng) * kDeg, e = el(rng) * kDeg;
    const Interpolation in = s.interpolate(a, e);
    const auto& b = in.barycentric;
    const auto top = static_cast<std::size_t>(std::max_element(b.begin(), b.end()) - b.begin());
    for (std::size_t v = 0; v < 3; ++v) ASSERT_EQ(in.blend.weight[v], v == top ? 1.0 : 0.0) << k;
    // The cues that do not depend on the filter blend stay where they were.
    const Interpolation ref = floored.interpolate(a, e);
    EXPECT_EQ(in.delays.left_s, ref.delays.left_s) << k;
    EXPECT_EQ(in.delays.right_s, ref.delays.right_s) << k;
    EXPECT_EQ(in.energy[0], ref.energy[0]) << k;
  }
  s.set_filter_blend(HrtfSet::FilterBlend::floored);
  EXPECT_EQ(s.filter_blend(), HrtfSet::FilterBlend::floored);
  const Interpolation back = s.interpolate(0.3, 0.1), ref = floored.interpolate(0.3, 0.1);
  for (std::size_t v = 0; v < 3; ++v) EXPECT_EQ(back.blend.weight[v], ref.blend.weight[v]);
}

TEST(HrtfSet, FlooredWeightsAreContinuousAcrossTriangles) {
  // A moving source's gains glide only if its weights do: along fine paths
  // no measurement's weight jumps, also where the path crosses into
  // another triangle (the vertices it leaves have faded to zero there).
  const auto& s = kemar48();
  double worst = 0;
  for (double el : {-35.0, -12.5, 0.0, 7.0, 33.0, 61.0}) {
    std::vector<std::pair<std::uint32_t, double>> prev;
    for (int i = 0; i <= 36000; ++i) {
      const double a = -180.0 + i * 0.01;
      const Interpolation in = s.interpolate(a * kDeg, el * kDeg);
      std::vector<std::pair<std::uint32_t, double>> now;
      for (std::size_t v = 0; v < 3; ++v)
        if (in.blend.weight[v] > 0.0) now.emplace_back(in.blend.index[v], in.blend.weight[v]);
      if (i > 0) {
        const auto weight_in = [](const std::vector<std::pair<std::uint32_t, double>>& set, std::uint32_t m) {
          for (const auto& [idx, w] : set)
            if (idx == m) return w;
          return 0.0;
        };
        for (const auto& [m, w] : now) worst = std::max(worst, std::abs(w - weight_in(prev, m)));
        for (const auto& [m, w] : prev) worst = std::max(worst, std::abs(w - weight_in(now, m)));
      }
      prev = std::move(now);
    }
  }
  // 0.01 degrees of a >= 5-degree triangle moves a plain weight by ~0.002;
  // the floor steepens that by at most 1 / (1 - 3 x floor).
  EXPECT_LT(worst, 0.02);
}
