// The near field through the renderer: KEMAR (measured at 1.4 m) rendered
// near the head against the rigid-sphere model, a source moving through the
// measurement distance without a click, far sources untouched, and a set
// measured at three distances (tests/fixtures/make_sofa.py) rendered from its
// own shells.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "binaural_cues.hpp"
#include "earshot/audio/real_fft.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/hrtf/rigid_sphere.hpp"
#include "../scratch_path.hpp"

using namespace earshot::audio;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kRate = 48000.0;

std::shared_ptr<const earshot::hrtf::HrtfSet> kemar() {
  static const auto set = std::make_shared<const earshot::hrtf::HrtfSet>(earshot::hrtf::HrtfSet::load_default(kRate));
  return set;
}

struct Stereo {
  std::vector<float> l, r;
};

/// OpenAL's frame (+x right, +y up, -z ahead) for a head-relative point at
/// `r` metres, SOFA azimuth (counter-clockwise from ahead) and elevation.
earshot::Vec3 openal_at(double r, double azimuth_deg, double elevation_deg = 0.0) {
  const double az = azimuth_deg * kDeg, el = elevation_deg * kDeg;
  const double x = r * std::cos(el) * std::cos(az), y = r * std::cos(el) * std::sin(az), z = r * std::sin(el);
  return {-y, z, -x};
}

/// White noise from one head-relative source, no distance attenuation, no
/// propagation delay; the first 4800 samples (the filters filling) dropped.
Stereo render(std::shared_ptr<const earshot::hrtf::HrtfSet> set, double r, double azimuth_deg, bool near_field = true,
              int blocks = 400) {
  RendererConfig cfg;
  cfg.doppler_factor = 0.0;
  cfg.near_field = near_field;
  Renderer ren(std::move(set), cfg);
  SourceState s;
  s.relative = true;
  s.distance.model = DistanceModel::none;
  s.position = openal_at(r, azimuth_deg);
  const int id = ren.add_source(s);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.05f, 0.05f);
  Stereo out;
  std::vector<float> l(ren.block()), rr(ren.block());
  for (int b = 0; b < blocks; ++b) {
    for (float& x : ren.source_input(id)) x = u(rng);
    ren.render(l, rr);
    out.l.insert(out.l.end(), l.begin(), l.end());
    out.r.insert(out.r.end(), rr.begin(), rr.end());
  }
  out.l.erase(out.l.begin(), out.l.begin() + 4800);
  out.r.erase(out.r.begin(), out.r.begin() + 4800);
  return out;
}

/// Left over right energy (dB) between lo and hi Hz (Hann-windowed frames of 4096).
double band_ild_db(const Stereo& s, double lo, double hi) {
  constexpr std::size_t N = 4096;
  const RealFft fft(N);
  std::vector<float> frame(N);
  std::vector<std::complex<float>> spec(N / 2 + 1);
  double el = 0.0, er = 0.0;
  for (std::size_t at = 0; at + N <= s.l.size(); at += N / 2)
    for (int ear = 0; ear < 2; ++ear) {
      const auto& x = ear == 0 ? s.l : s.r;
      for (std::size_t i = 0; i < N; ++i)
        frame[i] = x[at + i] * static_cast<float>(0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * double(i) / N));
      fft.forward(frame, spec);
      for (std::size_t k = 0; k < spec.size(); ++k) {
        const double f = double(k) * kRate / N;
        if (f >= lo && f < hi) (ear == 0 ? el : er) += std::norm(spec[k]);
      }
    }
  return 10.0 * std::log10(el / er);
}

/// The sphere's ILD (dB) between lo and hi Hz for a horizontal source at
/// (r, azimuth): each ear's angle from the centre, energy over the same bins.
double sphere_ild_db(double r, double azimuth_deg, double lo, double hi) {
  const double uy = std::sin(azimuth_deg * kDeg);
  double el = 0.0, er = 0.0;
  for (double f = lo; f < hi; f += kRate / 4096) {
    const earshot::hrtf::RigidSphereSeries h(r, f);
    el += std::norm(h.at(std::acos(uy)));
    er += std::norm(h.at(std::acos(-uy)));
  }
  return 10.0 * std::log10(el / er);
}

}  // namespace

