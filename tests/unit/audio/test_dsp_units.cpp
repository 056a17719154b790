#include <gtest/gtest.h>

#include <mutex>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "earshot/audio/air_absorption.hpp"
#include "earshot/audio/aligned_vector.hpp"
#include "earshot/audio/binaural_bus.hpp"
#include "earshot/audio/binaural_convolver.hpp"
#include "earshot/audio/fractional_delay.hpp"
#include "earshot/audio/real_fft.hpp"

using namespace earshot::audio;

namespace {
std::vector<float> noise(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> v(n);
  for (auto& x : v) x = u(rng);
  return v;
}

std::vector<double> direct_convolution(const std::vector<float>& x, const std::vector<float>& h) {
  std::vector<double> y(x.size(), 0.0);
  for (std::size_t n = 0; n < x.size(); ++n)
    for (std::size_t k = 0; k < h.size() && k <= n; ++k) y[n] += double(h[k]) * x[n - k];
  return y;
}
}  // namespace

TEST(RealFft, RoundTrip) {
  RealFft fft(256);
  const auto x = noise(256, 1);
  std::vector<std::complex<float>> X(fft.bins());
  std::vector<float> y(256);
  fft.forward(x, X);
  fft.inverse(X, y);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(y[i], x[i], 1e-5);
}

TEST(RealFft, MatchesTheDefinitionAlignedOrNot) {
  // The fast path needs 32-byte alignment; other buffers are copied
  // through. Both must give the DFT and leave the input as it was.
  const std::size_t n = 64;
  AlignedVector<float> aligned_in(n + 1);
  const auto x = noise(n, 12);
  for (std::size_t shift : {0u, 1u}) {
    std::copy(x.begin(), x.end(), aligned_in.begin() + static_cast<long>(shift));
    const std::span<const float> in(aligned_in.data() + shift, n);
    AlignedVector<std::complex<float>> out(n / 2 + 2);
    RealFft fft(n);
    fft.forward(in, std::span(out.data() + shift, n / 2 + 1));
    for (std::size_t k = 0; k <= n / 2; ++k) {
      std::complex<double> ref{};
      for (std::size_t t = 0; t < n; ++t) ref += double(x[t]) * std::polar(1.0, -2 * std::numbers::pi * double(k * t) / double(n));
      ASSERT_NEAR(out[k + shift].real(), ref.real(), 1e-4) << "bin " << k << " shift " << shift;
      ASSERT_NEAR(out[k + shift].imag(), ref.imag(), 1e-4) << "bin " << k << " shift " << shift;
    }
    for (std::size_t t = 0; t < n; ++t) ASSERT_EQ(in[t], x[t]) << "the forward transform wrote its input";
  }
}

namespace {
/// Runs x (left ear) and x2 (right ear) through one convolver and a bus.
void run(BinauralConvolver& conv, BinauralBus& bus, const std::vector<float>& xl, const std::vector<float>& xr,
         std::vector<float>& yl, std::vector<float>& yr, std::size_t blk) {
  const std::size_t B = conv.block();
  bus.clear();
  conv.process(std::span(xl).subspan(blk * B, B), std::span(xr).subspan(blk * B, B), bus);
  bus.mix_into(std::span(yl).subspan(blk * B, B), std::span(yr).subspan(blk * B, B));
}
}  // namespace

TEST(BinauralConvolver, EqualsDirectConvolution) {
  for (std::size_t block : {32u, 128u}) {
    const auto hl = noise(558, 2), hr = noise(300, 3);  // lengths not multiples of the block
    const auto xl = noise(block * 20, 4), xr = noise(block * 20, 14);  // each ear its own input
    BinauralConvolver conv(block, 558);
    BinauralBus bus(block);
    conv.set_filters(hl, hr, bus.fft());
    std::vector<float> yl(xl.size()), yr(xl.size());
    for (std::size_t b = 0; b < 20; ++b) run(conv, bus, xl, xr, yl, yr, b);
    const auto el = direct_convolution(xl, hl), er = direct_convolution(xr, hr);
    for (std::size_t i = 0; i < xl.size(); ++i) {
      ASSERT_NEAR(yl[i], el[i], 2e-4 * (1 + std::abs(el[i]))) << "block " << block << " sample " << i;
      ASSERT_NEAR(yr[i], er[i], 2e-4 * (1 + std::abs(er[i])));
    }
  }
}

