#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "earshot/audio/air_absorption.hpp"
#include "earshot/audio/aligned_vector.hpp"
#include "earshot/audio/direction_bank.hpp"
#include "earshot/audio/fractional_delay.hpp"
#include "earshot/audio/simd_kernels.hpp"
#include "earshot/audio/spectral_kernels.hpp"
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

TEST(RealFft, PlanarForwardMatchesTheDefinition) {
  // forward_planar: av_tx's half-size complex FFT and the real_spectrum
  // kernel for powers of two, KissFFT for the rest; odd bins negated on
  // request; the padding bins untouched; aligned input or not.
  for (const std::size_t n : {std::size_t{256}, std::size_t{64}, std::size_t{200}}) {
    const std::size_t bins = n / 2 + 1, S = (bins + 7) / 8 * 8;
    const auto x = noise(n, static_cast<unsigned>(40 + n));
    AlignedVector<float> buffer(n + 1);
    RealFft fft(n);
    for (const std::size_t shift : {0u, 1u})
      for (const bool negated : {false, true}) {
        std::copy(x.begin(), x.end(), buffer.begin() + static_cast<long>(shift));
        std::vector<float> out(2 * S, 7.0f);
        fft.forward_planar(std::span<const float>(buffer.data() + shift, n), out.data(), S, negated);
        for (std::size_t k = 0; k < S; ++k) {
          if (k >= bins) {
            ASSERT_EQ(out[k], 7.0f) << "padding written, n " << n;
            ASSERT_EQ(out[S + k], 7.0f) << "padding written, n " << n;
            continue;
          }
          std::complex<double> ref{};
          for (std::size_t t = 0; t < n; ++t)
            ref += double(x[t]) * std::polar(1.0, -2 * std::numbers::pi * double(k * t) / double(n));
          if (negated && k % 2) ref = -ref;
          ASSERT_NEAR(out[k], ref.real(), 1e-4) << "n " << n << " bin " << k << " shift " << shift << " negated " << negated;
          ASSERT_NEAR(out[S + k], ref.imag(), 1e-4) << "n " << n << " bin " << k << " shift " << shift << " negated " << negated;
        }
      }
  }
}

namespace {
const std::shared_ptr<const earshot::hrtf::HrtfSet>& kemar48() {
  static const auto set = std::make_shared<const earshot::hrtf::HrtfSet>(earshot::hrtf::HrtfSet::load_default(48000.0));
  return set;
}

std::vector<float> filter_of(std::size_t m, std::size_t ear) {
  const auto f = kemar48()->filter(m, static_cast<earshot::hrtf::Ear>(ear));
  return {f.begin(), f.end()};
}

/// x with block b's gain curve applied, as add() applies it (computed independently).
std::vector<float> shaped(const std::vector<float>& x, std::size_t B, const std::vector<DirectionBank::GainCurve>& g) {
  std::vector<float> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const DirectionBank::GainCurve c = g[i / B];
    const double r = (double(i % B) + 1.0) / double(B);
    y[i] = static_cast<float>((c.c0 + c.c1 * r + c.c2 * r * r) * x[i]);
  }
  return y;
}
}  // namespace