TEST(NearFieldRender, IldGrowthAt20cmOnTheAxisFollowsTheSphere) {
  // 90 degrees left at 0.2 m against the same at KEMAR's own 1.4 m: on the
  // interaural axis parallax changes nothing, so the rendered ILD grows by
  // what the near-field filters add; the sphere model says by how much.
  const Stereo near = render(kemar(), 0.2, 90), far = render(kemar(), 1.4, 90);
  for (const auto& [lo, hi] : {std::pair{500.0, 2000.0}, std::pair{2000.0, 6000.0}}) {
    const double rendered = band_ild_db(near, lo, hi) - band_ild_db(far, lo, hi);
    const double model = sphere_ild_db(0.2, 90, lo, hi) - sphere_ild_db(1.4, 90, lo, hi);
    RecordProperty("ild_growth_" + std::to_string(int(lo)), std::to_string(rendered) + " vs " + std::to_string(model));
    std::printf("%g-%g Hz: near-minus-far ILD %.2f dB rendered, %.2f dB model\n", lo, hi, rendered, model);
    EXPECT_GT(model, 5.0);
    EXPECT_NEAR(rendered, model, 1.0) << lo << "-" << hi << " Hz";
  }
}

TEST(NearFieldRender, ItdGrowsNearTheHeadAsTheSpheresPaths) {
  // At 90 degrees and 0.2 m the sphere's ITD exceeds its far-field value by
  // the longer way around to the shadowed ear.
  const Stereo near = render(kemar(), 0.2, 90), far = render(kemar(), 1.4, 90);
  const double rendered = earshot::analysis::itd_s(near.l, near.r, kRate, 1.2e-3, 1500.0) -
                          earshot::analysis::itd_s(far.l, far.r, kRate, 1.2e-3, 1500.0);
  using earshot::hrtf::sphere_path_delay;
  const double model = (sphere_path_delay(0.2, std::numbers::pi) - sphere_path_delay(0.2, 0.0)) -
                       (sphere_path_delay(1.4, std::numbers::pi) - sphere_path_delay(1.4, 0.0));
  std::printf("near-minus-far ITD %.1f us rendered, %.1f us model\n", rendered * 1e6, model * 1e6);
  EXPECT_GT(model, 40e-6);
  EXPECT_NEAR(rendered, model, 8e-6);
}

TEST(NearFieldRender, FarSourcesAreUntouchedBitForBit) {
  // Beyond the measurement distance the near-field path does nothing: the
  // samples equal those of a renderer with it switched off.
  for (const double az : {0.0, 50.0, 130.0}) {
    const Stereo on = render(kemar(), 2.0, az, true, 100), off = render(kemar(), 2.0, az, false, 100);
    EXPECT_EQ(on.l, off.l) << az;
    EXPECT_EQ(on.r, off.r) << az;
  }
  // And near the head it does something.
  const Stereo on = render(kemar(), 0.3, 50, true, 100), off = render(kemar(), 0.3, 50, false, 100);
  EXPECT_NE(on.l, off.l);
}

TEST(NearFieldRender, MovingThroughTheMeasurementDistanceDoesNotClick) {
  // A 500 Hz tone at 60 degrees moving from 2 m to 0.25 m in 3 s, through
  // KEMAR's 1.4 m: the glides of filters, directions and delays must keep
  // what they add above 2 kHz 60 dB below the tone (as the turning head).
  RendererConfig cfg;
  Renderer r(kemar(), cfg);
  SourceState s;
  s.relative = true;
  s.distance.model = DistanceModel::none;
  const int id = r.add_source(s);
  std::vector<float> left, right, l(r.block()), rr(r.block());
  std::size_t n = 0;
  const std::size_t total = 3 * 48000;
  while (n < total) {
    const double t = double(n) / double(total);
    s.position = openal_at(2.0 - 1.75 * t, 60);
    r.set_source(id, s);
    for (float& x : r.source_input(id)) x = 0.1f * float(std::sin(2 * std::numbers::pi * 500.0 * double(n++) / kRate));
    r.render(l, rr);
    left.insert(left.end(), l.begin(), l.end());
    right.insert(right.end(), rr.begin(), rr.end());
  }
  const std::span<const float> sl(left), sr(right);
  const double el = earshot::analysis::energy_above_db(sl.subspan(4800), kRate, 2000.0);
  const double er = earshot::analysis::energy_above_db(sr.subspan(4800), kRate, 2000.0);
  RecordProperty("above_2khz_db", std::to_string(el) + " / " + std::to_string(er));
  std::printf("energy above 2 kHz: left %.1f dB, right %.1f dB\n", el, er);
  EXPECT_LT(el, -60.0);
  EXPECT_LT(er, -60.0);
}

namespace {

/// A set of fibonacci:200 directions at 0.5, 1 and 2 m whose nearer shells
/// have larger ILDs (make_sofa.py's model), written once per process.
fs::path three_shells() {
  static const fs::path file = [] {
    const fs::path dir = earshot::test::scratch_path("near_field");
    fs::create_directories(dir);
    const fs::path f = dir / "three_shells.sofa";
    const std::string cmd = std::string("/usr/bin/python3 ") + EARSHOT_MAKE_SOFA + " --out " + f.string() +
                            " --rate 48000 --length 256 --grid fibonacci:200 --distances 0.5,1,2";
    if (std::system(cmd.c_str()) != 0) throw std::runtime_error("failed: " + cmd);
    return f;
  }();
  return file;
}

}  // namespace

