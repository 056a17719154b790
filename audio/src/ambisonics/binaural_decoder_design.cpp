#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <array>
#include <span>
#include <numbers>
#include <stdexcept>
#include <string>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/audio/real_fft.hpp"
#include "joint_ear_fit.hpp"

namespace earshot::ambisonics {
namespace {

using cd = std::complex<double>;
constexpr double kHeadRadius = 0.0875;
constexpr double kSpeedOfSound = 343.0;
constexpr double kMaxTransitionHz = 2000.0;
/// Below this the ITD is heard (and ambi_cues measures it).
constexpr double kItdBandHz = 1500.0;
constexpr std::size_t kQuadraturePoints = std::size_t{1} << 15;
using design_detail::kPowerFloor;

/// Third-octave band edges from f0 up, as bin indices (first bin of each band).
std::vector<std::size_t> band_starts(std::size_t first_bin, std::size_t bins, double bin_hz) {
  std::vector<std::size_t> starts{first_bin};
  double f = std::max(double(first_bin) * bin_hz, bin_hz);
  for (;;) {
    f *= std::pow(2.0, 1.0 / 3.0);
    const auto k = static_cast<std::size_t>(std::ceil(f / bin_hz));
    if (k >= bins) break;
    if (k > starts.back()) starts.push_back(k);
  }
  starts.push_back(bins);
  return starts;
}

/// The standard third-octave bands (base 2, 1 kHz reference: edges at
/// 1000 x 2^((2k + 1) / 6) Hz) above `first_bin`, as bin indices (first bin of
/// each band; the first band starts at first_bin, the last ends at `bins`).
/// The joint fit works in these bands, which docs/AMBISONICS.md's band errors
/// are measured in.
std::vector<std::size_t> standard_third_octaves(std::size_t first_bin, std::size_t bins, double bin_hz) {
  std::vector<std::size_t> starts{first_bin};
  for (int k = -40; k < 40; ++k) {
    const auto edge = static_cast<std::size_t>(std::ceil(1000.0 * std::pow(2.0, (2.0 * k + 1.0) / 6.0) / bin_hz));
    if (edge >= bins) break;
    if (edge > starts.back()) starts.push_back(edge);
  }
  // A first band narrower than half a third of an octave joins the next.
  if (starts.size() > 2 && double(starts[1]) < double(starts[0]) * std::pow(2.0, 1.0 / 6.0)) starts.erase(starts.begin() + 1);
  starts.push_back(bins);
  return starts;
}

}  // namespace

std::string design_key(const DecoderDesign& d, int order) {
  char buf[384];
  std::snprintf(buf, sizeof buf,
                "v%u order=%d method=%s transition=%.17g shadow=%d below=%.17g joint=%d ild_weight=%.17g "
                "level_weight=%.17g covariance=%d reg=%.17g length=%zu",
                unsigned(kDecoderDesignVersion), order, d.method == DecoderMethod::ls ? "ls" : "magls", d.transition_hz,
                int(d.shadow_weighting), d.shadow_below_db, int(d.joint_ear_fit), d.ild_weight, d.level_weight,
                int(d.diffuse_covariance), d.regularisation, d.length);
  return buf;
}

double transition_hz_for(const DecoderDesign& design, int order) {
  if (design.transition_hz > 0.0) return design.transition_hz;
  return std::min(kMaxTransitionHz, order * kSpeedOfSound / (2.0 * std::numbers::pi * kHeadRadius));
}

std::vector<double> sphere_quadrature(const hrtf::HrtfSet& set) {
  const std::size_t Q = set.measurement_count();
  std::vector<Vec3> d(Q);
  for (std::size_t q = 0; q < Q; ++q) d[q] = ambix_from_sofa(set.direction(q).azimuth, set.direction(q).elevation);
  // The grid's typical spacing: the median angle to the nearest neighbour.
  std::vector<double> nearest(Q, -1.0);
  for (std::size_t q = 0; q < Q; ++q)
    for (std::size_t r = 0; r < Q; ++r)
      if (r != q) nearest[q] = std::max(nearest[q], dot(d[q], d[r]));
  std::nth_element(nearest.begin(), nearest.begin() + static_cast<long>(Q / 2), nearest.end());
  const double spacing = std::acos(std::clamp(nearest[Q / 2], -1.0, 1.0));
  const double min_cos = std::cos(std::min(std::numbers::pi, 2.0 * spacing));
  std::vector<double> w(Q, 0.0);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  const double cell = 4.0 * std::numbers::pi / double(kQuadraturePoints);
  // Half the points on a Fibonacci lattice, half their mirror images across
  // the median plane: a left-right symmetric grid gets symmetric weights
  // (and a symmetric decoder, so ILD 0 ahead and behind).
  for (std::size_t i = 0; i < kQuadraturePoints; ++i) {
    const std::size_t j = i / 2;
    const double z = 1.0 - (2.0 * double(j) + 1.0) / double(kQuadraturePoints / 2);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = golden * double(j);
    const Vec3 p{r * std::cos(phi), (i % 2 ? -1.0 : 1.0) * r * std::sin(phi), z};
    std::size_t best = 0;
    double best_cos = -2.0;
    for (std::size_t q = 0; q < Q; ++q) {
      const double c = dot(p, d[q]);
      if (c > best_cos) best_cos = c, best = q;
    }
    if (best_cos >= min_cos) w[best] += cell;
  }
  return w;
}

namespace {

/// How long the filters are and the FFT the design runs at: the filters
/// with their delays fit in `length`; the design runs at twice that, so what
/// MagLS's phase continuation puts before time zero or late lands in the
/// half that is cut off, not on the filters.
struct DesignSizes {
  std::size_t length = 0, nfft = 0, bins = 0;
  double bin_hz = 0.0;
};

DesignSizes design_sizes(const hrtf::HrtfSet& set, const DecoderDesign& design) {
  const double rate = set.sample_rate();
  double max_delay = 0.0;
  for (std::size_t q = 0; q < set.measurement_count(); ++q)
    max_delay = std::max({max_delay, set.delays(q).left_s * rate, set.delays(q).right_s * rate});
  DesignSizes z;
  z.length = design.length ? design.length : std::bit_ceil(set.filter_length() + static_cast<std::size_t>(std::ceil(max_delay)));
  z.nfft = 2 * std::bit_ceil(std::max(z.length, set.filter_length() + static_cast<std::size_t>(std::ceil(max_delay))));
  z.bins = z.nfft / 2 + 1;
  z.bin_hz = rate / double(z.nfft);
  return z;
}

/// The real SH matrix at the measured directions (Q x C).
Eigen::MatrixXd sh_matrix(const hrtf::HrtfSet& set, int order) {
  const std::size_t Q = set.measurement_count(), C = channel_count(order);
  Eigen::MatrixXd Y(Q, C);
  std::vector<double> y(C);
  for (std::size_t q = 0; q < Q; ++q) {
    real_sh(order, ambix_from_sofa(set.direction(q).azimuth, set.direction(q).elevation), std::span<double>(y));
    for (std::size_t c = 0; c < C; ++c) Y(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(c)) = y[c];
  }
  return Y;
}

/// The weighted, Tikhonov-regularised pseudo-inverse of Y (C x Q):
/// (Y' V Y + mu I)^-1 Y' V, mu = `regularisation` x the mean diagonal.
Eigen::MatrixXd regularised_pinv(const Eigen::MatrixXd& Y, const Eigen::VectorXd& v, double regularisation) {
  Eigen::MatrixXd A = Y.transpose() * v.asDiagonal() * Y;
  const double mu = regularisation * A.trace() / double(Y.cols());
  A.diagonal().array() += mu;
  return A.ldlt().solve(Y.transpose() * v.asDiagonal());
}

/// Each measured filter played at its delay, as the direct renderer does,
/// as a spectrum (per ear: Q x bins).
void measured_spectra(const hrtf::HrtfSet& set, const DesignSizes& z, Eigen::MatrixXcd (&H)[2]) {
  const std::size_t Q = set.measurement_count();
  const double rate = set.sample_rate();
  for (auto& h : H) h.resize(static_cast<Eigen::Index>(Q), static_cast<Eigen::Index>(z.bins));
  audio::RealFft fft(z.nfft);
  std::vector<float> x(z.nfft);
  std::vector<std::complex<float>> X(z.bins);
  for (std::size_t q = 0; q < Q; ++q)
    for (std::size_t e = 0; e < 2; ++e) {
      const auto f = set.filter(q, static_cast<hrtf::Ear>(e));
      std::fill(x.begin(), x.end(), 0.0f);
      std::copy(f.begin(), f.end(), x.begin());
      fft.forward(x, X);
      const double tau = (e == 0 ? set.delays(q).left_s : set.delays(q).right_s) * rate;
      for (std::size_t k = 0; k < z.bins; ++k)
        H[e](static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(k)) =
            cd(X[k]) * std::polar(1.0, -2.0 * std::numbers::pi * double(k) * tau / double(z.nfft));
    }
}

/// Each ear's typical delay (samples): the quadrature-weighted mean over
/// directions of the energy centroid of its response (filter at its
/// delay). MagLS's phase above the transition runs on from the previous bin
/// with this group delay, so the high band sits where the responses' energy
/// is instead of around time zero (half of it wrapping to the end).
std::array<double, 2> group_delays(const hrtf::HrtfSet& set, const std::vector<double>& w, double wsum) {
  const double rate = set.sample_rate();
  std::array<double, 2> group_delay{0.0, 0.0};
  for (std::size_t e = 0; e < 2; ++e) {
    for (std::size_t q = 0; q < set.measurement_count(); ++q) {
      const auto f = set.filter(q, static_cast<hrtf::Ear>(e));
      double num = 0.0, den = 0.0;
      for (std::size_t i = 0; i < f.size(); ++i) {
        num += double(i) * double(f[i]) * f[i];
        den += double(f[i]) * f[i];
      }
      const double tau = (e == 0 ? set.delays(q).left_s : set.delays(q).right_s) * rate;
      if (den > 0.0) group_delay[e] += w[q] * (num / den + tau) / wsum;
    }
  }
  return group_delay;
}

/// Above the transition bin kc: per third-octave band and ear, a weighted
/// LS fit of magnitudes (DecoderDesign::shadow_weighting), each bin's phase
/// run on from the previous bin's decoder by the ear's group delay.
void magls_above(const DecoderDesign& design, const Eigen::MatrixXd& Y, const Eigen::VectorXd& wv, double wsum,
                 const Eigen::MatrixXcd& G, const Eigen::MatrixXcd (&H)[2], const std::array<double, 2>& group_delay,
                 const DesignSizes& z, std::size_t kc, Eigen::MatrixXcd (&D)[2]) {
  const Eigen::Index Qi = Y.rows();
  const Eigen::MatrixXcd Yc = Y.cast<cd>();
  const std::vector<std::size_t> bands = band_starts(kc, z.bins, z.bin_hz);
  Eigen::VectorXcd t(Qi), reproduced(Qi);
  const cd step[2] = {std::polar(1.0, -2.0 * std::numbers::pi * group_delay[0] / double(z.nfft)),
                      std::polar(1.0, -2.0 * std::numbers::pi * group_delay[1] / double(z.nfft))};
  Eigen::VectorXd v(Qi), power(Qi);
  Eigen::MatrixXcd Gb;
  for (std::size_t e = 0; e < 2; ++e)
    for (std::size_t b = 0; b + 1 < bands.size(); ++b) {
      const auto k0 = static_cast<Eigen::Index>(bands[b]), n = static_cast<Eigen::Index>(bands[b + 1] - bands[b]);
      if (design.shadow_weighting) {
        // Weight = quadrature x max(1, threshold / power): plain where a
        // direction is loud, relative error where it is in the shadow.
        power = H[e].middleCols(k0, n).cwiseAbs2().rowwise().sum();
        const double mean = power.dot(wv) / wsum;
        const double threshold = mean * std::pow(10.0, -design.shadow_below_db / 10.0);
        const double floor = mean * kPowerFloor;
        v = wv.cwiseProduct((threshold / power.array().max(floor)).max(1.0).matrix());
        // As regularised_pinv, but the solve cast to complex as it is
        // evaluated (Eigen rounds that path differently in the last bits,
        // which the joint fit's L-BFGS would carry into the filters).
        Eigen::MatrixXd Ab = Y.transpose() * v.asDiagonal() * Y;
        Ab.diagonal().array() += design.regularisation * Ab.trace() / double(Y.cols());
        Gb = Ab.ldlt().solve(Y.transpose() * v.asDiagonal()).cast<cd>();
      }
      const Eigen::MatrixXcd& Gu = design.shadow_weighting ? Gb : G;
      for (Eigen::Index K = k0; K < k0 + n; ++K) {
        reproduced.noalias() = Yc * D[e].col(K - 1) * step[e];
        for (Eigen::Index q = 0; q < Qi; ++q) {
          const double mag = std::abs(H[e](q, K));
          const double a = std::abs(reproduced(q));
          t(q) = a > 0.0 ? reproduced(q) * (mag / a) : cd(mag, 0.0);
        }
        D[e].col(K).noalias() = Gu * t;
      }
    }
}

/// From bin kc up: the ears' 2 x 2 covariance in a diffuse field (SN3D
/// channel covariance diag(1 / (2l + 1))) matched to the measured one.
void match_diffuse_covariance(const std::vector<double>& w, double wsum, const Eigen::MatrixXcd (&H)[2], std::size_t kc,
                              Eigen::MatrixXcd (&D)[2]) {
  const Eigen::Index C = D[0].rows(), Qi = H[0].rows();
  const auto bins = static_cast<std::size_t>(D[0].cols());
  Eigen::VectorXd cdiag(C);
  for (std::size_t c = 0; c < static_cast<std::size_t>(C); ++c)
    cdiag(static_cast<Eigen::Index>(c)) = 1.0 / (2.0 * degree_of(c) + 1.0);
  for (std::size_t k = kc; k < bins; ++k) {
    const auto K = static_cast<Eigen::Index>(k);
    Eigen::Matrix2cd R = Eigen::Matrix2cd::Zero(), Rh = Eigen::Matrix2cd::Zero();
    for (Eigen::Index q = 0; q < Qi; ++q) {
      const cd h[2] = {H[0](q, K), H[1](q, K)};
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) R(i, j) += w[static_cast<std::size_t>(q)] * std::conj(h[i]) * h[j];
    }
    R /= wsum;
    Eigen::MatrixXcd Dk(C, 2);
    Dk.col(0) = D[0].col(K);
    Dk.col(1) = D[1].col(K);
    Rh = Dk.adjoint() * cdiag.asDiagonal() * Dk;
    Eigen::LLT<Eigen::Matrix2cd> lr(R), lh(Rh);
    if (lr.info() != Eigen::Success || lh.info() != Eigen::Success) continue;
    const Eigen::Matrix2cd X = lr.matrixL().adjoint(), Xh = lh.matrixL().adjoint();
    Eigen::JacobiSVD<Eigen::Matrix2cd> svd(X * Xh.adjoint(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix2cd Qm = svd.matrixV() * svd.matrixU().adjoint();
    const Eigen::Matrix2cd M = Xh.inverse() * Qm * X;
    const Eigen::MatrixXcd Dn = Dk * M;
    D[0].col(K) = Dn.col(0);
    D[1].col(K) = Dn.col(1);
  }
}

/// Real filters from the spectra: DC and Nyquist real, back to time, cut to
/// `length` with a short fade at the end.
DecoderFilters to_filters(const Eigen::MatrixXcd (&D)[2], int order, double rate, const DesignSizes& z) {
  const std::size_t C = channel_count(order), length = z.length;
  DecoderFilters out;
  out.order = order;
  out.sample_rate = rate;
  out.length = length;
  out.taps.assign(2 * C * length, 0.0f);
  audio::RealFft fft(z.nfft);
  std::vector<std::complex<float>> S(z.bins);
  std::vector<float> x(z.nfft);
  const std::size_t fade = std::min<std::size_t>(32, length / 4);
  for (std::size_t e = 0; e < 2; ++e)
    for (std::size_t c = 0; c < C; ++c) {
      for (std::size_t k = 0; k < z.bins; ++k) {
        cd v = D[e](static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(k));
        if (k == 0 || k + 1 == z.bins) v = cd(v.real(), 0.0);
        S[k] = std::complex<float>(v);
      }
      fft.inverse(S, x);
      float* dst = out.taps.data() + (e * C + c) * length;
      std::copy_n(x.begin(), length, dst);
      for (std::size_t i = 0; i < fade; ++i)
        dst[length - fade + i] *= float(0.5 + 0.5 * std::cos(std::numbers::pi * (double(i) + 0.5) / double(fade)));
    }
  return out;
}

}  // namespace

DecoderFilters design_binaural_decoder(const hrtf::HrtfSet& set, int order, const DecoderDesign& design) {
  if (order < 1 || order > kMaxOrder)
    throw std::invalid_argument("design_binaural_decoder: order " + std::to_string(order) + " outside 1.." +
                                std::to_string(kMaxOrder));
  const std::size_t Q = set.measurement_count(), C = channel_count(order);
  if (Q < C)
    throw std::invalid_argument("design_binaural_decoder: " + std::to_string(Q) + " measurements cannot determine " +
                                std::to_string(C) + " channels");
  const double rate = set.sample_rate();
  const DesignSizes z = design_sizes(set, design);

  // The quadrature and the LS decoder G (C x Q) at every frequency.
  const Eigen::MatrixXd Y = sh_matrix(set, order);
  const std::vector<double> w = sphere_quadrature(set);
  double wsum = 0.0;
  for (double v : w) wsum += v;
  const Eigen::VectorXd wv = Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(Q));
  const Eigen::MatrixXcd G = regularised_pinv(Y, wv, design.regularisation).cast<cd>();

