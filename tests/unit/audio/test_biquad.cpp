// The biquad designs against their analytic responses. The expectations are
// computed here, not taken from the code under test:
//  - a 2nd-order Butterworth section is the RBJ cookbook's LPF/HPF with
//    Q = 1/sqrt(2), coefficient for coefficient; each section of a higher
//    order is the cookbook's with the Butterworth pole pair's Q;
//  - through the bilinear transform pre-warped at fc, an order-n Butterworth
//    has |H|^2 = 1 / (1 + W^2n) (low-pass) and W^2n / (1 + W^2n) (high-pass),
//    W = tan(pi f / fs) / tan(pi fc / fs): -3.01 dB at the corner;
//  - the 4th-order high shelf has |H|^2 = (1 + g^2 W^8) / (1 + W^8) and
//    exactly the asked gain at f.
// Magnitudes are measured by running sines through Biquad::tick (the filter
// itself), and compared with magnitude(). Every design the reverbs and their
// measurements use is stable over the parameter range they use it in.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <span>
#include <vector>

#include "earshot/audio/biquad.hpp"
#include "earshot/audio/decay_filter.hpp"

using namespace earshot::audio;

namespace {

constexpr double kPi = std::numbers::pi;

double warp_ratio(double f, double fc, double fs) { return std::tan(kPi * f / fs) / std::tan(kPi * fc / fs); }
double butterworth_lp(double f, double fc, double fs, int order) {
  return 1.0 / std::sqrt(1.0 + std::pow(warp_ratio(f, fc, fs), 2.0 * order));
}
double butterworth_hp(double f, double fc, double fs, int order) {
  const double w2n = std::pow(warp_ratio(f, fc, fs), 2.0 * order);
  return std::sqrt(w2n / (1.0 + w2n));
}

/// The RBJ Audio EQ Cookbook's low-pass / high-pass, normalised by a0.
BiquadCoeffs rbj(bool high, double fc, double q, double fs) {
  const double w0 = 2 * kPi * fc / fs, c = std::cos(w0), alpha = std::sin(w0) / (2 * q);
  const double a0 = 1 + alpha;
  BiquadCoeffs k;
  k.b0 = (high ? (1 + c) / 2 : (1 - c) / 2) / a0;
  k.b1 = (high ? -(1 + c) : (1 - c)) / a0;
  k.b2 = k.b0;
  k.a1 = -2 * c / a0;
  k.a2 = (1 - alpha) / a0;
  return k;
}

/// Q of the Butterworth pole pairs of order 2N, from the pole angles.
std::vector<double> butterworth_q(int sections) {
  std::vector<double> q;
  const int n = 2 * sections;
  for (int k = 0; k < sections; ++k) q.push_back(1.0 / (2.0 * std::sin(kPi * (2 * k + 1) / (2.0 * n))));
  return q;
}

/// Steady-state gain of the cascade at integer frequency f (Hz): a sine
/// through Biquad::tick, settled for 0.5 s, then correlated over 1 s (a
/// whole number of periods) with sine and cosine.
double measured_gain(std::span<const BiquadCoeffs> cascade, double f, double fs) {
  std::vector<Biquad> filters(cascade.begin(), cascade.end());
  const auto settle = static_cast<long>(fs / 2), length = static_cast<long>(fs);
  double s = 0, c = 0;
  for (long n = 0; n < settle + length; ++n) {
    const double phase = 2 * kPi * f * static_cast<double>(n) / fs;
    double y = std::sin(phase);
    for (auto& b : filters) y = b.tick(y);
    if (n >= settle) s += y * std::sin(phase), c += y * std::cos(phase);
  }
  return 2.0 * std::hypot(s, c) / static_cast<double>(length);
}

/// Poles of 1 + a1 z^-1 + a2 z^-2 strictly inside the unit circle (the
/// stability triangle: |a2| < 1 and |a1| < 1 + a2).
bool stable(const BiquadCoeffs& c) { return std::abs(c.a2) < 1.0 && std::abs(c.a1) < 1.0 + c.a2; }

double db(double x) { return 20.0 * std::log10(x); }

}  // namespace