TEST(DirectionBank, EqualsDirectConvolutionWithTheMeasuredFilters) {
  // Two signals panned into two measurements (one only in the right ear),
  // with steady and ramping gains: the output is the sum of the ramped
  // signals convolved with the measured onset-free filters.
  for (std::size_t B : {32u, 128u}) {
    DirectionBank bank(std::make_shared<const HrtfSpectra>(*kemar48(), B));
    const std::size_t blocks = 30, m1 = 100, m2 = 401;
    const auto x1 = noise(B * blocks, 4), x2 = noise(B * blocks, 14);
    using Curve = DirectionBank::GainCurve;
    std::vector<Curve> r1(blocks, Curve::ramp(0.5f, 0.5f)), r2(blocks);
    for (std::size_t b = 10; b < blocks; ++b) r2[b] = b == 10 ? Curve::ramp(0.0f, 0.8f) : Curve::ramp(0.8f, 0.8f);
    r1[20] = Curve::ramp(0.5f, 0.1f);
    r1[21] = {0.1f, 0.3f, -0.25f};  // a quadratic curve, ending at 0.15
    for (std::size_t b = 22; b < blocks; ++b) r1[b] = Curve::ramp(0.15f, 0.15f);
    std::vector<float> yl(x1.size(), 0.0f), yr(x1.size(), 0.0f);
    for (std::size_t b = 0; b < blocks; ++b) {
      const auto in1 = std::span(x1).subspan(b * B, B), in2 = std::span(x2).subspan(b * B, B);
      bank.add(m1, 0, in1, r1[b]);
      bank.add(m1, 1, in1, r1[b]);
      if (b >= 10) bank.add(m2, 1, in2, r2[b]);
      bank.process(std::span(yl).subspan(b * B, B), std::span(yr).subspan(b * B, B));
    }
    const auto a = shaped(x1, B, r1), c = shaped(x2, B, r2);
    const auto el = direct_convolution(a, filter_of(m1, 0));
    const auto er1 = direct_convolution(a, filter_of(m1, 1)), er2 = direct_convolution(c, filter_of(m2, 1));
    // The filters' tails are kept as scaled 16-bit integers (HrtfSpectra),
    // so this is exact to their rounding: the error is measured as energy.
    double err = 0, ref = 0;
    for (std::size_t i = 0; i < x1.size(); ++i) {
      const double r = er1[i] + er2[i];
      err += (yl[i] - el[i]) * (yl[i] - el[i]) + (yr[i] - r) * (yr[i] - r);
      ref += el[i] * el[i] + r * r;
    }
    const double db = 10 * std::log10(err / ref);
    std::printf("block %zu: error %.1f dB\n", B, db);
    EXPECT_LT(db, -90.0) << "block " << B;
  }
}

TEST(DirectionBank, ALaneStopsWithItsInputAndItsTailRingsOut) {
  const std::size_t B = 64;
  const auto spectra = std::make_shared<const HrtfSpectra>(*kemar48(), B);
  DirectionBank bank(spectra);
  const auto x = noise(B, 21);
  std::vector<float> l(B), r(B);
  bank.add(7, 0, x, DirectionBank::GainCurve::ramp(1.0f, 1.0f));
  bank.process(l, r);
  EXPECT_EQ(bank.lanes_run(), 1u);
  // One more block for the input's second half of the overlap-save window,
  // then the lane is idle while the tail (in the shared accumulators) plays
  // out over the filter's partitions.
  std::vector<std::size_t> runs;
  std::size_t ringing = 0;
  for (int blk = 0; blk < 20; ++blk) {
    std::fill(l.begin(), l.end(), 0.0f);
    bank.process(l, r);
    runs.push_back(bank.lanes_run());
    double e = 0;
    for (float v : l) e += double(v) * v;
    if (e > 0.0) ++ringing;
    for (float v : r) ASSERT_EQ(v, 0.0f) << "the right ear had no input";
  }
  EXPECT_EQ(runs[0], 1u);
  EXPECT_EQ(runs[1], 0u);
  EXPECT_EQ(ringing, spectra->partitions());  // B + 558 - 1 samples span partitions() + 1 blocks
  std::fill(l.begin(), l.end(), 1.0f);
  bank.process(l, r);
  for (float v : l) ASSERT_EQ(v, 1.0f);  // nothing left to add
}

namespace {
/// The instruction sets this build and CPU run: each kernel test runs on all of them.
std::vector<simd::Isa> runnable_isas() {
  std::vector<simd::Isa> v;
  for (const auto isa : {simd::Isa::portable, simd::Isa::avx2})
    if (simd::supported(isa)) v.push_back(isa);
  return v;
}
}  // namespace