  Eigen::MatrixXcd H[2];
  measured_spectra(set, z, H);

  // LS below the transition (everywhere for DecoderMethod::ls), MagLS above.
  const double fc = design.method == DecoderMethod::ls ? rate : transition_hz_for(design, order);
  const auto kc = std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(fc / z.bin_hz)), 1, z.bins);
  const auto Kc = static_cast<Eigen::Index>(kc);
  Eigen::MatrixXcd D[2] = {Eigen::MatrixXcd(C, z.bins), Eigen::MatrixXcd(C, z.bins)};
  for (std::size_t e = 0; e < 2; ++e) D[e].leftCols(Kc) = G * H[e].leftCols(Kc);
  if (kc < z.bins) {
    magls_above(design, Y, wv, wsum, G, H, group_delays(set, w, wsum), z, kc, D);
    // The joint fit starts above the ITD's band too: below 1.5 kHz each
    // bin's interaural phase is what the ITD is heard (and measured) from,
    // and a mix there moved order 2's ITD by 0.85 ms.
    const auto k_itd = static_cast<std::size_t>(std::ceil(kItdBandHz / z.bin_hz));
    if (design.joint_ear_fit && std::max(kc, k_itd) < z.bins)
      design_detail::fit_ears_jointly(set, order, design, Y, w, H, D, standard_third_octaves(std::max(kc, k_itd), z.bins, z.bin_hz));
  }
  if (design.diffuse_covariance && kc < z.bins) match_diffuse_covariance(w, wsum, H, kc, D);
  return to_filters(D, order, rate, z);
}