TEST(NearFieldRender, ASetWithSeveralDistancesKeepsEveryShell) {
  const auto set = earshot::hrtf::HrtfSet::load(three_shells(), kRate);
  ASSERT_EQ(set.shell_count(), 3u);
  EXPECT_NEAR(set.shell(0).radius_m, 2.0, 1e-6);
  EXPECT_NEAR(set.shell(1).radius_m, 1.0, 1e-6);
  EXPECT_NEAR(set.shell(2).radius_m, 0.5, 1e-6);
  EXPECT_EQ(set.measurement_count(), 200u);
  EXPECT_EQ(set.all_measurement_count(), 600u);
  EXPECT_EQ(set.nearest_shell(5.0), 0u);
  EXPECT_EQ(set.nearest_shell(0.8), 1u);
  EXPECT_EQ(set.nearest_shell(0.3), 2u);
  // A blend within a shell names that shell's measurements.
  const auto in = set.interpolate_in_shell(earshot::Vec3{0.0, 1.0, 0.0}, 2);
  for (const auto m : in.blend.index) {
    EXPECT_GE(m, 400u);
    EXPECT_LT(m, 600u);
  }
}

TEST(NearFieldRender, ASourceAtANearerShellSoundsAsThatShellsOwnData) {
  // At a shell's own distance the render's ILD is that shell's measured ILD
  // (no synthetic filter on top), not the farthest shell's corrected by the
  // sphere; the shells differ by several dB here, so a wrong shell shows.
  const auto set = std::make_shared<const earshot::hrtf::HrtfSet>(earshot::hrtf::HrtfSet::load(three_shells(), kRate));
  for (const std::size_t s : {std::size_t{2}, std::size_t{1}}) {
    const auto& shell = set->shell(s);
    // A measured direction of that shell, well to the side.
    std::size_t m = shell.first;
    for (std::size_t i = shell.first; i < shell.first + shell.count; ++i)
      if (std::abs(std::sin(set->direction(i).azimuth) * std::cos(set->direction(i).elevation)) > 0.6 &&
          std::abs(set->direction(i).elevation) < 0.4) {
        m = i;
        break;
      }
    const auto d = set->direction(m);
    RendererConfig cfg;
    cfg.doppler_factor = 0.0;
    Renderer ren(set, cfg);
    SourceState src;
    src.relative = true;
    src.distance.model = DistanceModel::none;
    src.position = openal_at(shell.radius_m, d.azimuth / kDeg, d.elevation / kDeg);
    const int id = ren.add_source(src);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-0.05f, 0.05f);
    Stereo out;
    std::vector<float> l(ren.block()), rr(ren.block());
    for (int b = 0; b < 300; ++b) {
      for (float& x : ren.source_input(id)) x = u(rng);
      ren.render(l, rr);
      if (b >= 40) out.l.insert(out.l.end(), l.begin(), l.end()), out.r.insert(out.r.end(), rr.begin(), rr.end());
    }
    const double rendered = earshot::analysis::ild_db(out.l, out.r);
    const auto hl = set->measured_hrir(m, earshot::hrtf::Ear::left), hr = set->measured_hrir(m, earshot::hrtf::Ear::right);
    const double own = earshot::analysis::ild_db(hl, hr);
    // The same direction in the farthest shell: what the wrong shell would give.
    const std::size_t far = [&] {
      std::size_t best = 0;
      double dot = -2.0;
      for (std::size_t i = 0; i < set->measurement_count(); ++i) {
        const auto e = set->direction(i);
        const double c = std::cos(e.elevation) * std::cos(d.elevation) * std::cos(e.azimuth - d.azimuth) +
                         std::sin(e.elevation) * std::sin(d.elevation);
        if (c > dot) dot = c, best = i;
      }
      return best;
    }();
    const double far_ild = earshot::analysis::ild_db(set->measured_hrir(far, earshot::hrtf::Ear::left),
                                                     set->measured_hrir(far, earshot::hrtf::Ear::right));
    std::printf("shell %.1f m, measurement %zu: ILD rendered %.2f dB, its own %.2f dB, the farthest shell's %.2f dB\n",
                shell.radius_m, m, rendered, own, far_ild);
    EXPECT_GT(std::abs(own - far_ild), 1.5);
    EXPECT_NEAR(rendered, own, 0.3) << "shell " << s;
  }
}