TEST(Biquad, SecondOrderButterworthIsTheCookbookFilter) {
  for (double fs : {44100.0, 48000.0, 96000.0})
    for (double fc : {30.0, 500.0, 5000.0, 18000.0}) {
      SCOPED_TRACE(testing::Message() << "fs " << fs << " fc " << fc);
      for (bool high : {false, true}) {
        const auto k = high ? butterworth_highpass<1>(fc, fs)[0] : butterworth_lowpass<1>(fc, fs)[0];
        const auto r = rbj(high, fc, 1.0 / std::sqrt(2.0), fs);
        EXPECT_NEAR(k.b0, r.b0, 1e-12);
        EXPECT_NEAR(k.b1, r.b1, 1e-12);
        EXPECT_NEAR(k.b2, r.b2, 1e-12);
        EXPECT_NEAR(k.a1, r.a1, 1e-12);
        EXPECT_NEAR(k.a2, r.a2, 1e-12);
      }
    }
}

TEST(Biquad, HigherOrdersAreCookbookSectionsWithTheButterworthQs) {
  constexpr double fs = 48000.0, fc = 1000.0;
  const auto q = butterworth_q(4);  // 8th order: Q 0.51, 0.60, 0.90, 2.56
  const auto lp = butterworth_lowpass<4>(fc, fs);
  const auto hp = butterworth_highpass<4>(fc, fs);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto rl = rbj(false, fc, q[i], fs), rh = rbj(true, fc, q[i], fs);
    EXPECT_NEAR(lp[i].a1, rl.a1, 1e-12) << i;
    EXPECT_NEAR(lp[i].a2, rl.a2, 1e-12) << i;
    EXPECT_NEAR(lp[i].b0, rl.b0, 1e-12) << i;
    EXPECT_NEAR(hp[i].b0, rh.b0, 1e-12) << i;
    EXPECT_NEAR(hp[i].b1, rh.b1, 1e-12) << i;
  }
}

template <std::size_t N>
void check_butterworth(double fc, double fs) {
  constexpr int order = 2 * static_cast<int>(N);
  SCOPED_TRACE(testing::Message() << "order " << order << " fc " << fc << " fs " << fs);
  const auto lp = butterworth_lowpass<N>(fc, fs);
  const auto hp = butterworth_highpass<N>(fc, fs);
  // The corner (rounded to a whole Hz for the measurement), an octave and two
  // below (pass band of the low-pass), an octave and two above (its stop band).
  for (double f : {std::round(fc), std::round(fc / 2), std::round(fc / 4), std::round(fc * 2), std::round(fc * 4)}) {
    if (f >= fs / 2) continue;
    SCOPED_TRACE(testing::Message() << f << " Hz");
    const double want_lp = butterworth_lp(f, fc, fs, order), want_hp = butterworth_hp(f, fc, fs, order);
    EXPECT_NEAR(measured_gain(lp, f, fs), want_lp, 1e-4 * want_lp + 1e-7);
    EXPECT_NEAR(measured_gain(hp, f, fs), want_hp, 1e-4 * want_hp + 1e-7);
    EXPECT_NEAR(magnitude(lp, f, fs), want_lp, 1e-9 * want_lp + 1e-12);
    EXPECT_NEAR(magnitude(hp, f, fs), want_hp, 1e-9 * want_hp + 1e-12);
    // Power complementary: what the low-pass loses the high-pass keeps.
    EXPECT_NEAR(want_lp * want_lp + want_hp * want_hp, 1.0, 1e-12);
  }
  EXPECT_NEAR(db(magnitude(lp, fc, fs)), -3.0103, 1e-3);
  EXPECT_NEAR(db(magnitude(hp, fc, fs)), -3.0103, 1e-3);
  // Stop bands fall 6 dB per octave per order, as the analytic curve does:
  // two octaves from the corner, at least 12 * order - 1 dB down (pre-warping
  // only steepens the low-pass towards Nyquist).
  EXPECT_LT(db(magnitude(lp, fc * 4, fs)), -(12.0 * order - 1.0));
  EXPECT_LT(db(magnitude(hp, fc / 4, fs)), -(12.0 * order - 1.0));
  EXPECT_NEAR(magnitude(lp, 0.0, fs), 1.0, 1e-12);  // DC passes whole
  EXPECT_NEAR(magnitude(hp, fs / 2, fs), 1.0, 1e-9);
  EXPECT_LT(magnitude(hp, 0.0, fs), 1e-12);
  EXPECT_LT(magnitude(lp, fs / 2, fs), 1e-9);
}

