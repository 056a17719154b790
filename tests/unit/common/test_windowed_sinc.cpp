// The Kaiser-windowed sinc against values worked out independently: the
// Bessel function's tabulated values, the sinc's zeros, the window's edge.
#include "earshot/windowed_sinc.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace earshot {
namespace {

TEST(WindowedSinc, BesselI0MatchesTables) {
  EXPECT_EQ(bessel_i0(0.0), 1.0);
  EXPECT_NEAR(bessel_i0(1.0), 1.2660658777520084, 1e-15);
  EXPECT_NEAR(bessel_i0(7.0) / 168.59390851028968, 1.0, 1e-14);
  EXPECT_NEAR(bessel_i0(8.0) / 427.56411572180479, 1.0, 1e-14);
}

TEST(WindowedSinc, IsOneAtZeroAndZeroAtOtherWholeNumbers) {
  EXPECT_EQ(kaiser_sinc(0.0, 8.0, 7.0), 1.0);
  for (double x : {-7.0, -3.0, -1.0, 1.0, 2.0, 5.0}) EXPECT_EQ(kaiser_sinc(x, 8.0, 7.0), 0.0) << x;
}

TEST(WindowedSinc, IsTheSincTimesTheKaiserWindow) {
  const double half = 8.0, beta = 7.0;
  for (double x : {0.5, -0.25, 2.75, -6.5, 7.9}) {
    const double sinc = std::sin(std::numbers::pi * x) / (std::numbers::pi * x);
    const double r = x / half;
    const double window = bessel_i0(beta * std::sqrt(1 - r * r)) / bessel_i0(beta);
    EXPECT_NEAR(kaiser_sinc(x, half, beta), sinc * window, 1e-15) << x;
    EXPECT_EQ(kaiser_sinc(x, half, beta), kaiser_sinc(-x, half, beta)) << x;  // even
  }
  EXPECT_NEAR(kaiser_sinc(0.5, half, beta), 2 / std::numbers::pi * bessel_i0(beta * std::sqrt(1 - 1.0 / 256)) / bessel_i0(beta), 1e-15);
}

TEST(WindowedSinc, IsZeroFromTheHalfWidthOut) {
  EXPECT_EQ(kaiser_sinc(8.0, 8.0, 7.0), 0.0);
  EXPECT_EQ(kaiser_sinc(-8.5, 8.0, 7.0), 0.0);
  EXPECT_EQ(kaiser_sinc(40.3, 32.0, 8.0), 0.0);
  EXPECT_GT(std::abs(kaiser_sinc(31.5, 32.0, 8.0)), 0.0);
}

}  // namespace
}  // namespace earshot
