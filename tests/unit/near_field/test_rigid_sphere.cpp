// The rigid-sphere model (earshot/hrtf/rigid_sphere.hpp) against what is
// known of it: the far-field and low-frequency limits, the bright spot behind
// the sphere, and values cross-checked with an independent evaluation of the
// same series (closed-form Hankel functions, long double, a fixed 90 terms).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include "earshot/hrtf/hrtf_set.hpp"
#include "earshot/hrtf/rigid_sphere.hpp"

using namespace earshot::hrtf;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();

double db(std::complex<double> h) { return 20.0 * std::log10(std::abs(h)); }

using cld = std::complex<long double>;

/// h_m(x) of the first kind from its closed form
///   (-i)^{m+1} e^{ix} / x sum_{k=0}^{m} i^k (m + k)! / (k! (m - k)! (2x)^k),
/// no recurrence.
cld hankel(int m, long double x) {
  const cld i(0.0L, 1.0L);
  cld sum = 0.0L, ik = 1.0L;
  long double ratio = 1.0L;  // (m + k)! / (k! (m - k)!) / (2x)^k, built term by term
  for (int k = 0; k <= m; ++k) {
    if (k > 0) ratio *= static_cast<long double>((m + k) * (m - k + 1)) / (static_cast<long double>(k) * 2.0L * x);
    sum += ik * ratio;
    ik *= i;
  }
  cld pre = std::exp(i * x) / x;
  for (int k = 0; k <= m; ++k) pre *= -i;
  return pre * sum;
}

/// Duda and Martens' H summed directly: h'_m = (m h_{m-1} - (m + 1) h_{m+1}) / (2m + 1).
std::complex<double> direct_sum(double r, double theta, double f, double a = 0.0875, double c = 343.0) {
  const long double rho = r / a, mu = 2.0L * std::numbers::pi_v<long double> * f * a / c;
  const long double x = std::cos(static_cast<long double>(theta));
  cld sum = 0.0L;
  long double p_prev = 0.0L, p = 1.0L;
  for (int m = 0; m < 90; ++m) {
    const cld dh = m == 0 ? -hankel(1, mu)
                          : (static_cast<long double>(m) * hankel(m - 1, mu) -
                             static_cast<long double>(m + 1) * hankel(m + 1, mu)) /
                                static_cast<long double>(2 * m + 1);
    sum += static_cast<long double>(2 * m + 1) * p * hankel(m, mu * rho) / dh;
    const long double next = ((2.0L * m + 1.0L) * x * p - m * p_prev) / (m + 1.0L);
    p_prev = p;
    p = next;
  }
  const cld i(0.0L, 1.0L);
  const cld h = -(rho / mu) * std::exp(-i * mu * rho) * sum;
  return {static_cast<double>(h.real()), static_cast<double>(h.imag())};
}

}  // namespace

TEST(RigidSphere, MatchesAnIndependentDirectSum) {
  struct Point {
    double r, theta_deg, f;
  };
  for (const Point p : {Point{0.2, 30, 500}, Point{0.2, 90, 12000}, Point{0.5, 120, 3000}, Point{1.0, 180, 8000},
                        Point{1.0, 0, 100}, Point{0.3, 150, 5000}}) {
    const auto got = rigid_sphere_response(p.r, p.theta_deg * kDeg, p.f);
    const auto want = direct_sum(p.r, p.theta_deg * kDeg, p.f);
    EXPECT_LT(std::abs(got - want), 1e-9 * std::abs(want))
        << "r " << p.r << " theta " << p.theta_deg << " f " << p.f << ": " << got << " vs " << want;
  }
}

TEST(RigidSphere, FarSourceAtLowFrequencyIsTheFreeField) {
  for (double theta = 0; theta <= 180; theta += 15) {
    EXPECT_NEAR(std::abs(rigid_sphere_response(1000.0, theta * kDeg, 20.0)), 1.0, 2e-3) << theta;
    EXPECT_NEAR(std::abs(rigid_sphere_response(kInf, theta * kDeg, 20.0)), 1.0, 2e-3) << theta;
  }
}