TEST(BinauralConvolver, FilterChangeCrossfadesOverOneBlock) {
  const std::size_t B = 64;
  const auto a = noise(200, 5), b = noise(200, 6), x = noise(B * 10, 7);
  BinauralConvolver conv(B, 200);
  BinauralBus bus(B);
  conv.set_filters(a, a, bus.fft());
  std::vector<float> yl(x.size()), yr(x.size());
  for (std::size_t blk = 0; blk < 10; ++blk) {
    if (blk == 5) conv.set_filters(b, b, bus.fft());
    run(conv, bus, x, x, yl, yr, blk);
  }
  const auto ya = direct_convolution(x, a), yb = direct_convolution(x, b);
  for (std::size_t i = 0; i < x.size(); ++i) {
    double expect = ya[i];
    if (i >= 5 * B && i < 6 * B) {
      const double w = double(i - 5 * B + 1) / B;
      expect = (1 - w) * ya[i] + w * yb[i];
    } else if (i >= 6 * B) {
      expect = yb[i];
    }
    ASSERT_NEAR(yl[i], expect, 2e-4 * (1 + std::abs(expect))) << "sample " << i;
  }
}

TEST(BinauralBus, SumsSourcesSteadyAndCrossfading) {
  // Two sources through one bus: the sum of their convolutions, also in the
  // block where one of them crossfades to new filters and the other does not.
  const std::size_t B = 32, blocks = 12;
  const auto a = noise(90, 15), b = noise(70, 16), c = noise(90, 17);
  const auto x1 = noise(B * blocks, 18), x2 = noise(B * blocks, 19);
  BinauralBus bus(B);
  BinauralConvolver one(B, 90), two(B, 90);
  one.set_filters(a, b, bus.fft());
  two.set_filters(b, a, bus.fft());
  std::vector<float> yl(x1.size(), 0.0f), yr(x1.size(), 0.0f);
  for (std::size_t blk = 0; blk < blocks; ++blk) {
    if (blk == 6) one.set_filters(c, c, bus.fft());
    bus.clear();
    one.process(std::span(x1).subspan(blk * B, B), std::span(x1).subspan(blk * B, B), bus);
    two.process(std::span(x2).subspan(blk * B, B), std::span(x2).subspan(blk * B, B), bus);
    bus.mix_into(std::span(yl).subspan(blk * B, B), std::span(yr).subspan(blk * B, B));
  }
  const auto la = direct_convolution(x1, a), lc = direct_convolution(x1, c), lb2 = direct_convolution(x2, b);
  for (std::size_t i = 0; i < x1.size(); ++i) {
    double w = i < 6 * B ? 0.0 : i >= 7 * B ? 1.0 : double(i - 6 * B + 1) / B;
    const double expect = (1 - w) * la[i] + w * lc[i] + lb2[i];
    ASSERT_NEAR(yl[i], expect, 3e-4 * (1 + std::abs(expect))) << "sample " << i;
  }
}

TEST(FractionalDelay, IntegerDelayIsExact) {
  FractionalDelay d(32, 100);
  const auto x = noise(320, 8);
  std::vector<float> y(x.size());
  for (std::size_t b = 0; b < x.size(); b += 32) d.process(std::span(x).subspan(b, 32), std::span(y).subspan(b, 32), 17.0);
  for (std::size_t i = 17; i < x.size(); ++i) ASSERT_FLOAT_EQ(y[i], x[i - 17]);
}

TEST(FractionalDelay, FractionalDelayOfASine) {
  // 1 kHz at 48 kHz delayed by 10.37 samples: error well below -60 dB.
  const double f = 1000.0 / 48000.0, d = 10.37;
  std::vector<float> x(4800), y(4800);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(std::sin(2 * std::numbers::pi * f * static_cast<double>(i)));
  FractionalDelay line(48, 64);
  for (std::size_t b = 0; b < x.size(); b += 48) line.process(std::span(x).subspan(b, 48), std::span(y).subspan(b, 48), d);
  double err = 0;
  for (std::size_t i = 100; i < x.size(); ++i) {
    const double e = y[i] - std::sin(2 * std::numbers::pi * f * (double(i) - d));
    err = std::max(err, std::abs(e));
  }
  EXPECT_LT(err, 1e-3);
}

TEST(FractionalDelay, StillAndGlidingReadsAgree) {
  // A still delay takes the vectorised path (except where the ring wraps),
  // a moving one the per-sample path: across many blocks, with the ring
  // wrapping, the two must read the same samples.
  const std::size_t B = 48;
  FractionalDelay still(B, 300), glide(B, 300);
  const auto x = noise(B * 200, 20);
  std::vector<float> a(B), b(B);
  for (std::size_t blk = 0; blk < 200; ++blk) {
    const auto in = std::span(x).subspan(blk * B, B);
    still.write(in);
    glide.write(in);
    const double d = 37.3 + 0.01 * double(blk % 7);
    still.read(a, d, d);
    glide.read(b, d, d + 1e-9);  // moves by less than a kernel phase
    for (std::size_t i = 0; i < B; ++i) ASSERT_NEAR(a[i], b[i], 1e-5) << "block " << blk << " sample " << i;
  }
}

