// IrResampler against the continuous signal it samples: tones up to 18 kHz
// come out as the same tones at the new rate (error energy 60 dB or more
// below the signal), DC keeps unit gain, an impulse keeps its time, and the
// output length is the one libmysofa's resampler gives. Rates up and down,
// by small and large ratios.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "earshot/hrtf/ir_resampler.hpp"

using earshot::hrtf::IrResampler;

namespace {

struct Rates {
  double from, to;
};
const Rates kRates[] = {{44100, 48000}, {48000, 44100}, {44100, 96000}, {96000, 48000},
                        {48000, 96000}, {96000, 44100}, {32000, 48000}, {48000, 48000.5}};

/// A sum of tones, each below 90% of the lower rate's Nyquist frequency.
double tones(double t, double nyquist_low) {
  double v = 0.0;
  for (const double f : {200.0, 1000.0, 5000.0, 12000.0, 18000.0})
    if (f < 0.9 * nyquist_low) v += std::sin(2.0 * std::numbers::pi * f * t + f * 1e-3);
  return v;
}

}  // namespace

TEST(IrResampler, TonesBelowTheCutOffComeOutUnchanged) {
  for (const auto& r : kRates) {
    SCOPED_TRACE(std::to_string(r.from) + " -> " + std::to_string(r.to));
    const double nyq = 0.5 * std::min(r.from, r.to);
    const std::size_t n = 2048;
    std::vector<float> in(n);
    for (std::size_t i = 0; i < n; ++i) in[i] = static_cast<float>(tones(static_cast<double>(i) / r.from, nyq));
    const IrResampler rs(r.from, r.to, n);
    std::vector<float> out(rs.out_length());
    rs.process(in, out);
    // Away from the ends (where the input stops) the output is the tones.
    double err = 0.0, sig = 0.0;
    for (std::size_t k = 0; k < out.size(); ++k) {
      const double t = static_cast<double>(k) / r.to;
      if (t < 200.0 / std::min(r.from, r.to) || t > (n - 200.0) / r.from) continue;
      const double want = tones(t, nyq);
      err += (out[k] - want) * (out[k] - want);
      sig += want * want;
    }
    ASSERT_GT(sig, 0.0);
    EXPECT_LT(10.0 * std::log10(err / sig), -60.0);
  }
}

TEST(IrResampler, DcKeepsUnitGain) {
  const IrResampler rs(44100, 48000, 512);
  std::vector<float> in(512, 1.0f), out(rs.out_length());
  rs.process(in, out);
  for (std::size_t k = 60; k + 60 < out.size(); ++k) EXPECT_NEAR(out[k], 1.0, 1e-5) << k;
}

TEST(IrResampler, AnImpulseKeepsItsTimeAndItsLevel) {
  for (const auto& r : kRates) {
    SCOPED_TRACE(std::to_string(r.from) + " -> " + std::to_string(r.to));
    const std::size_t n = 512, at = 100;
    std::vector<float> in(n, 0.0f);
    in[at] = 1.0f;
    const IrResampler rs(r.from, r.to, n);
    std::vector<float> out(rs.out_length());
    rs.process(in, out);
    // Zero phase: the energy centroid sits where the impulse was in time.
    double e = 0.0, et = 0.0, sum = 0.0;
    for (std::size_t k = 0; k < out.size(); ++k) {
      e += double(out[k]) * out[k];
      et += double(out[k]) * out[k] * static_cast<double>(k);
      sum += out[k];
    }
    EXPECT_NEAR(et / e / r.to, static_cast<double>(at) / r.from, 0.05 / r.to);
    // The area (DC gain times the sample spacing) is kept: sum scales with the rate.
    EXPECT_NEAR(sum, r.to / r.from, 1e-3 * r.to / r.from);
  }
}

TEST(IrResampler, OutputLengthIsTheLengthScaledUp) {
  EXPECT_EQ(IrResampler(44100, 48000, 512).out_length(), 558u);
  EXPECT_EQ(IrResampler(48000, 44100, 512).out_length(), 471u);
  EXPECT_EQ(IrResampler(48000, 96000, 256).out_length(), 512u);
  EXPECT_EQ(IrResampler(96000, 48000, 8192).out_length(), 4096u);
  EXPECT_EQ(IrResampler(44100, 48000, 32).out_length(), 35u);
  EXPECT_THROW(IrResampler(0.0, 48000, 32), std::invalid_argument);
  const IrResampler rs(44100, 48000, 32);
  std::vector<float> wrong(31), out(rs.out_length());
  EXPECT_THROW(rs.process(wrong, out), std::invalid_argument);
}
