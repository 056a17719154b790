#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <deque>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/audio/real_fft.hpp"

namespace earshot::ambisonics {
namespace {

using cd = std::complex<double>;
constexpr double kHeadRadius = 0.0875;
constexpr double kSpeedOfSound = 343.0;
constexpr double kMaxTransitionHz = 2000.0;
/// Below this the ITD is heard (and ambi_cues measures it).
constexpr double kItdBandHz = 1500.0;
constexpr std::size_t kQuadraturePoints = std::size_t{1} << 15;
/// Shadow weighting: a direction's power counts at least this share of the
/// band's mean (-30 dB), so a deep notch does not take all the weight.
constexpr double kPowerFloor = 1e-3;

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

/// Real spherical harmonics of every degree up to `degree` at the unit vector
/// d, orthonormal up to one constant factor (the fully normalised associated
/// Legendre recursion), ACN order. Only their span matters here: the
/// products of two order-N harmonics are functions of degree 2N, which the
/// joint fit below writes in this basis.
void sh_basis(int degree, const Vec3& d, double* out) {
  const auto L = static_cast<std::size_t>(degree);
  const double z = std::clamp(d[2], -1.0, 1.0), s = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = std::atan2(d[1], d[0]);
  std::vector<double> p((L + 1) * (L + 1), 0.0);  // p[l * (L + 1) + m]
  const auto at = [&](std::size_t l, std::size_t m) -> double& { return p[l * (L + 1) + m]; };
  at(0, 0) = 1.0;
  for (std::size_t m = 1; m <= L; ++m) at(m, m) = std::sqrt((2.0 * double(m) + 1.0) / (2.0 * double(m))) * s * at(m - 1, m - 1);
  for (std::size_t m = 0; m < L; ++m) at(m + 1, m) = std::sqrt(2.0 * double(m) + 3.0) * z * at(m, m);
  for (std::size_t m = 0; m <= L; ++m)
    for (std::size_t l = m + 2; l <= L; ++l) {
      const double ll = double(l), mm = double(m);
      const double a = std::sqrt((4.0 * ll * ll - 1.0) / (ll * ll - mm * mm));
      const double b = std::sqrt(((ll - 1.0) * (ll - 1.0) - mm * mm) / (4.0 * (ll - 1.0) * (ll - 1.0) - 1.0));
      at(l, m) = a * (z * at(l - 1, m) - b * at(l - 2, m));
    }
  for (int l = 0; l <= degree; ++l)
    for (int m = -l; m <= l; ++m) {
      const auto am = static_cast<std::size_t>(m < 0 ? -m : m);
      const double v = at(static_cast<std::size_t>(l), am);
      out[acn(l, m)] = m == 0 ? v : std::sqrt(2.0) * v * (m > 0 ? std::cos(double(m) * phi) : std::sin(double(am) * phi));
    }
}

/// Limited-memory BFGS (two-loop recursion, Armijo backtracking) on f, which
/// returns the value at x and writes the gradient. Stops after `iterations`
/// or when the value no longer moves. Returns the value at the x it leaves.
double minimise_lbfgs(const std::function<double(const Eigen::VectorXd&, Eigen::VectorXd&)>& f, Eigen::VectorXd& x,
                      int iterations, std::size_t memory = 12) {
  Eigen::VectorXd g(x.size()), g_new(x.size()), x_new(x.size()), d(x.size());
  double fx = f(x, g);
  std::deque<Eigen::VectorXd> ss, ys;
  std::deque<double> rhos;
  int still = 0;
  for (int it = 0; it < iterations; ++it) {
    // d = -H g (two-loop recursion)
    d = -g;
    std::vector<double> alpha(ss.size());
    for (std::size_t i = ss.size(); i-- > 0;) {
      alpha[i] = rhos[i] * ss[i].dot(d);
      d -= alpha[i] * ys[i];
    }
    if (!ss.empty()) d *= ss.back().dot(ys.back()) / ys.back().squaredNorm();
    for (std::size_t i = 0; i < ss.size(); ++i) d += ss[i] * (alpha[i] - rhos[i] * ys[i].dot(d));
    double slope = g.dot(d);
    if (!(slope < 0.0)) {
      ss.clear(), ys.clear(), rhos.clear();
      d = -g;
      slope = -g.squaredNorm();
    }
    double step = ss.empty() ? std::min(1.0, 1.0 / std::max(1e-12, g.lpNorm<Eigen::Infinity>())) : 1.0;
    double f_new = fx;
    bool moved = false;
    for (int k = 0; k < 40; ++k, step *= 0.5) {
      x_new = x + step * d;
      f_new = f(x_new, g_new);
      if (std::isfinite(f_new) && f_new <= fx + 1e-4 * step * slope) {
        moved = true;
        break;
      }
    }
    if (!moved) break;
    Eigen::VectorXd s_k = x_new - x, y_k = g_new - g;
    const double sy = s_k.dot(y_k);
    if (sy > 1e-12 * s_k.norm() * y_k.norm()) {
      ss.push_back(std::move(s_k)), ys.push_back(std::move(y_k)), rhos.push_back(1.0 / sy);
      if (ss.size() > memory) ss.pop_front(), ys.pop_front(), rhos.pop_front();
    }
    still = fx - f_new < 1e-9 * std::max(1.0, std::abs(fx)) ? still + 1 : 0;
    x.swap(x_new), g.swap(g_new), fx = f_new;
    if (still >= 5) break;
  }
  return fx;
}

/// What the joint fit of the two ears weighs (docs/AMBISONICS.md, "The
/// decoder", has the figures behind each choice).
constexpr double kBandErrorSoftDb = 0.5;    // a band's level error r (dB) costs sqrt(r^2 + 0.5^2) ...
constexpr double kBandErrorSquare = 0.05;   // ... + 0.05 r^2: large errors more than linearly
constexpr double kHorizontalWeight = 1.0;   // the horizontal measurements count 1 + 1 times their cell
constexpr double kIldScaleDb = 0.2;         // an ILD error e costs log(1 + (e / 0.2 dB)^2) ...
constexpr double kIldLimitDb = 1.0;         // ... + 300 (|e| - limit)^2 beyond a limit: MagLS's error
constexpr double kIldFloorDb = 0.5;         //     there, at least 0.5 dB, at most 1 dB
constexpr double kLevelLimitDb = 1.0;       // an ear's level error beyond max(MagLS's, 1 dB): 300 x its square
constexpr double kLimitWeight = 300.0;
constexpr double kMixRegularisation = 1e-3;  // x |K - K0|^2 (whitened, below)
constexpr int kJointIterations = 200;

/// The joint fit of the two ears (DecoderDesign::joint_ear_fit): per ear e
/// and standard third-octave band b in `bands` (above the transition and
/// 1.5 kHz), a real C x C mix M_eb of the channels' filters,
/// d_e(k) <- M_eb d_e(k) for the band's bins. A band's energy from direction
/// q is then y_q' M S M' y_q, S = Re sum_k d d^H over the band: every energy
/// pattern a linear order-N decoder can give the band is reachable, and each
/// bin's phase and the band's detail within it stay MagLS's. The mixes
/// minimise, all at once (the constants above):
///   mean over ears, bands and measurements (quadrature weights, the
///     horizontal ones 1 + kHorizontalWeight times) of
///     sqrt(r^2 + 0.5^2) + 0.05 r^2, r the band's level error in dB;
///   + level_weight x mean over the horizontal measurements and ears of the
///     broadband (white-noise) level error in dB, squared, and 300 x the
///     square of what exceeds max(MagLS's error there, 1 dB);
///   + ild_weight x mean over the horizontal measurements of
///     log(1 + (ILD error / 0.2 dB)^2), and 300 x the square of what exceeds
///     min(1 dB, max(MagLS's error there, 0.5 dB));
///   + 1e-3 x |K - K0|^2 (the whitened variables below: stay near MagLS).
/// The band energies are linear in A = M S M', whose entries multiply
/// products of two harmonics of order N, functions of degree 2N: so
/// P = Z T vech(A), Z a degree-2N basis at the measurements and T fitted
/// once on a grid (exactly), and an evaluation costs (2N + 1)^2 per
/// direction instead of C^2. L-BFGS, kJointIterations steps.
void fit_ears_jointly(const hrtf::HrtfSet& set, int order, const DecoderDesign& design, const Eigen::MatrixXd& Y,
                      const std::vector<double>& w, const Eigen::MatrixXcd (&H)[2], Eigen::MatrixXcd (&D)[2],
                      const std::vector<std::size_t>& bands) {
  using Eigen::Index;
  const Index Q = Y.rows(), C = Y.cols();
  const auto NB = static_cast<Index>(bands.size() - 1);
  const Index EB = 2 * NB;
  constexpr double k10 = 10.0 / std::numbers::ln10;

  // The horizontal measurements: where the ILD is measured.
  std::vector<Index> horiz;
  for (Index q = 0; q < Q; ++q)
    if (std::abs(set.direction(static_cast<std::size_t>(q)).elevation) < 1e-6) horiz.push_back(q);
  const auto J = static_cast<Index>(horiz.size());

  // Products of harmonics in the degree-2N basis: Phi(d) = Zbasis(d) T.
  const int deg2 = 2 * order;
  const auto R = static_cast<Index>((deg2 + 1) * (deg2 + 1));
  const Index Mp = C * (C + 1) / 2;
  std::vector<std::pair<Index, Index>> pairs;
  for (Index c = 0; c < C; ++c)
    for (Index c2 = c; c2 < C; ++c2) pairs.emplace_back(c, c2);
  Eigen::MatrixXd T;
  {
    const Index G = 4 * R;
    Eigen::MatrixXd Zg(G, R), Pg(G, Mp);
    std::vector<double> y(static_cast<std::size_t>(C)), z_row(static_cast<std::size_t>(R));
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (Index i = 0; i < G; ++i) {
      const double z = 1.0 - (2.0 * double(i) + 1.0) / double(G), r = std::sqrt(std::max(0.0, 1.0 - z * z));
      const Vec3 d{r * std::cos(golden * double(i)), r * std::sin(golden * double(i)), z};
      sh_basis(deg2, d, z_row.data());
      for (Index k = 0; k < R; ++k) Zg(i, k) = z_row[static_cast<std::size_t>(k)];
      real_sh(order, d, std::span<double>(y));
      for (Index p = 0; p < Mp; ++p) {
        const auto [a, b] = pairs[static_cast<std::size_t>(p)];
        Pg(i, p) = (a == b ? 1.0 : 2.0) * y[static_cast<std::size_t>(a)] * y[static_cast<std::size_t>(b)];
      }
    }
    T = (Zg.transpose() * Zg).ldlt().solve(Zg.transpose() * Pg);  // R x Mp
  }
  Eigen::MatrixXd Zq(Q, R);
  {
    Eigen::VectorXd row(R);
    for (Index q = 0; q < Q; ++q) {
      const auto dir = set.direction(static_cast<std::size_t>(q));
      sh_basis(deg2, ambix_from_sofa(dir.azimuth, dir.elevation), row.data());
      Zq.row(q) = row.transpose();
    }
  }

  // The bands' channel covariances, the measured band energies, and what
  // lies below the transition (fixed: LS) in the horizontal ears' energies.
  std::vector<Eigen::MatrixXd> S(static_cast<std::size_t>(EB));
  Eigen::MatrixXd Href(EB, Q), floor_p(EB, 1);
  Eigen::VectorXd band_on(EB);
  double wsum = 0.0;
  for (double v : w) wsum += v;
  Eigen::VectorXd omega(Q);
  for (Index q = 0; q < Q; ++q) omega(q) = w[static_cast<std::size_t>(q)];
  for (Index j : horiz) omega(j) *= 1.0 + kHorizontalWeight;
  omega /= omega.sum();
  double loudest = 0.0;
  for (Index e = 0; e < 2; ++e)
    for (Index b = 0; b < NB; ++b) {
      const Index eb = e * NB + b, k0 = static_cast<Index>(bands[static_cast<std::size_t>(b)]);
      const Index n = static_cast<Index>(bands[static_cast<std::size_t>(b) + 1]) - k0;
      const Eigen::MatrixXcd Db = D[e].middleCols(k0, n);
      S[static_cast<std::size_t>(eb)] = (Db * Db.adjoint()).real();
      Href.row(eb) = H[e].middleCols(k0, n).cwiseAbs2().rowwise().sum().transpose();
      double mean = 0.0;
      for (Index q = 0; q < Q; ++q) mean += w[static_cast<std::size_t>(q)] * Href(eb, q);
      mean /= wsum;
      floor_p(eb, 0) = kPowerFloor * mean;
      band_on(eb) = mean / double(n);  // per bin, for the check below
      loudest = std::max(loudest, band_on(eb));
    }
  Index bands_on = 0;
  for (Index eb = 0; eb < EB; ++eb) {
    // A band 40 dB (per bin) below the loudest is left out of the spectral
    // term (KEMAR above 23.8 kHz): its level errors say nothing.
    band_on(eb) = band_on(eb) >= 1e-4 * loudest ? 1.0 : 0.0;
    bands_on += band_on(eb) > 0.0;
  }
  Eigen::MatrixXd Elow(J, 2), Eref(J, 2);
  Eigen::VectorXd ild_ref(J);
  for (Index j = 0; j < J; ++j)
    for (Index e = 0; e < 2; ++e) {
      const Eigen::RowVectorXcd yq = Y.row(horiz[static_cast<std::size_t>(j)]).cast<cd>();
      Elow(j, e) = (yq * D[e].leftCols(static_cast<Index>(bands.front()))).cwiseAbs2().sum();
      Eref(j, e) = H[e].row(horiz[static_cast<std::size_t>(j)]).cwiseAbs2().sum();
    }
  for (Index j = 0; j < J; ++j) ild_ref(j) = k10 * std::log(Eref(j, 0) / Eref(j, 1));

  // The variables, per ear and band: K with A = K K' (band energies in
  // units of the band's mean channel power s), started at K0 = U L^(1/2) for
  // S / s = U L U' (M = I); eigen-directions below 1e-9 of the largest carry
  // nothing and are left out. Whitened so, every variable moves energy on
  // the same scale and L-BFGS converges in a few hundred steps where the raw
  // mixes M took thousands (the channels' powers span decades).
  std::vector<Eigen::MatrixXd> K0(static_cast<std::size_t>(EB)), back(static_cast<std::size_t>(EB));
  std::vector<double> scale(static_cast<std::size_t>(EB));
  std::vector<Index> offset(static_cast<std::size_t>(EB) + 1, 0);
  for (Index eb = 0; eb < EB; ++eb) {
    const auto i = static_cast<std::size_t>(eb);
    scale[i] = std::max(S[i].trace() / double(C), 1e-300);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S[i] / scale[i]);
    const Eigen::VectorXd lam = es.eigenvalues().cwiseMax(0.0);
    Index kept = 0;  // the eigenvalues ascend: the largest `kept` are the last
    for (Index c = 0; c < C; ++c) kept += lam(c) > 1e-9 * lam(C - 1);
    K0[i] = es.eigenvectors().rightCols(kept) * lam.tail(kept).cwiseSqrt().asDiagonal();
    back[i] = lam.tail(kept).cwiseSqrt().cwiseInverse().asDiagonal() * es.eigenvectors().rightCols(kept).transpose();
    offset[i + 1] = offset[i] + C * kept;
  }