TEST(Biquad, ButterworthMagnitudesMatchTheAnalyticCurve) {
  for (double fs : {44100.0, 48000.0}) {
    for (double fc : {250.0, 1000.0, 4000.0}) {
      check_butterworth<1>(fc, fs);
      check_butterworth<2>(fc, fs);
      check_butterworth<4>(fc, fs);
    }
    check_butterworth<3>(1500.0, fs);
  }
}

TEST(Biquad, HighShelfHasTheAskedGainAtFAndIsFlatBelow) {
  constexpr double fs = 48000.0;
  for (double f : {1000.0, 5000.0, 15000.0})
    for (double gain : {0.9, 0.5, 0.1, 0.05, 1.5}) {  // reachable at f = 2.2 fc: >= 0.043
      SCOPED_TRACE(testing::Message() << "f " << f << " gain " << gain);
      const double fc = f / 2.2;  // as the reverbs use it
      const auto shelf = high_shelf4(fc, f, gain, fs);
      EXPECT_NEAR(magnitude(shelf, f, fs), gain, 1e-9 * gain);
      EXPECT_NEAR(measured_gain(shelf, f, fs), gain, 1e-4 * gain);
      // The far gain g from the analytic curve at f, then the curve elsewhere.
      const double w8 = std::pow(warp_ratio(f, fc, fs), 8.0);
      const double g2 = (gain * gain * (1 + w8) - 1) / w8;
      for (double probe : {fc / 4, fc / 2, fc, 2 * fc, 20000.0}) {
        const double v8 = std::pow(warp_ratio(probe, fc, fs), 8.0);
        const double want = std::sqrt((1 + g2 * v8) / (1 + v8));
        EXPECT_NEAR(magnitude(shelf, probe, fs), want, 1e-9) << probe << " Hz";
      }
      // The header's promise for a cut: within 0.02 dB of 1 an octave below the corner.
      if (gain <= 1.0) {
        EXPECT_LT(std::abs(db(magnitude(shelf, fc / 2, fs))), 0.02);
      }
      EXPECT_NEAR(magnitude(shelf, 0.0, fs), 1.0, 1e-12);
    }
}

TEST(Biquad, AShelfDeeperThanReachableIsClampedToTheDeepest) {
  // One octave above the corner the shelf cannot go below ~1/sqrt(1 + 2^8).
  constexpr double fs = 48000.0, fc = 1000.0, f = 2000.0;
  const double w8 = std::pow(warp_ratio(f, fc, fs), 8.0);
  const auto shelf = high_shelf4(fc, f, 1e-6, fs);
  EXPECT_NEAR(magnitude(shelf, f, fs), std::sqrt(1.0 / (1.0 + w8)), 1e-4);
  for (const auto& s : shelf) EXPECT_TRUE(stable(s));
}

