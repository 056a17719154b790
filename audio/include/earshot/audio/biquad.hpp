// Second-order IIR sections (transposed direct form II) and the designs the
// reverbs and their measurements need: Butterworth low/high-pass, and a
// 4th-order Butterworth high shelf whose gain is set *at* a given frequency
// (the reverbs' absorption and input filters). Designs go through the
// bilinear transform with the corner pre-warped.
#pragma once

#include <array>
#include <span>

namespace earshot::audio {

struct BiquadCoeffs {
  double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0;  ///< a0 normalised to 1
};

/// One section with its state; process() runs in place and never allocates.
class Biquad {
 public:
  Biquad() = default;
  explicit Biquad(const BiquadCoeffs& c) : c_(c) {}
  void set(const BiquadCoeffs& c) { c_ = c; }
  void reset() { z1_ = z2_ = 0; }
  double tick(double x) {
    const double y = c_.b0 * x + z1_;
    z1_ = c_.b1 * x - c_.a1 * y + z2_;
    z2_ = c_.b2 * x - c_.a2 * y;
    return y;
  }
  void process(std::span<float> io) {
    for (auto& v : io) v = static_cast<float>(tick(v));
  }

 private:
  BiquadCoeffs c_;
  double z1_ = 0, z2_ = 0;
};

/// Butterworth sections of order 2 * N (N sections), corner fc (Hz).
template <std::size_t N>
[[nodiscard]] std::array<BiquadCoeffs, N> butterworth_lowpass(double fc, double fs);
template <std::size_t N>
[[nodiscard]] std::array<BiquadCoeffs, N> butterworth_highpass(double fc, double fs);

/// 4th-order Butterworth high shelf, two sections: gain 1 below fc, and gain
/// `gain_at_f` at frequency f (> fc) exactly, flat above. Its magnitude is
/// |H|^2 = (1 + g^2 W^8) / (1 + W^8), W the pre-warped frequency over fc, so
/// it stays within 0.02 dB of 1 an octave below fc. A gain deeper than the
/// shelf can reach at f is clamped to the deepest it can (|H(f)|^2 ~ 1/(1+W^8)).
[[nodiscard]] std::array<BiquadCoeffs, 2> high_shelf4(double fc, double f, double gain_at_f, double fs);

/// |H(e^jw)| of a cascade at frequency f.
[[nodiscard]] double magnitude(std::span<const BiquadCoeffs> cascade, double f, double fs);
/// Group delay (samples) of a cascade at frequency f.
[[nodiscard]] double group_delay(std::span<const BiquadCoeffs> cascade, double f, double fs);

}  // namespace earshot::audio
