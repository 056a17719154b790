// The binaural decoder: its design from the default SOFA set, its byte
// form, and the convolver against a plain convolution.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <complex>
#include <cstring>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "earshot/audio/ambisonics/bed_renderer.hpp"
#include "earshot/audio/ambisonics/binaural_decoder.hpp"
#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"
#include "earshot/audio/ambisonics/scene_rotator.hpp"
#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/audio/real_fft.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

using namespace earshot;
using namespace earshot::ambisonics;

namespace {

constexpr double kRate = 48000.0;
constexpr double kPi = std::numbers::pi;

const hrtf::HrtfSet& kemar() {
  static const hrtf::HrtfSet set = hrtf::HrtfSet::load_default(kRate);
  return set;
}

/// |spectrum| of x zero-padded to n, bins 0..n/2.
std::vector<double> magnitude(std::span<const float> x, std::size_t n, double delay_samples = 0.0) {
  audio::RealFft fft(n);
  std::vector<float> buf(n, 0.0f);
  std::copy_n(x.begin(), std::min(x.size(), n), buf.begin());
  std::vector<std::complex<float>> X(n / 2 + 1);
  fft.forward(buf, X);
  (void)delay_samples;
  std::vector<double> m(X.size());
  for (std::size_t k = 0; k < X.size(); ++k) m[k] = std::abs(X[k]);
  return m;
}

/// The decoder's response to a plane wave from d, per ear: sum_c Y_c(d) h_{e,c}.
std::vector<float> plane_wave_response(const DecoderFilters& f, const Vec3& d, std::size_t ear) {
  std::vector<float> y(f.channels());
  real_sh(f.order, d, std::span<float>(y));
  std::vector<float> h(f.length, 0.0f);
  for (std::size_t c = 0; c < f.channels(); ++c) {
    const auto fc = f.filter(ear, c);
    for (std::size_t i = 0; i < f.length; ++i) h[i] += y[c] * fc[i];
  }
  return h;
}

/// Mean |dB| difference of the decoded and measured magnitudes over
/// [lo, hi) Hz at the set's horizontal measurements, both ears.
double mean_db_error(const DecoderFilters& f, double lo, double hi) {
  const auto& set = kemar();
  const std::size_t n = 2 * f.length;
  double sum = 0.0;
  int count = 0;
  for (std::size_t q = 0; q < set.measurement_count(); ++q) {
    if (std::abs(set.direction(q).elevation) > 1e-6) continue;
    const Vec3 d = ambix_from_sofa(set.direction(q).azimuth, 0.0);
    for (std::size_t e = 0; e < 2; ++e) {
      const auto dec = magnitude(plane_wave_response(f, d, e), n);
      const auto ref = magnitude(set.filter(q, static_cast<hrtf::Ear>(e)), n);
      for (std::size_t k = 0; k < dec.size(); ++k) {
        const double hz = double(k) * kRate / double(n);
        if (hz < lo || hz >= hi) continue;
        sum += std::abs(20 * std::log10(dec[k] / ref[k]));
        ++count;
      }
    }
  }
  return sum / count;
}

}  // namespace

TEST(DecoderDesign, QuadratureCoversTheMeasuredSphere) {
  const auto w = sphere_quadrature(kemar());
  ASSERT_EQ(w.size(), kemar().measurement_count());
  double total = 0.0;
  for (double v : w) {
    EXPECT_GT(v, 0.0);
    total += v;
  }
  // KEMAR reaches down to -40 deg: the cap below -50 deg is 12% of the sphere.
  const double covered = total / (4 * kPi);
  EXPECT_GT(covered, 0.82);
  EXPECT_LT(covered, 0.95);
}

