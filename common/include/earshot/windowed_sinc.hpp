// The Kaiser-windowed sinc: the one band-limited interpolation kernel, used
// by the fractional delay's read kernels (audio) and the HRTF onset split's
// sub-sample shifts (hrtf).
#pragma once

namespace earshot {

/// Modified Bessel function of the first kind, order 0 (its power series,
/// 40 terms: exact to double precision for the window's arguments, <= 20).
[[nodiscard]] double bessel_i0(double x);

/// One tap of a Kaiser-windowed sinc: sin(pi x) / (pi x) (exactly 1 at 0
/// and exactly 0 at the other whole numbers) times the Kaiser window of
/// shape `beta` reaching zero at |x| = half_width. Not normalised: callers
/// scale their taps to unit DC gain.
[[nodiscard]] double kaiser_sinc(double x, double half_width, double beta);

/// The same kernel with the window's normalisation computed once: for
/// callers that evaluate many taps of one shape (load-time FIR design).
class KaiserSinc {
 public:
  KaiserSinc(double half_width, double beta);
  [[nodiscard]] double operator()(double x) const;

 private:
  double half_width_, beta_, i0_beta_;
};

}  // namespace earshot
