// The near field against the rigid-sphere model (issue 15, part 5): white
// noise rendered through the Renderer from 0.2, 0.5, 1 and 2 m at azimuths
// 0..180 degrees (horizontal plane, left side) with MIT KEMAR (measured at
// 1.4 m), and its ILD per band and ITD (below 1.5 kHz) compared, as changes
// from the render at KEMAR's own distance, with the same changes of the
// sphere model (a = 8.75 cm, ears at +-90 degrees). Then a set measured at
// 0.5, 1 and 2 m (tests/fixtures/make_sofa.py) rendered at and between its
// shells against its own data.
//
//   near_field [--sofa FILE] [--csv OUT.csv] [--make-sofa make_sofa.py]
//
// Prints markdown tables; --csv writes one row per (distance, azimuth) for
// tools/plot_near_field.py.
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "binaural_cues.hpp"
#include "earshot/audio/real_fft.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/errors.hpp"
#include "earshot/hrtf/rigid_sphere.hpp"

using namespace earshot;
using namespace earshot::audio;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kRate = 48000.0;

struct Band {
  double lo, hi;
  const char* name;
};
constexpr Band kBands[] = {{500, 2000, "0.5-2k"}, {2000, 6000, "2-6k"}, {6000, 12000, "6-12k"}};

struct Stereo {
  std::vector<float> l, r;
};

Vec3 openal_at(double r, double azimuth_deg, double elevation_deg = 0.0) {
  const double az = azimuth_deg * kDeg, el = elevation_deg * kDeg;
  return {-r * std::cos(el) * std::sin(az), r * std::sin(el), -r * std::cos(el) * std::cos(az)};
}

Stereo render(const std::shared_ptr<const hrtf::HrtfSet>& set, double r, double az, double el = 0.0) {
  RendererConfig cfg;
  cfg.doppler_factor = 0.0;
  Renderer ren(set, cfg);
  SourceState s;
  s.relative = true;
  s.distance.model = DistanceModel::none;
  s.position = openal_at(r, az, el);
  const int id = ren.add_source(s);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-0.05f, 0.05f);
  Stereo out;
  std::vector<float> l(ren.block()), rr(ren.block());
  for (int b = 0; b < 420; ++b) {
    for (float& x : ren.source_input(id)) x = u(rng);
    ren.render(l, rr);
    if (b < 40) continue;  // the filters filling
    out.l.insert(out.l.end(), l.begin(), l.end());
    out.r.insert(out.r.end(), rr.begin(), rr.end());
  }
  return out;
}

/// Left over right energy per band (dB), Hann frames of 4096.
std::vector<double> band_ild(const Stereo& s) {
  constexpr std::size_t N = 4096;
  const RealFft fft(N);
  std::vector<float> frame(N);
  std::vector<std::complex<float>> spec(N / 2 + 1);
  std::vector<double> el(std::size(kBands)), er(std::size(kBands));
  for (std::size_t at = 0; at + N <= s.l.size(); at += N / 2)
    for (int ear = 0; ear < 2; ++ear) {
      const auto& x = ear == 0 ? s.l : s.r;
      for (std::size_t i = 0; i < N; ++i)
        frame[i] = x[at + i] * static_cast<float>(0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * double(i) / N));
      fft.forward(frame, spec);
      for (std::size_t k = 0; k < spec.size(); ++k)
        for (std::size_t b = 0; b < std::size(kBands); ++b) {
          const double f = double(k) * kRate / N;
          if (f >= kBands[b].lo && f < kBands[b].hi) (ear == 0 ? el : er)[b] += std::norm(spec[k]);
        }
    }
  std::vector<double> out(std::size(kBands));
  for (std::size_t b = 0; b < out.size(); ++b) out[b] = 10.0 * std::log10(el[b] / er[b]);
  return out;
}

/// The sphere's band ILDs for a horizontal source at (r, azimuth).
std::vector<double> sphere_ild(double r, double az) {
  const double uy = std::sin(az * kDeg);
  std::vector<double> out;
  for (const Band& b : kBands) {
    double el = 0.0, er = 0.0;
    for (double f = b.lo; f < b.hi; f += kRate / 4096) {
      const hrtf::RigidSphereSeries h(r, f);
      el += std::norm(h.at(std::acos(uy)));
      er += std::norm(h.at(std::acos(-uy)));
    }
    out.push_back(10.0 * std::log10(el / er));
  }
  return out;
}