TEST(DecoderDesign, LeastSquaresAtOrder5ReproducesTheHrtfMagnitudeAtLowFrequencies) {
  DecoderDesign ls;
  ls.method = DecoderMethod::ls;
  const DecoderFilters f = design_binaural_decoder(kemar(), 5, ls);
  EXPECT_EQ(f.channels(), 36u);
  const double low = mean_db_error(f, 100.0, 1000.0);
  const double high = mean_db_error(f, 8000.0, 16000.0);
  std::printf("LS order 5, horizontal directions: mean |dB| error 100-1000 Hz %.3f, 8-16 kHz %.3f\n", low, high);
  EXPECT_LT(low, 0.35);  // measured 0.28: the data's fine ripple over direction is of higher order
  EXPECT_GT(high, 10 * low);  // the order's limit shows above
  // Order 1 cannot: a first-order pattern misses the head shadow already.
  const double low1 = mean_db_error(design_binaural_decoder(kemar(), 1, ls), 100.0, 1000.0);
  std::printf("LS order 1: mean |dB| error 100-1000 Hz %.3f\n", low1);
  EXPECT_GT(low1, 2 * low);
}

TEST(DecoderDesign, MagLsFitsMagnitudesAboveTheTransitionBetterThanLs) {
  DecoderDesign ls, mls;
  ls.method = DecoderMethod::ls;
  mls.method = DecoderMethod::magls;
  const double e_ls = mean_db_error(design_binaural_decoder(kemar(), 3, ls), 4000.0, 16000.0);
  const double e_mls = mean_db_error(design_binaural_decoder(kemar(), 3, mls), 4000.0, 16000.0);
  std::printf("order 3, 4-16 kHz mean |dB| error: LS %.2f, MagLS %.2f\n", e_ls, e_mls);
  EXPECT_LT(e_mls, 0.6 * e_ls);
}

/// The worst (or with `mean`, the mean) broadband ILD error (dB) of a plane
/// wave at the horizontal measurements of `set` whose |azimuth| is within
/// [from_deg, to_deg]: decoded response energies against the measured
/// filters'.
double worst_ild_error(const DecoderFilters& f, const hrtf::HrtfSet& set = kemar(), double from_deg = 0.0,
                       double to_deg = 180.0, bool mean = false) {
  double worst = 0.0, sum = 0.0;
  int count = 0;
  for (std::size_t q = 0; q < set.measurement_count(); ++q) {
    if (std::abs(set.direction(q).elevation) > 1e-6) continue;
    const double az = std::abs(std::remainder(set.direction(q).azimuth, 2 * kPi)) * 180.0 / kPi;
    if (az < from_deg - 1e-3 || az > to_deg + 1e-3) continue;  // azimuths are stored as float
    const Vec3 d = ambix_from_sofa(set.direction(q).azimuth, 0.0);
    double dec[2], ref[2];
    for (std::size_t e = 0; e < 2; ++e) {
      dec[e] = ref[e] = 0.0;
      for (float v : plane_wave_response(f, d, e)) dec[e] += double(v) * v;
      for (float v : set.filter(q, static_cast<hrtf::Ear>(e))) ref[e] += double(v) * v;
    }
    const double e = std::abs(10 * std::log10(dec[0] / dec[1]) - 10 * std::log10(ref[0] / ref[1]));
    worst = std::max(worst, e);
    sum += e;
    ++count;
  }
  return mean ? sum / count : worst;
}

TEST(DecoderDesign, ShadowWeightingKeepsTheFarEarsLevelAtOrder3) {
  // Plain MagLS fills in the far ear's head shadow (KEMAR, 110 deg: 4.3 dB
  // of ILD lost); weighting the shadow's directions by relative error
  // brings the worst horizontal ILD error under 2 dB (the joint fit of the
  // ears off, to see the weighting alone).
  DecoderDesign plain, shadow;
  plain.shadow_weighting = false;
  plain.joint_ear_fit = shadow.joint_ear_fit = false;
  const double e_plain = worst_ild_error(design_binaural_decoder(kemar(), 3, plain));
  const double e_shadow = worst_ild_error(design_binaural_decoder(kemar(), 3, shadow));
  std::printf("order 3, worst horizontal ILD error: plain MagLS %.2f dB, shadow-weighted %.2f dB\n", e_plain, e_shadow);
  EXPECT_GT(e_plain, 3.5);
  EXPECT_LT(e_shadow, 2.2);
}