  // Each ear's broadband level error at the horizontal measurements may
  // grow to max(MagLS's there, 1 dB) and not beyond (a hinge like the
  // ILD's): the ILD is not bought with a level error MagLS did not have.
  Eigen::MatrixXd level_limit = Eigen::MatrixXd::Constant(J, 2, kLevelLimitDb);
  Eigen::VectorXd ild_limit = Eigen::VectorXd::Constant(J, kIldLimitDb);
  const auto objective = [&](const Eigen::VectorXd& x, Eigen::VectorXd& grad) -> double {
    grad.setZero(x.size());
    Eigen::MatrixXd gP = Eigen::MatrixXd::Zero(EB, Q), Avec(Mp, EB);
    for (Index eb = 0; eb < EB; ++eb) {
      const auto i = static_cast<std::size_t>(eb);
      const Eigen::Map<const Eigen::MatrixXd> Kb(x.data() + offset[i], C, K0[i].cols());
      const Eigen::MatrixXd A = scale[i] * (Kb * Kb.transpose());
      for (Index p = 0; p < Mp; ++p) Avec(p, eb) = A(pairs[static_cast<std::size_t>(p)].first, pairs[static_cast<std::size_t>(p)].second);
    }
    const Eigen::MatrixXd P = (Zq * (T * Avec)).transpose();  // EB x Q
    double value = 0.0;
    // Band spectra.
    for (Index eb = 0; eb < EB; ++eb) {
      if (band_on(eb) == 0.0) continue;
      for (Index q = 0; q < Q; ++q) {
        const double p = std::max(P(eb, q), 1e-6 * floor_p(eb, 0));
        const double r = k10 * std::log(p / std::max(Href(eb, q), floor_p(eb, 0)));
        const double s = std::sqrt(r * r + kBandErrorSoftDb * kBandErrorSoftDb);
        value += omega(q) * (s + kBandErrorSquare * r * r) / double(bands_on);
        gP(eb, q) = omega(q) * (r / s + 2.0 * kBandErrorSquare * r) * k10 / p / double(bands_on);
      }
    }
    // Each ear's broadband level and the ILD at the horizontal measurements.
    if (J > 0) {
      Eigen::MatrixXd E = Elow, gE = Eigen::MatrixXd::Zero(J, 2);
      for (Index j = 0; j < J; ++j)
        for (Index e = 0; e < 2; ++e)
          for (Index b = 0; b < NB; ++b) E(j, e) += std::max(0.0, P(e * NB + b, horiz[static_cast<std::size_t>(j)]));
      for (Index j = 0; j < J; ++j) {
        for (Index e = 0; e < 2; ++e) {
          const double lev = k10 * std::log(E(j, e) / Eref(j, e));
          const double lev_over = std::max(0.0, std::abs(lev) - level_limit(j, e));
          value += (design.level_weight * lev * lev + kLimitWeight * lev_over * lev_over) / double(2 * J);
          gE(j, e) += (design.level_weight * 2.0 * lev + kLimitWeight * 2.0 * lev_over * (lev < 0 ? -1.0 : 1.0)) /
                      double(2 * J) * k10 / E(j, e);
        }
        const double err = k10 * std::log(E(j, 0) / E(j, 1)) - ild_ref(j);
        const double over = std::max(0.0, std::abs(err) - ild_limit(j));
        value += design.ild_weight * (std::log1p(err * err / (kIldScaleDb * kIldScaleDb)) + kLimitWeight * over * over) /
                 double(J);
        const double g = design.ild_weight *
                         (2.0 * err / (kIldScaleDb * kIldScaleDb + err * err) + kLimitWeight * 2.0 * over * (err < 0 ? -1.0 : 1.0)) /
                         double(J);
        gE(j, 0) += g * k10 / E(j, 0);
        gE(j, 1) -= g * k10 / E(j, 1);
      }
      for (Index j = 0; j < J; ++j)
        for (Index e = 0; e < 2; ++e)
          for (Index b = 0; b < NB; ++b) gP(e * NB + b, horiz[static_cast<std::size_t>(j)]) += gE(j, e);
    }
    // Back to the variables.
    Eigen::MatrixXd GA(C, C);
    const Eigen::MatrixXd gAvec = T.transpose() * (Zq.transpose() * gP.transpose());  // Mp x EB
    for (Index eb = 0; eb < EB; ++eb) {
      const auto i = static_cast<std::size_t>(eb);
      const Eigen::Map<const Eigen::MatrixXd> Kb(x.data() + offset[i], C, K0[i].cols());
      Eigen::Map<Eigen::MatrixXd> gK(grad.data() + offset[i], C, K0[i].cols());
      const auto ga = scale[i] * gAvec.col(eb);
      for (Index p = 0; p < Mp; ++p) {
        const auto [c1, c2] = pairs[static_cast<std::size_t>(p)];
        if (c1 == c2)
          GA(c1, c1) = ga(p);
        else
          GA(c1, c2) = GA(c2, c1) = 0.5 * ga(p);
      }
      gK = 2.0 * GA * Kb;
      const Eigen::MatrixXd dK = Kb - K0[i];
      value += kMixRegularisation * dK.squaredNorm();
      gK += 2.0 * kMixRegularisation * dK;
    }
    return value;
  };