namespace {
constexpr char kMagic[8] = {'E', 'S', 'A', 'M', 'B', 'D', 'E', 'C'};
constexpr std::uint32_t kFormatVersion = 1;

template <class T>
void put(std::vector<std::uint8_t>& b, T v) {
  static_assert(std::endian::native == std::endian::little, "the byte form is little-endian");
  const std::size_t at = b.size();
  b.resize(at + sizeof(T));
  std::memcpy(b.data() + at, &v, sizeof(T));
}
template <class T>
T get(std::span<const std::uint8_t> b, std::size_t& at) {
  if (at + sizeof(T) > b.size()) throw std::invalid_argument("decoder filters: truncated");
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}
}  // namespace

std::vector<std::uint8_t> DecoderFilters::serialise() const {
  std::vector<std::uint8_t> b;
  b.reserve(40 + taps.size() * 4);
  b.resize(sizeof kMagic);
  std::memcpy(b.data(), kMagic, sizeof kMagic);
  put<std::uint32_t>(b, kFormatVersion);
  put<std::int32_t>(b, order);
  put<double>(b, sample_rate);
  put<std::uint64_t>(b, length);
  put<std::uint64_t>(b, taps.size());
  const std::size_t at = b.size();
  b.resize(at + taps.size() * sizeof(float));
  if (!taps.empty()) std::memcpy(b.data() + at, taps.data(), taps.size() * sizeof(float));
  return b;
}