/// The mean |dB| error of the standard third-octave band energies (centres
/// 100 Hz to 16 kHz) of plane waves at the horizontal measurements of
/// `set`, both ears: what docs/AMBISONICS.md calls the mean band error.
double mean_band_error(const DecoderFilters& f, const hrtf::HrtfSet& set) {
  const std::size_t n = 2 * std::max(f.length, set.filter_length());
  const double bin_hz = set.sample_rate() / double(n);
  std::vector<std::size_t> edges;
  for (int k = -10; k <= 13; ++k)
    edges.push_back(std::min(n / 2 + 1, std::size_t(std::ceil(1000.0 * std::pow(2.0, (2.0 * k - 1.0) / 6.0) / bin_hz))));
  double sum = 0.0;
  int count = 0;
  for (std::size_t q = 0; q < set.measurement_count(); ++q) {
    if (std::abs(set.direction(q).elevation) > 1e-6) continue;
    const Vec3 d = ambix_from_sofa(set.direction(q).azimuth, 0.0);
    for (std::size_t e = 0; e < 2; ++e) {
      const auto dec = magnitude(plane_wave_response(f, d, e), n);
      const auto ref = magnitude(set.filter(q, static_cast<hrtf::Ear>(e)), n);
      for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
        if (edges[b + 1] <= edges[b]) continue;
        double a = 0.0, r = 0.0;
        for (std::size_t k = edges[b]; k < edges[b + 1]; ++k) a += dec[k] * dec[k], r += ref[k] * ref[k];
        sum += std::abs(10 * std::log10(a / r));
        ++count;
      }
    }
  }
  return sum / count;
}

/// A rigid sphere (radius 9 cm, the ears at +-100 deg azimuth and -10 deg
/// elevation) measured on KEMAR's grid at 48 kHz: the scattered pressure at
/// the ear by Rayleigh's series (Duda and Martens 1998),
/// H = (1 / mu^2) sum_n i^(n+1) (2n + 1) P_n(-cos theta) / h_n'(mu) for the
/// time dependence exp(-i w t) (conjugated here), mu = 2 pi f a / c, theta
/// between the source and the ear; 0.5 ms + a / c of delay in the filter
/// (the set's delays 0). A head the design was not tuned on.
const hrtf::HrtfSet& rigid_sphere() {
  static const hrtf::HrtfSet set = [] {
    hrtf::HrtfSet::Stored s = kemar().stored();
    const std::size_t L = s.filter_length, M = s.directions.size(), n = 2 * std::bit_ceil(L), bins = n / 2 + 1;
    const double a = 0.09, c = 343.0, delay = 0.5e-3 + a / c;
    std::vector<std::vector<std::complex<double>>> coef(bins);
    for (std::size_t k = 1; k < bins; ++k) {
      const double mu = 2 * kPi * double(k) * kRate / double(n) * a / c;
      for (unsigned m = 0; m <= unsigned(mu) + 30; ++m) {
        const auto dj = m == 0 ? -std::sph_bessel(1, mu) : std::sph_bessel(m - 1, mu) - (m + 1.0) / mu * std::sph_bessel(m, mu);
        const auto dy = m == 0 ? -std::sph_neumann(1, mu) : std::sph_neumann(m - 1, mu) - (m + 1.0) / mu * std::sph_neumann(m, mu);
        const std::complex<double> dh(dj, dy), ipow = std::pow(std::complex<double>(0, 1), double(m + 1));
        coef[k].push_back(std::isfinite(std::abs(dh)) ? ipow * (2.0 * m + 1.0) / dh / (mu * mu) : 0.0);
      }
    }
    audio::RealFft fft(n);
    std::vector<std::complex<float>> H(bins);
    std::vector<float> h(n);
    const double el = -10.0 * kPi / 180.0, az = 100.0 * kPi / 180.0;
    s.filters.assign(2 * M * L, 0.0f);
    s.hrirs.assign(2 * M * s.hrir_length, 0.0f);
    for (std::size_t q = 0; q < M; ++q) {
      const Vec3 d = ambix_from_sofa(s.directions[q].azimuth, s.directions[q].elevation);
      for (std::size_t e = 0; e < 2; ++e) {
        const Vec3 ear{std::cos(el) * std::cos(az), (e == 0 ? 1.0 : -1.0) * std::cos(el) * std::sin(az), std::sin(el)};
        const double x = -(d[0] * ear[0] + d[1] * ear[1] + d[2] * ear[2]);
        H[0] = 1.0f;
        for (std::size_t k = 1; k < bins; ++k) {
          std::complex<double> sum = 0.0;
          double p0 = 1.0, p1 = x;  // Legendre P_m(x) by the three-term recurrence
          for (std::size_t m = 0; m < coef[k].size(); ++m) {
            const double p = m == 0 ? p0 : p1;
            sum += coef[k][m] * p;
            if (m >= 1) {
              const double p2 = ((2.0 * double(m) + 1.0) * x * p1 - double(m) * p0) / (double(m) + 1.0);
              p0 = p1, p1 = p2;
            }
          }
          const double f = double(k) * kRate / double(n);
          const double fade = std::clamp((0.5 * kRate - f) / (0.05 * kRate), 0.0, 1.0);
          H[k] = std::complex<float>(std::conj(sum) * std::polar(fade, -2 * kPi * f * delay));
        }
        H[bins - 1] = H[bins - 1].real();
        fft.inverse(H, h);
        for (std::size_t i = 0; i < L; ++i) s.filters[(q * 2 + e) * L + i] = h[i];
        for (std::size_t i = 0; i < s.hrir_length; ++i) s.hrirs[(q * 2 + e) * s.hrir_length + i] = h[i];
        double energy = 0.0;
        for (std::size_t i = 0; i < L; ++i) energy += double(h[i]) * h[i];
        s.energies[q][e] = energy;
      }
      s.delays[q] = {};
    }
    return hrtf::HrtfSet::from_stored(std::move(s));
  }();
  return set;
}