TEST(SimdDispatch, ChosenOnceAndTheBestTheCpuRunsUnlessOverridden) {
  const simd::Kernels& k = simd::kernels();
  EXPECT_EQ(&k, &simd::kernels());
  EXPECT_TRUE(simd::supported(k.isa));
  EXPECT_EQ(&k, &simd::kernels(k.isa));
  const char* asked = std::getenv("EARSHOT_SIMD");
  if (asked == nullptr || *asked == '\0')
    EXPECT_EQ(k.isa, simd::supported(simd::Isa::avx2) ? simd::Isa::avx2 : simd::Isa::portable);
  else
    EXPECT_EQ(simd::name(k.isa), asked);
}

TEST(SimdDispatch, TheOverrideNamesAnInstructionSetTheCpuRuns) {
  EXPECT_TRUE(simd::supported(simd::Isa::portable));
  EXPECT_EQ(simd::choose("portable"), simd::Isa::portable);
  EXPECT_EQ(simd::choose(nullptr), simd::choose(""));
  if (simd::supported(simd::Isa::avx2)) {
    EXPECT_EQ(simd::choose("avx2"), simd::Isa::avx2);
    EXPECT_EQ(simd::choose(nullptr), simd::Isa::avx2);
    EXPECT_EQ(simd::kernels(simd::Isa::avx2).isa, simd::Isa::avx2);
  } else {
    EXPECT_THROW((void)simd::choose("avx2"), std::runtime_error);
    EXPECT_THROW((void)simd::kernels(simd::Isa::avx2), std::runtime_error);
  }
  EXPECT_EQ(simd::kernels(simd::Isa::portable).isa, simd::Isa::portable);
  try {
    (void)simd::choose("AVX512");
    ADD_FAILURE() << "an unknown instruction set was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("EARSHOT_SIMD=AVX512"), std::string::npos) << e.what();
  }
}

TEST(SpectralKernels, MultiplyAddOfScaledIntegersEqualsTheWidenedProduct) {
  const std::size_t S = 136;
  const auto x = noise(2 * S, 30), a0 = noise(2 * S, 32);
  std::mt19937 rng(31);
  std::uniform_int_distribution<int> q(-32767, 32767);
  std::vector<std::int16_t> h(2 * S);
  for (auto& v : h) v = static_cast<std::int16_t>(q(rng));
  const float scale = 3.0e-5f;
  for (const auto isa : runnable_isas()) {
    std::vector<float> acc = a0;
    simd::kernels(isa).multiply_add_scaled(x.data(), h.data(), scale, acc.data(), S);
    for (std::size_t k = 0; k < S; ++k) {
      const double re = double(scale) * h[k], im = double(scale) * h[S + k];
      ASSERT_NEAR(acc[k], a0[k] + x[k] * re - x[S + k] * im, 1e-6) << simd::name(isa) << " bin " << k;
      ASSERT_NEAR(acc[S + k], a0[S + k] + x[k] * im + x[S + k] * re, 1e-6) << simd::name(isa) << " bin " << k;
    }
  }
  // The named kernel runs the chosen set's.
  std::vector<float> named = a0, chosen = a0;
  kernels::multiply_add_scaled(x.data(), h.data(), scale, named.data(), S);
  simd::kernels().multiply_add_scaled(x.data(), h.data(), scale, chosen.data(), S);
  EXPECT_EQ(named, chosen);
}

TEST(SpectralKernels, MultiplyAddAccumulatesTheComplexProduct) {
  const std::size_t S = 136;
  const auto x = noise(2 * S, 33), h = noise(2 * S, 34), a0 = noise(2 * S, 35);
  for (const auto isa : runnable_isas()) {
    std::vector<float> acc = a0;
    simd::kernels(isa).multiply_add(x.data(), h.data(), acc.data(), S);
    for (std::size_t k = 0; k < S; ++k) {
      const std::complex<double> p = std::complex<double>(x[k], x[S + k]) * std::complex<double>(h[k], h[S + k]);
      ASSERT_NEAR(acc[k], a0[k] + p.real(), 1e-6) << simd::name(isa) << " bin " << k;
      ASSERT_NEAR(acc[S + k], a0[S + k] + p.imag(), 1e-6) << simd::name(isa) << " bin " << k;
    }
  }
}