TEST(FractionalDelay, FlatToSixteenKilohertzAtEveryFraction) {
  // A fractional read must not low-pass: one ear at a half-sample fraction
  // and the other at a whole one would otherwise change the rendered ILD.
  for (double frac : {0.0, 0.25, 0.5, 0.73}) {
    for (double hz : {1000.0, 8000.0, 16000.0}) {
      const double f = hz / 48000.0, d = 20.0 + frac;
      std::vector<float> x(9600), y(9600);
      for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(std::sin(2 * std::numbers::pi * f * double(i)));
      FractionalDelay line(64, 64);
      for (std::size_t b = 0; b < x.size(); b += 64) line.process(std::span(x).subspan(b, 64), std::span(y).subspan(b, 64), d);
      double ex = 0, ey = 0;
      for (std::size_t i = 200; i < x.size(); ++i) ex += double(x[i]) * x[i], ey += double(y[i]) * y[i];
      EXPECT_NEAR(10 * std::log10(ey / ex), 0.0, 0.1) << hz << " Hz, fraction " << frac;
    }
  }
}

TEST(DspUnits, NoHeapAllocationPerBlock) {
  const std::size_t B = 128;
  BinauralConvolver conv(B, 558);
  BinauralBus bus(B);
  FractionalDelay delay(B, 2000);
  const auto h1 = noise(558, 9), h2 = noise(558, 10), x = noise(B, 11);
  std::vector<float> l(B), r(B), tl(B), tr(B);
  conv.set_filters(h1, h1, bus.fft());
  earshot::testing::AllocationProbe probe;
  for (int blk = 0; blk < 200; ++blk) {
    conv.set_filters(blk % 2 ? h1 : h2, blk % 2 ? h2 : h1, bus.fft());  // a moving source: new filters every block
    delay.write(x);
    delay.read(tl, 40.0 + 0.3 * blk, 40.3 + 0.3 * blk);
    delay.read(tr, 50.0, 50.0);
    bus.clear();
    conv.process(tl, tr, bus);
    bus.mix_into(l, r);
  }
  EXPECT_EQ(probe.count(), 0u);
}

TEST(DspUnits, TheAllocationProbeSeesAllocations) {
  static int* volatile keep = nullptr;  // volatile: the allocation cannot be elided
  earshot::testing::AllocationProbe probe;
  keep = new int[10];
  delete[] keep;
  EXPECT_GE(probe.count(), 1u);
}

TEST(DspUnits, TheProbeSeesALock) {
  std::mutex m;
  earshot::testing::AllocationProbe probe;
  { const std::lock_guard hold(m); }
  EXPECT_GE(probe.lock_count(), 1u);
}

namespace {
/// Gain in dB that `air` gives a sine of `hz` (after it settles).
double air_gain_db(earshot::audio::AirAbsorption& air, double hz) {
  std::vector<float> x(4800);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(std::sin(2 * std::numbers::pi * hz * double(i) / 48000.0));
  std::vector<float> y = x;
  for (std::size_t b = 0; b < y.size(); b += 48) air.process(std::span(y).subspan(b, 48));
  double ex = 0, ey = 0;
  for (std::size_t i = 960; i < x.size(); ++i) ex += double(x[i]) * x[i], ey += double(y[i]) * y[i];
  return 10 * std::log10(ey / ex);
}
}  // namespace

TEST(AirAbsorption, HighsFallWithDistanceAsOpenAlSays) {
  using earshot::audio::AirAbsorption;
  AirAbsorption air(48000.0);
  air.update(100.0, 0.0);  // factor 0: untouched
  EXPECT_NEAR(air_gain_db(air, 12000), 0.0, 1e-6);
  air.update(100.0, 1.0);  // 0.99426^100: -5.0 dB in the high band
  const double hf = 20 * std::log10(std::pow(AirAbsorption::kGainPerMetre, 100.0));
  EXPECT_NEAR(hf, -5.0, 0.05);
  EXPECT_NEAR(air_gain_db(air, 16000), hf, 0.5);
  EXPECT_NEAR(air_gain_db(air, 100), 0.0, 0.1);
  air.update(400.0, 1.0);  // -20 dB in the high band
  EXPECT_LT(air_gain_db(air, 16000), 3 * hf);
  EXPECT_NEAR(air_gain_db(air, 100), 0.0, 0.1);
  air.update(NAN, 1.0);  // bad numbers stop here
  EXPECT_NEAR(air_gain_db(air, 16000), 0.0, 0.01);
}