TEST(DecoderDesign, RigidSphereModelHasAHeadsCues) {
  // The test set itself: ahead no ILD, the left ear nearer and louder for a
  // source at the left, the shadowed ear quieter above a few kHz.
  const auto& set = rigid_sphere();
  double ild_left = 0.0, ild_ahead = 1.0;
  for (std::size_t q = 0; q < set.measurement_count(); ++q) {
    if (std::abs(set.direction(q).elevation) > 1e-6) continue;
    double en[2];
    for (std::size_t e = 0; e < 2; ++e) {
      en[e] = 0.0;
      for (float v : set.filter(q, static_cast<hrtf::Ear>(e))) en[e] += double(v) * v;
    }
    const double az = std::remainder(set.direction(q).azimuth, 2 * kPi) * 180.0 / kPi;
    if (std::abs(az) < 1e-3) ild_ahead = 10 * std::log10(en[0] / en[1]);
    if (std::abs(az - 90.0) < 1e-3) ild_left = 10 * std::log10(en[0] / en[1]);  // azimuths are stored as float
  }
  std::printf("rigid sphere: ILD ahead %.3f dB, at +90 deg %.2f dB\n", ild_ahead, ild_left);
  EXPECT_NEAR(ild_ahead, 0.0, 0.01);
  EXPECT_GT(ild_left, 8.0);
  EXPECT_LT(ild_left, 16.0);
}

TEST(DecoderDesign, JointEarFitBringsKemarsOrder3IldWithin1_5DbAndKeepsTheBands) {
  // KEMAR at order 3: MagLS (shadow-weighted) alone errs 1.9 dB in ILD at
  // +-90 deg, each ear fitted on its own; fitted together (the default),
  // the worst is 1.3 dB and the band spectra at the horizontal directions
  // are no worse (docs/AMBISONICS.md: rendered figures and the bound).
  DecoderDesign alone;
  alone.joint_ear_fit = false;
  const DecoderFilters f_alone = design_binaural_decoder(kemar(), 3, alone);
  const DecoderFilters f_joint = design_binaural_decoder(kemar(), 3);
  const double e_alone = worst_ild_error(f_alone), e_joint = worst_ild_error(f_joint);
  const double b_alone = mean_band_error(f_alone, kemar()), b_joint = mean_band_error(f_joint, kemar());
  std::printf("KEMAR order 3: worst ILD error alone %.2f dB, joint %.2f dB; mean band error alone %.3f dB, joint %.3f dB\n",
              e_alone, e_joint, b_alone, b_joint);
  EXPECT_LT(e_joint, 1.45);
  EXPECT_LT(e_joint, 0.75 * e_alone);
  EXPECT_LT(b_joint, b_alone);
}