  Eigen::VectorXd x(offset.back());
  for (Index eb = 0; eb < EB; ++eb) {
    const auto i = static_cast<std::size_t>(eb);
    Eigen::Map<Eigen::MatrixXd>(x.data() + offset[i], C, K0[i].cols()) = K0[i];
  }
  if (J > 0) {
    // MagLS's levels: the band energies at the start (K = K0) and below.
    Eigen::MatrixXd E = Elow;
    for (Index e = 0; e < 2; ++e)
      for (Index b = 0; b < NB; ++b) {
        const auto i = static_cast<std::size_t>(e * NB + b);
        for (Index j = 0; j < J; ++j) {
          const Eigen::RowVectorXd y = Y.row(horiz[static_cast<std::size_t>(j)]);
          E(j, e) += y * S[i] * y.transpose();
        }
      }
    for (Index j = 0; j < J; ++j)
      for (Index e = 0; e < 2; ++e)
        level_limit(j, e) = std::max(kLevelLimitDb, std::abs(k10 * std::log(E(j, e) / Eref(j, e))));
    for (Index j = 0; j < J; ++j)
      ild_limit(j) = std::min(kIldLimitDb, std::max(kIldFloorDb, std::abs(k10 * std::log(E(j, 0) / E(j, 1)) - ild_ref(j))));
  }
  (void)minimise_lbfgs(objective, x, kJointIterations);
  // The mixes: M = K L^(-1/2) U', so M S M' = s K K'.
  for (Index e = 0; e < 2; ++e)
    for (Index b = 0; b < NB; ++b) {
      const auto i = static_cast<std::size_t>(e * NB + b);
      const Eigen::Map<const Eigen::MatrixXd> Kb(x.data() + offset[i], C, K0[i].cols());
      const Eigen::MatrixXd M = Kb * back[i];
      const Index k0 = static_cast<Index>(bands[static_cast<std::size_t>(b)]);
      const Index n = static_cast<Index>(bands[static_cast<std::size_t>(b) + 1]) - k0;
      D[e].middleCols(k0, n) = (M.cast<cd>() * D[e].middleCols(k0, n)).eval();
    }
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

DecoderFilters design_binaural_decoder(const hrtf::HrtfSet& set, int order, const DecoderDesign& design) {
  if (order < 1 || order > kMaxOrder)
    throw std::invalid_argument("design_binaural_decoder: order " + std::to_string(order) + " outside 1.." +
                                std::to_string(kMaxOrder));
  const std::size_t Q = set.measurement_count(), C = channel_count(order);
  if (Q < C)
    throw std::invalid_argument("design_binaural_decoder: " + std::to_string(Q) + " measurements cannot determine " +
                                std::to_string(C) + " channels");
  const double rate = set.sample_rate();

  // Sizes: the filters with their delays fit in `length`; the design runs
  // at twice that, so what MagLS's phase continuation puts before time zero
  // or late lands in the half that is cut off, not on the filters.
  double max_delay = 0.0;
  for (std::size_t q = 0; q < Q; ++q)
    max_delay = std::max({max_delay, set.delays(q).left_s * rate, set.delays(q).right_s * rate});
  const std::size_t length =
      design.length ? design.length : std::bit_ceil(set.filter_length() + static_cast<std::size_t>(std::ceil(max_delay)));
  const std::size_t nfft = 2 * std::bit_ceil(std::max(length, set.filter_length() + static_cast<std::size_t>(std::ceil(max_delay))));
  const std::size_t bins = nfft / 2 + 1;
  const double bin_hz = rate / double(nfft);

  // SH matrix, quadrature, regularised weighted pseudo-inverse G (C x Q).
  Eigen::MatrixXd Y(Q, C);
  {
    std::vector<double> y(C);
    for (std::size_t q = 0; q < Q; ++q) {
      real_sh(order, ambix_from_sofa(set.direction(q).azimuth, set.direction(q).elevation), std::span<double>(y));
      for (std::size_t c = 0; c < C; ++c) Y(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(c)) = y[c];
    }
  }
  const std::vector<double> w = sphere_quadrature(set);
  double wsum = 0.0;
  for (double v : w) wsum += v;
  Eigen::VectorXd wv = Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(Q));
  Eigen::MatrixXd A = Y.transpose() * wv.asDiagonal() * Y;
  const double mu = design.regularisation * A.trace() / double(C);
  A.diagonal().array() += mu;
  const Eigen::MatrixXd Gr = A.ldlt().solve(Y.transpose() * wv.asDiagonal());
  const Eigen::MatrixXcd G = Gr.cast<cd>();
  const Eigen::MatrixXcd Yc = Y.cast<cd>();