TEST(RigidSphere, TendsToThePlaneWaveAsTheSourceRecedes) {
  for (const double f : {500.0, 3000.0, 10000.0})
    for (double theta = 0; theta <= 180; theta += 30) {
      const auto plane = rigid_sphere_response(kInf, theta * kDeg, f);
      double last = 1e9;
      for (const double r : {1.0, 10.0, 100.0, 1000.0}) {
        const double miss = std::abs(rigid_sphere_response(r, theta * kDeg, f) - plane) / std::abs(plane);
        EXPECT_LT(miss, last) << "f " << f << " theta " << theta << " r " << r;  // closer the farther
        last = miss;
      }
      EXPECT_LT(last, 1e-3) << "f " << f << " theta " << theta;
    }
  // And the plane wave doubles the pressure on the lit pole at high frequency.
  EXPECT_NEAR(db(rigid_sphere_response(kInf, 0.0, 20000.0)), 6.0, 0.3);
}

TEST(RigidSphere, ZeroFrequencyIsTheLowFrequencyLimit) {
  for (const double r : {0.12, 0.2, 1.0})
    for (double theta = 0; theta <= 180; theta += 45)
      EXPECT_NEAR(std::abs(rigid_sphere_response(r, theta * kDeg, 0.0)),
                  std::abs(rigid_sphere_response(r, theta * kDeg, 1.0)), 1e-4)
          << r << " " << theta;
  // Near the sphere the facing side is louder than the centre even at DC
  // (the paper's figures: about +7 dB at 0.2 m for a = 8.75 cm).
  EXPECT_GT(db(rigid_sphere_response(0.2, 0.0, 0.0)), 6.0);
  EXPECT_LT(db(rigid_sphere_response(0.2, std::numbers::pi, 0.0)), -4.0);
}

TEST(RigidSphere, BrightSpotBehindTheSphere) {
  // Waves around every side arrive at the back pole in phase: louder there
  // than 20-40 degrees off it, at any distance.
  for (const double r : {0.5, 1.0, kInf})
    for (const double f : {2000.0, 4000.0, 8000.0}) {
      const double pole = db(rigid_sphere_response(r, std::numbers::pi, f));
      EXPECT_GT(pole, db(rigid_sphere_response(r, 160 * kDeg, f)) + 1.0) << r << " " << f;
      EXPECT_GT(pole, db(rigid_sphere_response(r, 140 * kDeg, f))) << r << " " << f;
    }
}

TEST(RigidSphere, SeriesStopsOnceTermsVanish) {
  // More terms nearer the surface (rho^-m decays slowly) and at higher mu.
  const RigidSphereSeries near(0.11, 4000.0), far(2.0, 4000.0), high(2.0, 16000.0);
  EXPECT_GT(near.terms(), far.terms());
  EXPECT_GT(high.terms(), far.terms());
  EXPECT_LT(near.terms(), 2000u);
}

TEST(RigidSphere, PathDelayIsWoodworthFarAwayAndStraightWhenLit) {
  const SphereHead head;
  for (double lateral = 0; lateral <= 90; lateral += 15) {
    // Left ear at 90 - lateral, right at 90 + lateral from the source.
    const double l = sphere_path_delay(kInf, (90 - lateral) * kDeg, head);
    const double r = sphere_path_delay(kInf, (90 + lateral) * kDeg, head);
    EXPECT_NEAR(r - l, woodworth_itd(lateral * kDeg, 0.0, head.radius_m, head.speed_of_sound), 1e-9) << lateral;
    EXPECT_NEAR(sphere_path_delay(1e6, (90 + lateral) * kDeg, head), r, 1e-8) << lateral;
  }
  EXPECT_NEAR(sphere_path_delay(0.2, 0.0, head), -head.radius_m / head.speed_of_sound, 1e-12);
  // Near and to the side, the ITD is larger than Woodworth's.
  EXPECT_GT(sphere_path_delay(0.2, std::numbers::pi, head) - sphere_path_delay(0.2, 0.0, head),
            woodworth_itd(std::numbers::pi / 2, 0.0, head.radius_m, head.speed_of_sound));
}
