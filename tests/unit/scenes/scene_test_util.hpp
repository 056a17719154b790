// Helpers of the scenes tests: reading a rendered WAV back, and the
// strongest frequency in a band.
#pragma once

#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <span>
#include <vector>

namespace earshot::scenes::test {

struct Stereo {
  std::vector<float> l, r;
  double rate = 0;
};

inline Stereo read_wav(const std::filesystem::path& p) {
  SF_INFO info{};
  SNDFILE* f = sf_open(p.c_str(), SFM_READ, &info);
  Stereo w;
  if (!f) return w;
  std::vector<float> inter(static_cast<std::size_t>(info.frames) * 2);
  sf_readf_float(f, inter.data(), info.frames);
  sf_close(f);
  for (std::size_t i = 0; i < inter.size() / 2; ++i) w.l.push_back(inter[2 * i]), w.r.push_back(inter[2 * i + 1]);
  w.rate = info.samplerate;
  return w;
}

/// Magnitude of x at frequency f (Hann-windowed Goertzel-like DFT bin).
inline double dft_mag(std::span<const float> x, double rate, double f) {
  double re = 0, im = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double w = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * static_cast<double>(i) / n);
    const double ph = 2 * std::numbers::pi * f * static_cast<double>(i) / rate;
    re += w * x[i] * std::cos(ph);
    im -= w * x[i] * std::sin(ph);
  }
  return std::hypot(re, im);
}

/// The frequency of the strongest component of x in [lo, hi] Hz: a coarse
/// scan, then a fine one around its best.
inline double peak_hz(std::span<const float> x, double rate, double lo, double hi) {
  auto scan = [&](double a, double b, double step) {
    double best = a, best_m = -1;
    for (double f = a; f <= b; f += step)
      if (const double m = dft_mag(x, rate, f); m > best_m) best_m = m, best = f;
    return best;
  };
  const double coarse = scan(lo, hi, 0.25);
  return scan(coarse - 0.3, coarse + 0.3, 0.01);
}

/// The median pitch (Hz) of the voiced frames of x (normalised
/// autocorrelation peak, 60 to 400 Hz), over frames louder than half the
/// signal's RMS.
inline double median_pitch_hz(std::span<const float> x, double rate);

inline double rms(std::span<const float> x) {
  double e = 0;
  for (float v : x) e += double(v) * v;
  return std::sqrt(e / static_cast<double>(std::max<std::size_t>(1, x.size())));
}

inline double median_pitch_hz(std::span<const float> x, double rate) {
  const std::size_t frame = 2048, hop = 1024;
  const double level = rms(x);
  const auto lo = static_cast<std::size_t>(rate / 400), hi = static_cast<std::size_t>(rate / 60);
  std::vector<double> f0;
  for (std::size_t s = 0; s + frame + hi < x.size(); s += hop) {
    const auto a = x.subspan(s, frame);
    if (rms(a) < 0.5 * level) continue;
    double best = 0;
    std::size_t best_lag = 0;
    for (std::size_t lag = lo; lag <= hi; ++lag) {
      double c = 0, e0 = 0, e1 = 0;
      for (std::size_t i = 0; i < frame; ++i) {
        c += double(x[s + i]) * x[s + i + lag];
        e0 += double(x[s + i]) * x[s + i];
        e1 += double(x[s + i + lag]) * x[s + i + lag];
      }
      const double r = c / std::sqrt(e0 * e1 + 1e-30);
      if (r > best) best = r, best_lag = lag;
    }
    if (best > 0.5) f0.push_back(rate / static_cast<double>(best_lag));
  }
  if (f0.empty()) return 0.0;
  std::nth_element(f0.begin(), f0.begin() + static_cast<long>(f0.size() / 2), f0.end());
  return f0[f0.size() / 2];
}

}  // namespace earshot::scenes::test