TEST(Biquad, TheDesignsAreStableWhereverTheReverbsAndMeasurementsUseThem) {
  for (double fs : {8000.0, 22050.0, 44100.0, 48000.0, 96000.0, 192000.0}) {
    SCOPED_TRACE(fs);
    // Band edges of the reverb measurements: octave and third-octave bands
    // from 20 Hz to 0.45 fs.
    for (double fc = 20.0; fc < 0.45 * fs; fc *= 1.25) {
      for (const auto& s : butterworth_lowpass<4>(fc, fs)) ASSERT_TRUE(stable(s)) << "low-pass " << fc;
      for (const auto& s : butterworth_highpass<4>(fc, fs)) ASSERT_TRUE(stable(s)) << "high-pass " << fc;
      for (const auto& s : butterworth_lowpass<2>(fc, fs)) ASSERT_TRUE(stable(s)) << "low-pass " << fc;
      for (const auto& s : butterworth_highpass<2>(fc, fs)) ASSERT_TRUE(stable(s)) << "high-pass " << fc;
    }
    // The reverbs' input shelves and loop absorption: f_hf from 1 kHz to
    // min(20 kHz, 0.45 fs), gains from 1e-6 up (RoomParams::gain_hf), and
    // the decay filter's shelves over the whole EFX range of decay times and
    // ratios (a ratio above 1 asks for a shelf that boosts).
    for (double f_hf : {1000.0, 2500.0, 5000.0, 10000.0, 20000.0}) {
      const double f = std::min(f_hf, 0.45 * fs);
      for (double gain : {1e-6, 1e-3, 0.1, 0.5, 0.8913, 1.0})
        for (const auto& s : high_shelf4(f / 2.2, f, gain, fs)) ASSERT_TRUE(stable(s)) << f << " Hz gain " << gain;
      for (double loop : {200.0, 1500.0, 6000.0})
        for (double t60 : {0.1, 1.49, 20.0})
          for (double ratio : {0.1, 0.83, 2.0}) {
            const DecayFilter d = design_decay_filter(loop, t60, ratio, f, fs);
            ASSERT_LT(d.gain, 1.0);
            for (const auto& s : d.shelf) ASSERT_TRUE(stable(s)) << "decay " << t60 << " ratio " << ratio;
            // The loop loses energy at every frequency: it cannot ring up.
            for (double probe : {50.0, 700.0, f, 0.49 * fs})
              ASSERT_LT(d.gain * magnitude(d.shelf, probe, fs), 1.0) << probe << " Hz, t60 " << t60;
          }
    }
  }
}

TEST(Biquad, AStableSectionsImpulseResponseDiesAway) {
  // The sharpest section in use: the 8th-order low-pass's Q 2.56 pair at 20 Hz.
  const auto lp = butterworth_lowpass<4>(20.0, 48000.0);
  Biquad b(lp[3]);
  double tail = 0.0;
  for (int n = 0; n < 96000; ++n) {
    const double y = b.tick(n == 0 ? 1.0 : 0.0);
    if (n >= 72000) tail = std::max(tail, std::abs(y));
  }
  EXPECT_LT(tail, 1e-6);
  // process() is tick() on floats, in place.
  Biquad x(lp[0]), y(lp[0]);
  std::vector<float> io(64, 0.0f);
  io[0] = 1.0f;
  x.process(io);
  for (std::size_t n = 0; n < io.size(); ++n) EXPECT_EQ(io[n], static_cast<float>(y.tick(n == 0 ? 1.0 : 0.0))) << n;
}

TEST(Biquad, GroupDelayOfKnownSections) {
  // z^-2: two samples at every frequency; a cascade adds its sections' delays.
  const BiquadCoeffs delay2{0, 0, 1, 0, 0};
  for (double f : {100.0, 5000.0, 20000.0}) EXPECT_NEAR(group_delay(std::span(&delay2, 1), f, 48000.0), 2.0, 1e-6);
  const auto lp = butterworth_lowpass<2>(1000.0, 48000.0);
  double sum = 0;
  for (const auto& s : lp) sum += group_delay(std::span(&s, 1), 300.0, 48000.0);
  EXPECT_NEAR(group_delay(lp, 300.0, 48000.0), sum, 1e-9);
  // A 2nd-order Butterworth low-pass near DC: the analog prototype's sqrt(2)
  // (in 1/fc units) times the bilinear map's slope at DC, k / 2 with
  // k = 1 / tan(pi fc / fs): ~ sqrt(2) fs / (2 pi fc) = 108 samples at 100 Hz.
  const double fc = 100.0, fs = 48000.0;
  const auto one = butterworth_lowpass<1>(fc, fs);
  EXPECT_NEAR(group_delay(one, 1.0, fs), std::sqrt(2.0) / (2.0 * std::tan(kPi * fc / fs)), 0.05);
}
