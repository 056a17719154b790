// Real spherical harmonics and Ambisonic conventions, checked against
// independent definitions: orthonormality on an exact quadrature, the C++
// library's associated Legendre functions, ambiX's first-order signs, and
// FuMa's maxN gains measured over the sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"

using namespace earshot;
using namespace earshot::ambisonics;

namespace {

constexpr double kPi = std::numbers::pi;

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  w.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[static_cast<std::size_t>(i)] = z;
    w[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

Vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Vec3 v{g(rng), g(rng), g(rng)};
  const double n = norm(v);
  return {v[0] / n, v[1] / n, v[2] / n};
}

double factorial(int n) {
  double f = 1.0;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

}  // namespace

TEST(SphericalHarmonics, N3dIsOrthonormalOnAnExactQuadrature) {
  // Gauss-Legendre in sin(elevation) x uniform azimuth integrates products
  // of degree <= 2 x 7 exactly.
  constexpr int N = kMaxOrder;
  std::vector<double> z, wz;
  gauss_legendre(N + 2, z, wz);
  const int naz = 2 * N + 4;
  const std::size_t C = channel_count(N);
  std::vector<double> gram(C * C, 0.0), y(C);
  for (std::size_t i = 0; i < z.size(); ++i)
    for (int a = 0; a < naz; ++a) {
      const double az = 2 * kPi * a / naz, el = std::asin(z[i]);
      real_sh(N, ambix_from_sofa(az, el), std::span<double>(y));
      for (std::size_t c = 0; c < C; ++c) y[c] *= std::sqrt(2.0 * degree_of(c) + 1.0);  // SN3D -> N3D
      const double w = wz[i] * 2 * kPi / naz / (4 * kPi);
      for (std::size_t r = 0; r < C; ++r)
        for (std::size_t c = 0; c < C; ++c) gram[r * C + c] += w * y[r] * y[c];
    }
  for (std::size_t r = 0; r < C; ++r)
    for (std::size_t c = 0; c < C; ++c) EXPECT_NEAR(gram[r * C + c], r == c ? 1.0 : 0.0, 1e-12) << r << "," << c;
}

TEST(SphericalHarmonics, MatchTheLibrarysLegendreFunctionsWithSn3d) {
  // std::assoc_legendre has no Condon-Shortley phase, as ambiX.
  std::mt19937 rng(3);
  std::vector<double> y(channel_count(kMaxOrder));
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 d = random_direction(rng);
    const double az = std::atan2(d[1], d[0]), el = std::asin(d[2]);
    real_sh(kMaxOrder, d, std::span<double>(y));
    for (int l = 0; l <= kMaxOrder; ++l)
      for (int m = -l; m <= l; ++m) {
        const int a = std::abs(m);
        const double n = std::sqrt((a == 0 ? 1.0 : 2.0) * factorial(l - a) / factorial(l + a));
        const double p = std::assoc_legendre(static_cast<unsigned>(l), static_cast<unsigned>(a), std::sin(el));
        const double expected = n * p * (m >= 0 ? std::cos(a * az) : std::sin(a * az));
        EXPECT_NEAR(y[acn(l, m)], expected, 1e-11) << "l " << l << " m " << m;
      }
  }
}

TEST(SphericalHarmonics, FirstOrderSignsFollowAmbix) {
  // ACN 1, 2, 3 = Y (left), Z (up), X (ahead); W = 1 in SN3D.
  std::vector<double> y(4);
  const auto enc = [&](const Vec3& world) {
    real_sh(1, ambix_from_world(world), std::span<double>(y));
    return y;
  };
  EXPECT_EQ(enc({0, 0, -1}), (std::vector<double>{1, 0, 0, 1}));   // ahead: -z in the world
  EXPECT_EQ(enc({-1, 0, 0}), (std::vector<double>{1, 1, 0, 0}));   // left: -x
  EXPECT_EQ(enc({0, 1, 0}), (std::vector<double>{1, 0, 1, 0}));    // up: +y
  EXPECT_EQ(enc({1, 0, 0}), (std::vector<double>{1, -1, 0, 0}));   // right
  EXPECT_EQ(enc({0, 0, 1}), (std::vector<double>{1, 0, 0, -1}));   // behind
  // A SOFA azimuth of +90 deg is the left.
  real_sh(1, ambix_from_sofa(kPi / 2, 0), std::span<double>(y));
  EXPECT_NEAR(y[1], 1.0, 1e-15);
  EXPECT_NEAR(y[3], 0.0, 1e-15);
  // The world <-> ambiX maps are inverse.
  const Vec3 w{0.3, -0.4, 0.5};
  EXPECT_EQ(world_from_ambix(ambix_from_world(w)), w);
}