TEST(DecoderDesign, JointEarFitOnARigidSphereBeatsMagLsAtTheSides) {
  // A head the design was not tuned on: at the sides (45-135 deg), where
  // the far ear's shadow lies, the jointly fitted ears keep the ILD closer
  // than plain MagLS and than the shadow-weighted MagLS alone; over the
  // whole horizon the mean ILD error drops; band spectra no worse.
  const auto& set = rigid_sphere();
  DecoderDesign plain, alone;
  plain.shadow_weighting = false;
  plain.joint_ear_fit = alone.joint_ear_fit = false;
  const DecoderFilters f_plain = design_binaural_decoder(set, 3, plain);
  const DecoderFilters f_alone = design_binaural_decoder(set, 3, alone);
  const DecoderFilters f_joint = design_binaural_decoder(set, 3);
  const double e_plain = worst_ild_error(f_plain, set, 45, 135), e_alone = worst_ild_error(f_alone, set, 45, 135);
  const double e_joint = worst_ild_error(f_joint, set, 45, 135);
  const double m_alone = worst_ild_error(f_alone, set, 0, 180, true), m_joint = worst_ild_error(f_joint, set, 0, 180, true);
  const double b_alone = mean_band_error(f_alone, set), b_joint = mean_band_error(f_joint, set);
  std::printf("rigid sphere order 3, worst ILD error at 45-135 deg: plain MagLS %.2f dB, shadow-weighted %.2f dB, "
              "joint %.2f dB; mean over the horizon: shadow-weighted %.2f dB, joint %.2f dB; mean band error "
              "shadow-weighted %.3f dB, joint %.3f dB\n",
              e_plain, e_alone, e_joint, m_alone, m_joint, b_alone, b_joint);
  EXPECT_LT(e_joint, 0.7 * e_plain);
  EXPECT_LT(e_joint, e_alone);
  EXPECT_LT(m_joint, 0.6 * m_alone);
  EXPECT_LT(b_joint, b_alone + 0.02);
}

TEST(DecoderDesign, RejectsOrdersItCannotDesign) {
  EXPECT_THROW((void)design_binaural_decoder(kemar(), 0), std::invalid_argument);
  EXPECT_THROW((void)design_binaural_decoder(kemar(), kMaxOrder + 1), std::invalid_argument);
}

TEST(DecoderFilters, ByteFormRoundTripsAndRefusesDamage) {
  DecoderFilters f;
  f.order = 1;
  f.sample_rate = 48000;
  f.length = 8;
  f.taps.resize(2 * 4 * 8);
  for (std::size_t i = 0; i < f.taps.size(); ++i) f.taps[i] = float(i) * 0.25f - 3.0f;
  const auto bytes = f.serialise();
  const DecoderFilters g = DecoderFilters::deserialise(bytes);
  EXPECT_EQ(g.order, 1);
  EXPECT_EQ(g.sample_rate, 48000);
  EXPECT_EQ(g.length, 8u);
  EXPECT_EQ(g.taps, f.taps);
  auto cut = bytes;
  cut.pop_back();
  EXPECT_THROW((void)DecoderFilters::deserialise(cut), std::invalid_argument);
  auto bad = bytes;
  bad[0] = 'X';
  EXPECT_THROW((void)DecoderFilters::deserialise(bad), std::invalid_argument);
  auto nan = bytes;
  const float q = std::nanf("");
  std::memcpy(nan.data() + nan.size() - 4, &q, 4);
  EXPECT_THROW((void)DecoderFilters::deserialise(nan), std::invalid_argument);
}