DecoderFilters DecoderFilters::deserialise(std::span<const std::uint8_t> bytes) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("decoder filters: " + what); };
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) fail("not decoder filters (magic)");
  std::size_t at = sizeof kMagic;
  if (const auto v = get<std::uint32_t>(bytes, at); v != kFormatVersion) fail("format version " + std::to_string(v));
  DecoderFilters f;
  f.order = get<std::int32_t>(bytes, at);
  f.sample_rate = get<double>(bytes, at);
  const auto length = get<std::uint64_t>(bytes, at);
  const auto count = get<std::uint64_t>(bytes, at);
  if (f.order < 1 || f.order > kMaxOrder) fail("order " + std::to_string(f.order));
  if (!(f.sample_rate >= 8000.0 && f.sample_rate <= 768000.0)) fail("rate " + std::to_string(f.sample_rate));
  if (length == 0 || length > (std::uint64_t{1} << 20)) fail("length " + std::to_string(length));
  f.length = static_cast<std::size_t>(length);
  if (count != 2 * f.channels() * f.length) fail("tap count " + std::to_string(count) + " does not fit order and length");
  if (bytes.size() - at != count * sizeof(float)) fail("size " + std::to_string(bytes.size()) + " bytes does not fit the taps");
  f.taps.resize(static_cast<std::size_t>(count));
  std::memcpy(f.taps.data(), bytes.data() + at, f.taps.size() * sizeof(float));
  for (float v : f.taps)
    if (!std::isfinite(v)) fail("a tap is not finite");
  return f;
}

}  // namespace earshot::ambisonics
