#include "earshot/audio/decay_filter.hpp"

#include <cmath>

namespace earshot::audio {

DecayFilter design_decay_filter(double loop_samples, double t60, double hf_ratio, double f_hf, double fs) {
  constexpr double kMidHz = 700.0;  // between the 500 Hz and 1 kHz bands
  const double fc = f_hf / 2.2;
  double tau_mid = 0.0, tau_hf = 0.0;
  DecayFilter d;
  // Twice: the second pass uses the group delays of the first design.
  for (int pass = 0; pass < 2; ++pass) {
    const double db_mid = -60.0 * (loop_samples + tau_mid) / (fs * t60);
    const double db_hf = -60.0 * (loop_samples + tau_hf) / (fs * t60 * hf_ratio);
    d.gain = std::pow(10.0, db_mid / 20.0);
    d.shelf = high_shelf4(fc, f_hf, std::pow(10.0, (db_hf - db_mid) / 20.0), fs);
    tau_mid = group_delay(d.shelf, kMidHz, fs);
    tau_hf = group_delay(d.shelf, f_hf, fs);
  }
  return d;
}

}  // namespace earshot::audio