TEST(SpectralKernels, AddShapedAddsTheSignalUnderTheGainCurve) {
  const std::size_t n = 61;  // not a multiple of eight: the vector loops' remainders run too
  const auto x = noise(n, 36), o0 = noise(n, 37);
  std::vector<float> r(n), r2(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = float(i + 1) / float(n), r2[i] = r[i] * r[i];
  const float c0 = 0.25f, c1 = 0.5f, c2 = -0.125f;
  for (const auto isa : runnable_isas()) {
    std::vector<float> out = o0;
    simd::kernels(isa).add_shaped(x.data(), c0, c1, c2, r.data(), r2.data(), out.data(), n);
    for (std::size_t i = 0; i < n; ++i) {
      const double gain = c0 + double(c1) * r[i] + double(c2) * r2[i];
      ASSERT_NEAR(out[i], o0[i] + gain * x[i], 1e-6) << simd::name(isa) << " sample " << i;
    }
  }
}

TEST(SpectralKernels, FirGlideIsBothFiltersCrossfadedAcrossTheBlock) {
  const std::size_t T = 64;
  const auto h0 = noise(T, 40), h1 = noise(T, 41);
  for (const std::size_t n : {std::size_t{128}, std::size_t{100}, std::size_t{7}}) {  // whole groups and remainders
    const auto line = noise(T - 1 + n, 42);
    const float* x = line.data() + T - 1;  // x[i - k] readable for k < T
    for (const auto isa : runnable_isas())
      for (const bool same : {false, true}) {
        const float* g1 = same ? h0.data() : h1.data();
        std::vector<float> y(n, 99.0f);
        simd::kernels(isa).fir_glide(h0.data(), g1, T, x, y.data(), n);
        for (std::size_t i = 0; i < n; ++i) {
          double a = 0.0, b = 0.0;
          for (std::size_t k = 0; k < T; ++k) {
            a += double(h0[k]) * x[static_cast<std::ptrdiff_t>(i) - static_cast<std::ptrdiff_t>(k)];
            b += double(g1[k]) * x[static_cast<std::ptrdiff_t>(i) - static_cast<std::ptrdiff_t>(k)];
          }
          const double r = double(i + 1) / double(n);
          ASSERT_NEAR(y[i], a + r * (b - a), 2e-5) << simd::name(isa) << " n " << n << " sample " << i
                                                    << (same ? " (one filter)" : "");
        }
      }
  }
}

TEST(SpectralKernels, LayoutChangesMoveEveryValueExactly) {
  const std::size_t n = 129, S = 136;  // 256-point spectra: 129 bins padded to 136
  const auto v = noise(2 * n, 38);
  std::vector<std::complex<float>> in(n);
  for (std::size_t k = 0; k < n; ++k) in[k] = {v[2 * k], v[2 * k + 1]};
  for (const auto isa : runnable_isas()) {
    const simd::Kernels& k = simd::kernels(isa);
    std::vector<float> planar(2 * S, 7.0f), negated(2 * S, 7.0f);
    k.to_planar(in.data(), n, planar.data(), S);
    k.to_planar_odd_negated(in.data(), n, negated.data(), S);
    for (std::size_t b = 0; b < S; ++b) {
      if (b < n) {
        const float sign = b % 2 ? -1.0f : 1.0f;
        ASSERT_EQ(planar[b], in[b].real()) << simd::name(isa) << " bin " << b;
        ASSERT_EQ(planar[S + b], in[b].imag()) << simd::name(isa) << " bin " << b;
        ASSERT_EQ(negated[b], sign * in[b].real()) << simd::name(isa) << " bin " << b;
        ASSERT_EQ(negated[S + b], sign * in[b].imag()) << simd::name(isa) << " bin " << b;
      } else {  // padding is left as it was
        ASSERT_EQ(planar[b], 7.0f);
        ASSERT_EQ(planar[S + b], 7.0f);
      }
    }
    std::vector<std::complex<float>> back(n);
    k.to_interleaved(planar.data(), S, back.data(), n);
    EXPECT_EQ(back, in) << simd::name(isa);
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

namespace {
/// The read's contract in double precision: out[i] is the input resampled
/// at (i - delay) through a 16-tap Kaiser-windowed sinc (beta 7) normalised
/// to unit DC gain, the delay moving linearly across the block.
double exact_read(const std::vector<float>& x, std::size_t at, double delay) {
  const auto whole = static_cast<std::size_t>(delay);
  const double frac = delay - double(whole);
  auto i0 = [](double v) {
    double sum = 1.0, term = 1.0;
    for (int k = 1; k < 40; ++k) term *= (v / (2.0 * k)) * (v / (2.0 * k)), sum += term;
    return sum;
  };
  double y = 0.0, dc = 0.0;
  for (std::size_t t = 0; t < 16; ++t) {
    const double u = 8.0 - double(t) - frac;
    const double sinc = u == 0.0 ? 1.0 : std::sin(std::numbers::pi * u) / (std::numbers::pi * u);
    const double r = u / 8.0;
    const double w = std::abs(r) >= 1.0 ? 0.0 : i0(7.0 * std::sqrt(1.0 - r * r)) / i0(7.0);
    const std::size_t k = at - whole - 8 + t;  // callers keep at >= delay + 8
    y += sinc * w * x[k];
    dc += sinc * w;
  }
  return y / dc;
}
}  // namespace

TEST(FractionalDelay, GlidingReadsMatchTheExactKernel) {
  // Slow glides keep eight samples' kernels in one cell or two, fast ones
  // cross many per group (each sample its own kernel); both directions,
  // through whole samples and around the ring, on the CPU-specific and the
  // portable path, and with a block that is not a multiple of eight.
  for (const auto isa : runnable_isas()) {
    for (const std::size_t B : {std::size_t{128}, std::size_t{61}}) {
      for (const double rate : {2e-5, 4e-4, 0.005, 0.04, 0.4, -0.005, -0.4}) {
        FractionalDelay line(B, 200, simd::kernels(isa));
        const std::size_t blocks = 60;
        const auto x = noise(B * blocks, 31);
        std::vector<float> y(B);
        double d = rate > 0 ? 9.0 : 150.0, worst = 0.0;
        for (std::size_t b = 0; b < blocks; ++b) {
          double next = d + rate * double(B);
          if (next > 190.0 || next < 9.0) next = d;  // hold at the ends: a still block now and then
          line.write(std::span(x).subspan(b * B, B));
          line.read(y, d, next);
          for (std::size_t i = 0; i < B; ++i) {
            const double di = d + (next - d) * double(i + 1) / double(B);
            const std::size_t at = b * B + i;
            if (double(at) < di + 9.0) continue;  // reads before the input began
            worst = std::max(worst, std::abs(double(y[i]) - exact_read(x, at, di)));
          }
          d = next;
        }
        EXPECT_LT(worst, 2e-5) << simd::name(isa) << " block " << B << " rate " << rate;
      }
    }
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
  DirectionBank bank(std::make_shared<const HrtfSpectra>(*kemar48(), B));
  FractionalDelay delay(B, 2000);
  const auto x = noise(B, 11);
  std::vector<float> l(B), r(B), tl(B), tr(B);
  earshot::testing::AllocationProbe probe;
  for (int blk = 0; blk < 200; ++blk) {
    delay.write(x);
    delay.read(tl, 40.0 + 0.3 * blk, 40.3 + 0.3 * blk);
    delay.read(tr, 50.0, 50.0);
    // A moving source: new measurements every few blocks, lanes starting and retiring.
    const auto m = static_cast<std::size_t>(blk / 3 % 600);
    bank.add(m, 0, tl, DirectionBank::GainCurve::ramp(0.3f, 0.5f));
    bank.add(m + 1, 1, tr, DirectionBank::GainCurve::ramp(0.5f, 0.3f));
    bank.process(l, r);
  }
  EXPECT_EQ(probe.count(), 0u);
  EXPECT_EQ(probe.lock_count(), 0u);
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

TEST(AirAbsorption, LeavingTheBypassDoesNotClick) {
  // Factor 0 skips the filter; when absorption starts, the filter starts
  // from the steady state of the signal rather than from zero. Compare with
  // a filter that ran all along (a factor too small to hear, so no bypass).
  using earshot::audio::AirAbsorption;
  AirAbsorption skipped(48000.0), running(48000.0);
  const std::size_t B = 64;
  std::vector<float> x(B * 40);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(0.8 * std::sin(2 * std::numbers::pi * 300.0 * double(i) / 48000.0 + 1.0));
  std::vector<float> a = x, b = x;
  for (std::size_t blk = 0; blk < 40; ++blk) {
    skipped.update(50.0, blk < 20 ? 0.0 : 1.0);
    running.update(50.0, blk < 20 ? 1e-9 : 1.0);
    skipped.process(std::span(a).subspan(blk * B, B));
    running.process(std::span(b).subspan(blk * B, B));
  }
  for (std::size_t i = 0; i < 20 * B; ++i) ASSERT_EQ(a[i], x[i]) << "factor 0 must leave the signal untouched";
  double worst = 0;
  for (std::size_t i = 20 * B; i < x.size(); ++i) worst = std::max(worst, double(std::abs(a[i] - b[i])));
  EXPECT_LT(worst, 1e-3);  // started from zero state instead: 3.5e-3
}

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

TEST(SpectralKernels, RealSpectrumIsTheSameOnEveryPath) {
  // Every path against the split computed in double, for a size with
  // whole groups of eight bins and one without (the scalar path).
  for (const std::size_t M : {std::size_t{128}, std::size_t{20}}) {
    const std::size_t S = (M + 1 + 7) / 8 * 8;
    const auto v = noise(2 * M, static_cast<unsigned>(41 + M));
    std::vector<std::complex<float>> z(M + 1);
    for (std::size_t k = 0; k < M; ++k) z[k] = {v[2 * k], v[2 * k + 1]};
    z[M] = z[0];
    std::vector<float> c(M + 1), s(M + 1), sign(M + 1);
    for (std::size_t k = 0; k <= M; ++k) {
      c[k] = float(0.5 * std::cos(std::numbers::pi * double(k) / double(M)));
      s[k] = float(0.5 * std::sin(std::numbers::pi * double(k) / double(M)));
      sign[k] = k % 3 ? 1.0f : -1.0f;
    }
    for (const auto isa : runnable_isas()) {
      std::vector<float> out(2 * S, 7.0f);
      simd::kernels(isa).real_spectrum(z.data(), M, c.data(), s.data(), sign.data(), out.data(), S);
      for (std::size_t k = 0; k < S; ++k) {
        if (k > M) {  // padding
          ASSERT_EQ(out[k], 7.0f);
          ASSERT_EQ(out[S + k], 7.0f);
          continue;
        }
        const std::complex<double> a = z[k], b = std::conj(std::complex<double>(z[M - k]));
        const std::complex<double> ref =
            double(sign[k]) * (0.5 * (a + b) + std::polar(1.0, -std::numbers::pi * double(k) / double(M)) *
                                                   std::complex<double>(0, -0.5) * (a - b));
        ASSERT_NEAR(out[k], ref.real(), 1e-5) << simd::name(isa) << " M " << M << " bin " << k;
        ASSERT_NEAR(out[S + k], ref.imag(), 1e-5) << simd::name(isa) << " M " << M << " bin " << k;
      }
    }
  }
}