  // HRTFs: each measured filter played at its delay, as the direct renderer does.
  Eigen::MatrixXcd H[2] = {Eigen::MatrixXcd(Q, bins), Eigen::MatrixXcd(Q, bins)};
  {
    audio::RealFft fft(nfft);
    std::vector<float> x(nfft);
    std::vector<std::complex<float>> X(bins);
    for (std::size_t q = 0; q < Q; ++q)
      for (std::size_t e = 0; e < 2; ++e) {
        const auto f = set.filter(q, static_cast<hrtf::Ear>(e));
        std::fill(x.begin(), x.end(), 0.0f);
        std::copy(f.begin(), f.end(), x.begin());
        fft.forward(x, X);
        const double tau = (e == 0 ? set.delays(q).left_s : set.delays(q).right_s) * rate;
        for (std::size_t k = 0; k < bins; ++k)
          H[e](static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(k)) =
              cd(X[k]) * std::polar(1.0, -2.0 * std::numbers::pi * double(k) * tau / double(nfft));
      }
  }

  // Each ear's typical delay: the quadrature-weighted mean over directions
  // of the energy centroid of its response (filter at its delay). MagLS's
  // phase above the transition runs on from the previous bin with this
  // group delay, so the high band sits where the responses' energy is
  // instead of around time zero (half of it wrapping to the end).
  double group_delay[2] = {0.0, 0.0};
  for (std::size_t e = 0; e < 2; ++e) {
    for (std::size_t q = 0; q < Q; ++q) {
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

  const double fc = design.method == DecoderMethod::ls ? rate : transition_hz_for(design, order);
  const auto kc = std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(fc / bin_hz)), 1, bins);
  const auto Kc = static_cast<Eigen::Index>(kc), Qi = static_cast<Eigen::Index>(Q);
  Eigen::MatrixXcd D[2] = {Eigen::MatrixXcd(C, bins), Eigen::MatrixXcd(C, bins)};
  for (std::size_t e = 0; e < 2; ++e) D[e].leftCols(Kc) = G * H[e].leftCols(Kc);

