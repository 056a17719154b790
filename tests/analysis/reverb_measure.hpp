// Measurements of a reverb's impulse response (tests/bench/reverb_decay and
// the reverb unit tests, tests/unit/audio/test_reverb.cpp):
//  - band_rt60: RT60 in a band by Schroeder backward integration, T30 (line
//    fit of the energy decay curve between -5 and -35 dB, times 2);
//  - echo density profile after Abel & Huang (2006): in a sliding 20 ms Hann
//    window, the weighted fraction of samples beyond one standard deviation,
//    divided by erfc(1/sqrt 2) (so Gaussian noise reads 1);
//  - interaural coherence (peak of the normalised cross-correlation, +-1 ms).
#pragma once

#include <optional>
#include <span>
#include <vector>

namespace earshot::analysis {

struct Band {
  double low_hz, high_hz;
  int order;  ///< Butterworth order of each of the high-pass and low-pass edges (2 or 4)
};
/// Octave band around fc (4th-order edges); third-octave (8th-order edges, for
/// the high band, where slower lower frequencies must not leak in).
[[nodiscard]] Band octave(double fc);
[[nodiscard]] Band third_octave(double fc);

/// `signals` filtered through the band, energies summed (e.g. both ears).
[[nodiscard]] std::vector<double> band_energy(std::span<const std::span<const float>> signals, const Band& b,
                                              double fs);
/// Energy decay curve in dB (0 dB at t = 0) by backward integration.
[[nodiscard]] std::vector<double> energy_decay_db(std::span<const double> energy);
/// T30-based RT60 (s) from an EDC; nullopt when it does not reach -35 dB.
[[nodiscard]] std::optional<double> rt60_t30(std::span<const double> edc_db, double fs);
/// RT60 of (left, right) in a band.
[[nodiscard]] std::optional<double> band_rt60(std::span<const float> left, std::span<const float> right,
                                              const Band& b, double fs);

/// Echo density profile, one value per `step` samples (window centred there).
[[nodiscard]] std::vector<double> echo_density(std::span<const float> h, double fs, std::size_t step);
/// Seconds from the first arrival (first |h| >= 1e-3 of the peak) to the first
/// time the normalised echo density reaches 1; nullopt if it never does.
[[nodiscard]] std::optional<double> echo_density_time(std::span<const float> h, double fs);

/// Largest |normalised cross-correlation| of left and right within +-1 ms.
[[nodiscard]] double interaural_coherence(std::span<const float> left, std::span<const float> right, double fs);

}  // namespace earshot::analysis