TEST(BinauralDecoder, EqualsPlainConvolutionAndNeverAllocates) {
  // Random filters longer than a few blocks, random input: the partitioned
  // convolver against the direct sum.
  DecoderFilters f;
  f.order = 2;
  f.sample_rate = kRate;
  f.length = 300;
  const std::size_t C = f.channels(), B = 64, blocks = 12;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1, 1);
  f.taps.resize(2 * C * f.length);
  for (float& v : f.taps) v = u(rng) * 0.1f;
  std::vector<float> in(C * B * blocks);
  for (float& v : in) v = u(rng);
  BinauralDecoder dec(f, B);
  EXPECT_EQ(dec.partitions(), 5u);
  std::vector<float> block(C * B), l(B), r(B), out_l(B * blocks), out_r(B * blocks);
  earshot::testing::AllocationProbe probe;
  for (std::size_t b = 0; b < blocks; ++b) {
    for (std::size_t c = 0; c < C; ++c)
      std::copy_n(in.begin() + static_cast<long>(c * B * blocks + b * B), B, block.begin() + static_cast<long>(c * B));
    dec.process(block, l, r);
    std::copy(l.begin(), l.end(), out_l.begin() + static_cast<long>(b * B));
    std::copy(r.begin(), r.end(), out_r.begin() + static_cast<long>(b * B));
  }
  EXPECT_EQ(probe.count(), 0u);
  EXPECT_EQ(probe.lock_count(), 0u);
  for (std::size_t n = 0; n < B * blocks; ++n)
    for (std::size_t e = 0; e < 2; ++e) {
      double y = 0.0;
      for (std::size_t c = 0; c < C; ++c) {
        const auto h = f.filter(e, c);
        for (std::size_t k = 0; k < f.length && k <= n; ++k) y += double(h[k]) * in[c * B * blocks + n - k];
      }
      ASSERT_NEAR(e == 0 ? out_l[n] : out_r[n], y, 2e-4) << "sample " << n << " ear " << e;
    }
}

TEST(BedRenderer, IsTheRotatorThenTheDecoderAndNeverAllocates) {
  DecoderFilters f;
  f.order = 1;
  f.sample_rate = kRate;
  f.length = 100;
  const std::size_t C = 4, B = 32;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1, 1);
  f.taps.resize(2 * C * f.length);
  for (float& v : f.taps) v = u(rng) * 0.1f;
  BedRenderer bed(f, B);
  SceneRotator rot(1, B);
  BinauralDecoder dec(f, B);
  std::vector<float> in(C * B), turned(C * B), l1(B), r1(B), l2(B), r2(B);
  earshot::testing::AllocationProbe probe;
  for (int b = 0; b < 8; ++b) {
    for (float& v : in) v = u(rng);
    const Quat q = quat_from_ypr(0.1 * b, 0.02 * b, 0);
    bed.set_orientation(q);
    bed.process(in, l1, r1);
    rot.update(q);
    rot.process(in, turned);
    dec.process(turned, l2, r2);
    for (std::size_t n = 0; n < B; ++n) {
      ASSERT_EQ(l1[n], l2[n]);
      ASSERT_EQ(r1[n], r2[n]);
    }
  }
  EXPECT_EQ(probe.count(), 0u);
  EXPECT_EQ(probe.lock_count(), 0u);
}

TEST(DecoderDesign, KeyNamesEveryInput) {
  DecoderDesign a, b, c, d;
  b.shadow_below_db = 12.0;
  c.joint_ear_fit = false;
  d.ild_weight = 2.0;
  EXPECT_NE(design_key(a, 3), design_key(b, 3));
  EXPECT_NE(design_key(a, 3), design_key(c, 3));
  EXPECT_NE(design_key(a, 3), design_key(d, 3));
  EXPECT_NE(design_key(a, 3), design_key(a, 4));
  EXPECT_EQ(design_key(a, 3), design_key(DecoderDesign{}, 3));
}