  if (kc < bins) {
    // Above the transition: per third-octave band and ear, a weighted LS fit
    // of magnitudes (DecoderDesign::shadow_weighting).
    const std::vector<std::size_t> bands = band_starts(kc, bins, bin_hz);
    Eigen::VectorXcd t(Qi), reproduced(Qi);
    const cd step[2] = {std::polar(1.0, -2.0 * std::numbers::pi * group_delay[0] / double(nfft)),
                        std::polar(1.0, -2.0 * std::numbers::pi * group_delay[1] / double(nfft))};
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
          Eigen::MatrixXd Ab = Y.transpose() * v.asDiagonal() * Y;
          Ab.diagonal().array() += design.regularisation * Ab.trace() / double(C);
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
    // The joint fit starts above the ITD's band too: below 1.5 kHz each
    // bin's interaural phase is what the ITD is heard (and measured) from,
    // and a mix there moved order 2's ITD by 0.85 ms.
    const auto k_itd = static_cast<std::size_t>(std::ceil(kItdBandHz / bin_hz));
    if (design.joint_ear_fit && std::max(kc, k_itd) < bins)
      fit_ears_jointly(set, order, design, Y, w, H, D, standard_third_octaves(std::max(kc, k_itd), bins, bin_hz));
  }

  if (design.diffuse_covariance && kc < bins) {
    // Diffuse field: SN3D channel covariance diag(1 / (2l + 1)).
    Eigen::VectorXd cdiag(C);
    for (std::size_t c = 0; c < C; ++c) cdiag(static_cast<Eigen::Index>(c)) = 1.0 / (2.0 * degree_of(c) + 1.0);
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

  // Real filters: DC and Nyquist real, back to time, cut to `length` with a
  // short fade at the end.
  DecoderFilters out;
  out.order = order;
  out.sample_rate = rate;
  out.length = length;
  out.taps.assign(2 * C * length, 0.0f);
  audio::RealFft fft(nfft);
  std::vector<std::complex<float>> S(bins);
  std::vector<float> x(nfft);
  const std::size_t fade = std::min<std::size_t>(32, length / 4);
  for (std::size_t e = 0; e < 2; ++e)
    for (std::size_t c = 0; c < C; ++c) {
      for (std::size_t k = 0; k < bins; ++k) {
        cd v = D[e](static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(k));
        if (k == 0 || k + 1 == bins) v = cd(v.real(), 0.0);
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