TEST(SphericalHarmonics, FumaHasMaxNGainsAndItsChannelOrder) {
  // Every FuMa channel but W peaks at 1 over the sphere; W is 1/sqrt 2.
  const ChannelMap to_fuma = from_ambix(Convention::fuma, 3);
  std::vector<double> peak(16, 0.0), y(16);
  for (int i = 0; i <= 360; ++i)
    for (int j = 0; j <= 180; ++j) {
      const double az = 2 * kPi * i / 360.0, el = kPi * (j - 90) / 180.0;
      real_sh(3, ambix_from_sofa(az, el), std::span<double>(y));
      for (std::size_t f = 0; f < 16; ++f) peak[f] = std::max(peak[f], std::abs(to_fuma.gain[f] * y[to_fuma.source[f]]));
    }
  EXPECT_NEAR(peak[0], 1.0 / std::sqrt(2.0), 1e-9);
  for (std::size_t f = 1; f < 16; ++f) EXPECT_NEAR(peak[f], 1.0, 2e-4) << "FuMa channel " << f;
  // Textbook FuMa channels (Malham): X Y Z, R, U, P at one direction.
  const double az = 0.7, el = 0.3;
  real_sh(3, ambix_from_sofa(az, el), std::span<double>(y));
  auto fuma = [&](std::size_t f) { return to_fuma.gain[f] * y[to_fuma.source[f]]; };
  EXPECT_NEAR(fuma(1), std::cos(az) * std::cos(el), 1e-12);                               // X
  EXPECT_NEAR(fuma(2), std::sin(az) * std::cos(el), 1e-12);                               // Y
  EXPECT_NEAR(fuma(3), std::sin(el), 1e-12);                                              // Z
  EXPECT_NEAR(fuma(4), 1.5 * std::sin(el) * std::sin(el) - 0.5, 1e-12);                   // R
  EXPECT_NEAR(fuma(5), std::cos(az) * std::sin(2 * el), 1e-12);                           // S
  EXPECT_NEAR(fuma(7), std::cos(2 * az) * std::cos(el) * std::cos(el), 1e-12);            // U
  EXPECT_NEAR(fuma(9), 0.5 * std::sin(el) * (5 * std::sin(el) * std::sin(el) - 3), 1e-12);  // K
  EXPECT_NEAR(fuma(14), std::cos(3 * az) * std::pow(std::cos(el), 3), 1e-12);             // P
  EXPECT_NEAR(fuma(15), std::sin(3 * az) * std::pow(std::cos(el), 3), 1e-12);             // Q
}

TEST(SphericalHarmonics, ConversionsRoundTrip) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Convention c : {Convention::ambix, Convention::n3d, Convention::fuma})
    for (int order = 1; order <= (c == Convention::fuma ? kMaxFumaOrder : kMaxOrder); ++order) {
      const std::size_t C = channel_count(order);
      std::vector<double> ambix(C), other(C), back(C);
      for (double& v : ambix) v = u(rng);
      const ChannelMap out = from_ambix(c, order), in = to_ambix(c, order);
      for (std::size_t n = 0; n < C; ++n) other[n] = out.gain[n] * ambix[out.source[n]];
      for (std::size_t n = 0; n < C; ++n) back[n] = in.gain[n] * other[in.source[n]];
      for (std::size_t n = 0; n < C; ++n) EXPECT_NEAR(back[n], ambix[n], 1e-14) << convention_name(c) << order;
    }
  // N3D is SN3D times sqrt(2l + 1).
  const ChannelMap n3d = from_ambix(Convention::n3d, 2);
  EXPECT_NEAR(n3d.gain[acn(2, 1)], std::sqrt(5.0), 1e-15);
  EXPECT_THROW((void)to_ambix(Convention::fuma, 4), std::invalid_argument);
}

TEST(SphericalHarmonics, OrderFromChannels) {
  EXPECT_EQ(order_from_channels(4), 1);
  EXPECT_EQ(order_from_channels(36), 5);
  EXPECT_EQ(order_from_channels(64), 7);
  EXPECT_EQ(order_from_channels(5), -1);
  EXPECT_EQ(order_from_channels(81), -1);
  EXPECT_EQ(degree_of(0), 0);
  EXPECT_EQ(degree_of(3), 1);
  EXPECT_EQ(degree_of(4), 2);
  EXPECT_EQ(degree_of(35), 5);
}
