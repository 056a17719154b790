#include "reverb_measure.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "earshot/audio/biquad.hpp"

namespace earshot::analysis {
using audio::Biquad;

Band octave(double fc) { return {fc / std::numbers::sqrt2, fc * std::numbers::sqrt2, 4}; }
Band third_octave(double fc) {
  const double k = std::pow(2.0, 1.0 / 6.0);
  return {fc / k, fc * k, 8};
}

std::vector<double> band_energy(std::span<const std::span<const float>> signals, const Band& b, double fs) {
  std::vector<Biquad> chain;
  auto add = [&](auto sections) {
    for (const auto& c : sections) chain.emplace_back(c);
  };
  if (b.order == 8) {
    add(audio::butterworth_highpass<4>(b.low_hz, fs));
    add(audio::butterworth_lowpass<4>(b.high_hz, fs));
  } else {
    add(audio::butterworth_highpass<2>(b.low_hz, fs));
    add(audio::butterworth_lowpass<2>(b.high_hz, fs));
  }
  std::vector<double> e(signals.empty() ? 0 : signals[0].size(), 0.0);
  for (const auto& s : signals) {
    for (auto& f : chain) f.reset();
    for (std::size_t i = 0; i < s.size() && i < e.size(); ++i) {
      double y = s[i];
      for (auto& f : chain) y = f.tick(y);
      e[i] += y * y;
    }
  }
  return e;
}

std::vector<double> energy_decay_db(std::span<const double> energy) {
  std::vector<double> edc(energy.size());
  double acc = 0.0;
  for (std::size_t i = energy.size(); i-- > 0;) {
    acc += energy[i];
    edc[i] = acc;
  }
  const double total = edc.empty() ? 0.0 : edc[0];
  for (auto& v : edc) v = total > 0 && v > 0 ? 10.0 * std::log10(v / total) : -400.0;
  return edc;
}

std::optional<double> rt60_t30(std::span<const double> edc_db, double fs) {
  std::size_t i5 = edc_db.size(), i35 = edc_db.size();
  for (std::size_t i = 0; i < edc_db.size(); ++i) {
    if (i5 == edc_db.size() && edc_db[i] <= -5.0) i5 = i;
    if (edc_db[i] <= -35.0) {
      i35 = i;
      break;
    }
  }
  if (i35 >= edc_db.size() || i35 <= i5 + 2) return std::nullopt;
  // Least-squares line through the EDC (dB) against time between the two points.
  double st = 0, sy = 0, stt = 0, sty = 0;
  const double n = static_cast<double>(i35 - i5 + 1);
  for (std::size_t i = i5; i <= i35; ++i) {
    const double t = static_cast<double>(i) / fs;
    st += t, sy += edc_db[i], stt += t * t, sty += t * edc_db[i];
  }
  const double slope = (n * sty - st * sy) / (n * stt - st * st);  // dB per second
  if (!(slope < 0)) return std::nullopt;
  return -60.0 / slope;
}

std::optional<double> band_rt60(std::span<const float> left, std::span<const float> right, const Band& b,
                                double fs) {
  const std::span<const float> both[] = {left, right};
  const auto e = band_energy(both, b, fs);
  return rt60_t30(energy_decay_db(e), fs);
}

std::vector<double> echo_density(std::span<const float> h, double fs, std::size_t step) {
  const auto half = static_cast<std::size_t>(std::lround(0.010 * fs));  // 20 ms window
  std::vector<double> w(2 * half + 1);
  double wsum = 0.0;
  for (std::size_t k = 0; k < w.size(); ++k) {
    w[k] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * double(k + 1) / double(w.size() + 1));
    wsum += w[k];
  }
  for (auto& v : w) v /= wsum;
  const double norm = 1.0 / std::erfc(1.0 / std::numbers::sqrt2);
  std::vector<double> out;
  for (std::size_t c = 0; c < h.size(); c += step) {
    double var = 0.0;
    for (std::size_t k = 0; k < w.size(); ++k) {
      const std::size_t i = c + k;
      if (i < half || i - half >= h.size()) continue;
      var += w[k] * double(h[i - half]) * h[i - half];
    }
    const double sd = std::sqrt(var);
    double frac = 0.0;
    if (sd > 0)
      for (std::size_t k = 0; k < w.size(); ++k) {
        const std::size_t i = c + k;
        if (i < half || i - half >= h.size()) continue;
        if (std::abs(h[i - half]) > sd) frac += w[k];
      }
    out.push_back(frac * norm);
  }
  return out;
}

std::optional<double> echo_density_time(std::span<const float> h, double fs) {
  float peak = 0.0f;
  for (float v : h) peak = std::max(peak, std::abs(v));
  if (peak <= 0) return std::nullopt;
  const auto first = static_cast<std::size_t>(
      std::find_if(h.begin(), h.end(), [&](float v) { return std::abs(v) >= 1e-3f * peak; }) - h.begin());
  const std::size_t step = static_cast<std::size_t>(std::lround(fs * 0.0005));  // 0.5 ms
  const auto tail = h.subspan(first, std::min(h.size() - first, static_cast<std::size_t>(fs)));
  const auto ed = echo_density(tail, fs, step);
  for (std::size_t k = 0; k < ed.size(); ++k)
    if (ed[k] >= 1.0) return static_cast<double>(k * step) / fs;
  return std::nullopt;
}

double interaural_coherence(std::span<const float> left, std::span<const float> right, double fs) {
  const auto lag = static_cast<long>(std::lround(0.001 * fs));
  const auto n = static_cast<long>(std::min(left.size(), right.size()));
  double el = 0, er = 0;
  for (long i = 0; i < n; ++i) el += double(left[i]) * left[i], er += double(right[i]) * right[i];
  if (el <= 0 || er <= 0) return 0.0;
  double best = 0.0;
  for (long d = -lag; d <= lag; ++d) {
    double c = 0.0;
    for (long i = std::max(0L, -d); i < n && i + d < n; ++i) c += double(left[i]) * right[i + d];
    best = std::max(best, std::abs(c) / std::sqrt(el * er));
  }
  return best;
}

}  // namespace earshot::analysis