/// The sphere's ITD (s, left leading positive) by its paths.
double sphere_itd(double r, double az) {
  const double uy = std::sin(az * kDeg);
  return hrtf::sphere_path_delay(r, std::acos(-uy)) - hrtf::sphere_path_delay(r, std::acos(uy));
}

double itd(const Stereo& s) { return analysis::itd_s(s.l, s.r, kRate, 1.2e-3, 1500.0); }

}  // namespace

int main(int argc, char** argv) {
  std::string sofa = hrtf::HrtfSet::kDefaultPath, csv, make_sofa;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sofa" && i + 1 < argc) sofa = argv[++i];
    else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
    else if (a == "--make-sofa" && i + 1 < argc) make_sofa = argv[++i];
    else {
      std::fprintf(stderr, "usage: near_field [--sofa FILE] [--csv OUT.csv] [--make-sofa make_sofa.py]\n");
      return 2;
    }
  }
  std::shared_ptr<const hrtf::HrtfSet> set;
  try {
    set = std::make_shared<const hrtf::HrtfSet>(hrtf::HrtfSet::load(sofa, kRate));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "near_field: %s\n", e.what());
    return 2;
  }
  const double R = set->shell(0).radius_m;
  std::printf("## Near field: %s (measured at %.2f m) against the rigid sphere (a = 8.75 cm)\n\n", sofa.c_str(), R);
  std::printf("Changes from the render at %.2f m (rendered / model): ILD per band (dB), ITD below 1.5 kHz (us).\n\n", R);
  std::printf("| r (m) | az | dILD 0.5-2k | dILD 2-6k | dILD 6-12k | dITD (us) |\n|---|---|---|---|---|---|\n");
  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    if (!out) {
      std::fprintf(stderr, "near_field: %s: cannot write\n", csv.c_str());
      return 2;
    }
    out << "distance_m,azimuth_deg,ild_lo_db,ild_mid_db,ild_hi_db,itd_us,far_ild_lo_db,far_ild_mid_db,far_ild_hi_db,"
           "far_itd_us,model_ild_lo_db,model_ild_mid_db,model_ild_hi_db,model_itd_us,model_far_ild_lo_db,"
           "model_far_ild_mid_db,model_far_ild_hi_db,model_far_itd_us\n";
  }
  const double distances[] = {0.2, 0.5, 1.0, 2.0};
  std::vector<std::vector<double>> worst_at(std::size(distances), std::vector<double>(std::size(kBands) + 1, 0.0));
  for (double az = 0; az <= 180; az += 15) {
    const Stereo far = render(set, R, az);
    const auto far_ild = band_ild(far), model_far = sphere_ild(R, az);
    const double far_itd = itd(far), model_far_itd = sphere_itd(R, az);
    for (std::size_t di = 0; di < std::size(distances); ++di) {
      const double r = distances[di];
      const Stereo s = render(set, r, az);
      const auto ild = band_ild(s), model = sphere_ild(r, az);
      const double t = itd(s), model_t = sphere_itd(r, az);
      std::printf("| %.1f | %3.0f |", r, az);
      for (std::size_t b = 0; b < ild.size(); ++b) {
        const double dr = ild[b] - far_ild[b], dm = model[b] - model_far[b];
        std::printf(" %+.2f / %+.2f |", dr, dm);
        worst_at[di][b] = std::max(worst_at[di][b], std::abs(dr - dm));
      }
      const double dt = (t - far_itd) * 1e6, dtm = (model_t - model_far_itd) * 1e6;
      std::printf(" %+.0f / %+.0f |\n", dt, dtm);
      worst_at[di].back() = std::max(worst_at[di].back(), std::abs(dt - dtm));
      if (out)
        out << r << ',' << az << ',' << ild[0] << ',' << ild[1] << ',' << ild[2] << ',' << t * 1e6 << ','
            << far_ild[0] << ',' << far_ild[1] << ',' << far_ild[2] << ',' << far_itd * 1e6 << ',' << model[0] << ','
            << model[1] << ',' << model[2] << ',' << model_t * 1e6 << ',' << model_far[0] << ',' << model_far[1]
            << ',' << model_far[2] << ',' << model_far_itd * 1e6 << '\n';
    }
  }
  std::printf("\nWorst |rendered - model| of the changes over azimuth:\n\n| r (m) | 0.5-2k (dB) | 2-6k (dB) | 6-12k (dB) | ITD (us) |\n|---|---|---|---|---|\n");
  for (std::size_t di = 0; di < std::size(distances); ++di)
    std::printf("| %.1f | %.2f | %.2f | %.2f | %.0f |\n", distances[di], worst_at[di][0], worst_at[di][1],
                worst_at[di][2], worst_at[di][3]);

  // Absolute far-field cues of the set beside the sphere's: where the
  // measured head is not a sphere.
  std::printf("\nThe set at its own distance against the sphere there (absolute ILD dB, ITD us):\n\n"
              "| az | ILD 0.5-2k | ILD 2-6k | ILD 6-12k | ITD |\n|---|---|---|---|---|\n");
  for (double az = 0; az <= 180; az += 30) {
    const Stereo far = render(set, R, az);
    const auto ild = band_ild(far), model = sphere_ild(R, az);
    std::printf("| %3.0f | %+.1f / %+.1f | %+.1f / %+.1f | %+.1f / %+.1f | %+.0f / %+.0f |\n", az, ild[0], model[0],
                ild[1], model[1], ild[2], model[2], itd(far) * 1e6, sphere_itd(R, az) * 1e6);
  }

  if (!make_sofa.empty()) {
    // A set with its own shells: at a shell's distance the render is that
    // shell's data; between shells the nearest shell, corrected by the sphere.
    const auto dir = std::filesystem::temp_directory_path() / "earshot_near_field_bench";
    std::filesystem::create_directories(dir);
    const auto file = dir / "three_shells.sofa";
    const std::string cmd = "/usr/bin/python3 " + make_sofa + " --out " + file.string() +
                            " --rate 48000 --length 256 --grid fibonacci:400 --distances 0.5,1,2";
    if (std::system(cmd.c_str()) != 0) {
      std::fprintf(stderr, "near_field: failed: %s\n", cmd.c_str());
      return 2;
    }
    const auto three = std::make_shared<const hrtf::HrtfSet>(hrtf::HrtfSet::load(file, kRate));
    std::printf("\n## A set measured at 0.5, 1 and 2 m (make_sofa.py, fibonacci:400): broadband ILD (dB) at 90 degrees\n\n"
                "| r (m) | shell used | rendered | nearest measurement of that shell | sphere change from the shell |\n|---|---|---|---|---|\n");
    for (const double r : {0.3, 0.5, 0.6, 0.75, 1.0, 1.25, 1.5, 2.0, 3.0}) {
      const std::size_t s = three->nearest_shell(r);
      const auto& sh = three->shell(s);
      std::size_t best = sh.first;
      double dot = -2.0;
      for (std::size_t i = sh.first; i < sh.first + sh.count; ++i) {
        const auto e = three->direction(i);
        const double c = std::cos(e.elevation) * std::sin(e.azimuth);
        if (c > dot) dot = c, best = i;
      }
      const auto e = three->direction(best);
      const Stereo st = render(three, r, e.azimuth / kDeg, e.elevation / kDeg);
      const double own = analysis::ild_db(three->measured_hrir(best, hrtf::Ear::left), three->measured_hrir(best, hrtf::Ear::right));
      const auto m_r = sphere_ild(r, e.azimuth / kDeg), m_s = sphere_ild(sh.radius_m, e.azimuth / kDeg);
      std::printf("| %.2f | %.1f m | %.2f | %.2f | %+.2f (0.5-2k) |\n", r, sh.radius_m, analysis::ild_db(st.l, st.r), own,
                  m_r[0] - m_s[0]);
    }
  }
  return 0;
}
