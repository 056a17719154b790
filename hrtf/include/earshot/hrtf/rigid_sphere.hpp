// The rigid-sphere head model of Duda and Martens (1998, "Range dependence
// of the response of a spherical head model", JASA 104(5)): the sound
// pressure at a point on the surface of a rigid sphere of radius a, from a
// point source at distance r from its centre, for a source seen at angle
// theta from that surface point (theta = 0: the point faces the source).
//
//   H(rho, mu, theta) = -(rho / mu) e^{-i mu rho}
//                       sum_m (2m + 1) P_m(cos theta) h_m(mu rho) / h'_m(mu)
//
// with rho = r / a (> 1), mu = 2 pi f a / c, P_m the Legendre polynomials and
// h_m the spherical Hankel functions of the first kind. H is relative to the
// free-field pressure the same source makes at the sphere's centre with the
// sphere absent: |H| -> 1 at low frequency for a distant source, and the
// factor e^{-i mu rho} takes out the flight time to the centre, so the phase
// is the ear's arrival relative to the centre (time convention e^{-i omega t}:
// a delay tau multiplies by e^{i omega tau}, so an earlier ear has a phase that
// falls with frequency).
//
// Evaluation as in the paper: P_m, h_m(mu rho) and h_m(mu) by their upward
// recurrences (h'_m from h_{m-1} and h_m), in double. The paper stops when a
// term falls below a threshold of the sum; here the coefficients
// c_m = (2m + 1) h_m(mu rho) / h'_m(mu) do not depend on theta, so one
// series serves every angle (RigidSphereSeries), and it stops once two
// coefficients in a row are below 1e-12 of the largest and m > mu + 2
// (before that the coefficients need not decay; testing the terms instead
// would stop early at theta = 90 degrees, where every odd P_m is zero).
// Infinite distance gives the plane-wave solution (Rayleigh's), which the
// same series reaches as rho -> infinity. Frequency 0 gives the quasi-static
// limit, c_m = (2m + 1) / (m + 1) rho^-m.
//
// Earshot uses it with a = 8.75 cm (the paper's and 3D Tune-In's default)
// and the ears at +-90 degrees on the interaural axis (the paper fits its
// data better with +-100; the renderer's parallax puts the ears on the axis,
// and the two must agree).
#pragma once

#include <complex>
#include <vector>

namespace earshot::hrtf {

struct SphereHead {
  double radius_m = 0.0875;
  double speed_of_sound = 343.0;
};

/// The series for one distance and frequency, summed at any angle.
class RigidSphereSeries {
 public:
  /// `distance_m` (> the radius; infinity for a plane wave), `freq_hz` >= 0.
  RigidSphereSeries(double distance_m, double freq_hz, const SphereHead& head = {});
  /// H at angle `theta` (radians, 0..pi) from the surface point.
  [[nodiscard]] std::complex<double> at(double theta) const;
  /// Terms kept (for tests of the stopping rule).
  [[nodiscard]] std::size_t terms() const { return c_.size(); }
  /// The coefficients c_m (prefactor included): H(theta) is
  /// sum_m c_m P_m(cos theta), for callers that sum many series at the same
  /// angles and keep the Legendre values.
  [[nodiscard]] const std::vector<std::complex<double>>& coefficients() const { return c_; }

 private:
  std::vector<std::complex<double>> c_;  // the coefficients, prefactor included
};

/// H for a source `distance_m` from the centre (> the radius; infinity for
/// a plane wave) at angle `theta` (radians, 0..pi) from the surface point,
/// at `freq_hz` (>= 0; 0 gives the low-frequency limit).
[[nodiscard]] std::complex<double> rigid_sphere_response(double distance_m, double theta, double freq_hz,
                                                         const SphereHead& head = {});

/// The delay (seconds, relative to the centre) of sound reaching the
/// surface point along the shortest path outside the sphere: straight when
/// the point sees the source, else the tangent and the arc around the
/// sphere. The near-field extension of Woodworth's formula, which it equals
/// as the distance grows.
[[nodiscard]] double sphere_path_delay(double distance_m, double theta, const SphereHead& head = {});

}  // namespace earshot::hrtf
