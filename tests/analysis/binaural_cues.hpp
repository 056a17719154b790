// Measuring what a listener would hear in a rendered binaural signal: the
// interaural time difference (ITD) from the cross-correlation peak, found to
// a fraction of a sample, and the broadband interaural level difference
// (ILD). Tests and benchmarks use these on rendered WAVs and on measured
// HRIRs alike, so both sides of a comparison go through the same estimator.
#pragma once

#include <span>

namespace earshot::analysis {

/// ITD in seconds, positive when the left ear leads (the source is on the
/// left). The peak of the cross-correlation within +-max_lag_s is located on
/// an 8x band-limited upsampling of it, then refined by a parabola, so the
/// estimate resolves well below a microsecond at 48 kHz. With max_hz > 0
/// only the band below it counts (ITD is heard mostly below 1.5 kHz).
[[nodiscard]] double itd_s(std::span<const float> left, std::span<const float> right, double sample_rate,
                           double max_lag_s = 1.2e-3, double max_hz = 0.0);

/// Broadband ILD in dB: left energy over right energy.
[[nodiscard]] double ild_db(std::span<const float> left, std::span<const float> right);

/// Energy of `x` above `cutoff_hz` relative to its total energy, in dB
/// (Hann-windowed Welch average over frames of `frame` samples).
[[nodiscard]] double energy_above_db(std::span<const float> x, double sample_rate, double cutoff_hz,
                                     std::size_t frame = 8192);

}  // namespace earshot::analysis
