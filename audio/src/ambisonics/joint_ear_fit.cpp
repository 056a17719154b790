#include "joint_ear_fit.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <deque>
#include <functional>
#include <numbers>
#include <span>
#include <utility>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"

namespace earshot::ambisonics::design_detail {
namespace {

using cd = std::complex<double>;
using Eigen::Index;
constexpr double k10 = 10.0 / std::numbers::ln10;

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
class JointEarFit {
 public:
  JointEarFit(const hrtf::HrtfSet& set, int order, const DecoderDesign& design, const Eigen::MatrixXd& Y,
              const std::vector<double>& w, const Eigen::MatrixXcd (&H)[2], const Eigen::MatrixXcd (&D)[2],
              const std::vector<std::size_t>& bands)
      : design_(design), bands_(bands), C_(Y.cols()), NB_(static_cast<Index>(bands.size() - 1)), EB_(2 * NB_) {
    find_horizontal(set, Y.rows());
    fit_product_basis(order);
    measurement_basis(set, Y.rows());
    band_statistics(w, H, D, Y.rows());
    horizontal_energies(Y, H, D);
    whiten();
  }

  /// Runs the fit and writes the mixes into D.
  void run(const Eigen::MatrixXd& Y, Eigen::MatrixXcd (&D)[2]) {
    Eigen::VectorXd x = start();
    if (J_ > 0) magls_limits(Y);
    (void)minimise_lbfgs([this](const Eigen::VectorXd& v, Eigen::VectorXd& g) { return objective(v, g); }, x,
                         kJointIterations);
    apply(x, D);
  }

 private:
  /// The horizontal measurements: where the ILD is measured.
  void find_horizontal(const hrtf::HrtfSet& set, Index Q) {
    for (Index q = 0; q < Q; ++q)
      if (std::abs(set.direction(static_cast<std::size_t>(q)).elevation) < 1e-6) horiz_.push_back(q);
    J_ = static_cast<Index>(horiz_.size());
  }

  /// Products of harmonics in the degree-2N basis: Phi(d) = Zbasis(d) T,
  /// fitted once on a Fibonacci grid of 4 R points (exactly).
  void fit_product_basis(int order) {
    deg2_ = 2 * order;
    R_ = static_cast<Index>((deg2_ + 1) * (deg2_ + 1));
    Mp_ = C_ * (C_ + 1) / 2;
    for (Index c = 0; c < C_; ++c)
      for (Index c2 = c; c2 < C_; ++c2) pairs_.emplace_back(c, c2);
    const Index G = 4 * R_;
    Eigen::MatrixXd Zg(G, R_), Pg(G, Mp_);
    std::vector<double> y(static_cast<std::size_t>(C_)), z_row(static_cast<std::size_t>(R_));
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (Index i = 0; i < G; ++i) {
      const double z = 1.0 - (2.0 * double(i) + 1.0) / double(G), r = std::sqrt(std::max(0.0, 1.0 - z * z));
      const Vec3 d{r * std::cos(golden * double(i)), r * std::sin(golden * double(i)), z};
      sh_basis(deg2_, d, z_row.data());
      for (Index k = 0; k < R_; ++k) Zg(i, k) = z_row[static_cast<std::size_t>(k)];
      real_sh(order, d, std::span<double>(y));
      for (Index p = 0; p < Mp_; ++p) {
        const auto [a, b] = pairs_[static_cast<std::size_t>(p)];
        Pg(i, p) = (a == b ? 1.0 : 2.0) * y[static_cast<std::size_t>(a)] * y[static_cast<std::size_t>(b)];
      }
    }
    T_ = (Zg.transpose() * Zg).ldlt().solve(Zg.transpose() * Pg);  // R x Mp
  }

  /// The degree-2N basis at the measurements.
  void measurement_basis(const hrtf::HrtfSet& set, Index Q) {
    Zq_.resize(Q, R_);
    Eigen::VectorXd row(R_);
    for (Index q = 0; q < Q; ++q) {
      const auto dir = set.direction(static_cast<std::size_t>(q));
      sh_basis(deg2_, ambix_from_sofa(dir.azimuth, dir.elevation), row.data());
      Zq_.row(q) = row.transpose();
    }
  }

  /// The bands' channel covariances, the measured band energies, and the
  /// measurements' weights (the horizontal ones 1 + kHorizontalWeight times).
  void band_statistics(const std::vector<double>& w, const Eigen::MatrixXcd (&H)[2], const Eigen::MatrixXcd (&D)[2],
                       Index Q) {
    S_.resize(static_cast<std::size_t>(EB_));
    Href_.resize(EB_, Q);
    floor_p_.resize(EB_, 1);
    band_on_.resize(EB_);
    double wsum = 0.0;
    for (double v : w) wsum += v;
    omega_.resize(Q);
    for (Index q = 0; q < Q; ++q) omega_(q) = w[static_cast<std::size_t>(q)];
    for (Index j : horiz_) omega_(j) *= 1.0 + kHorizontalWeight;
    omega_ /= omega_.sum();
    double loudest = 0.0;
    for (Index e = 0; e < 2; ++e)
      for (Index b = 0; b < NB_; ++b) {
        const Index eb = e * NB_ + b, k0 = static_cast<Index>(bands_[static_cast<std::size_t>(b)]);
        const Index n = static_cast<Index>(bands_[static_cast<std::size_t>(b) + 1]) - k0;
        const Eigen::MatrixXcd Db = D[e].middleCols(k0, n);
        S_[static_cast<std::size_t>(eb)] = (Db * Db.adjoint()).real();
        Href_.row(eb) = H[e].middleCols(k0, n).cwiseAbs2().rowwise().sum().transpose();
        double mean = 0.0;
        for (Index q = 0; q < Q; ++q) mean += w[static_cast<std::size_t>(q)] * Href_(eb, q);
        mean /= wsum;
        floor_p_(eb, 0) = kPowerFloor * mean;
        band_on_(eb) = mean / double(n);  // per bin, for the check below
        loudest = std::max(loudest, band_on_(eb));
      }
    for (Index eb = 0; eb < EB_; ++eb) {
      // A band 40 dB (per bin) below the loudest is left out of the spectral
      // term (KEMAR above 23.8 kHz): its level errors say nothing.
      band_on_(eb) = band_on_(eb) >= 1e-4 * loudest ? 1.0 : 0.0;
      bands_on_ += band_on_(eb) > 0.0;
    }
  }

  /// At the horizontal measurements: each ear's energy below the first band
  /// (fixed: LS, MagLS), the measured energies and the measured ILD.
  void horizontal_energies(const Eigen::MatrixXd& Y, const Eigen::MatrixXcd (&H)[2], const Eigen::MatrixXcd (&D)[2]) {
    Elow_.resize(J_, 2);
    Eref_.resize(J_, 2);
    ild_ref_.resize(J_);
    for (Index j = 0; j < J_; ++j)
      for (Index e = 0; e < 2; ++e) {
        const Eigen::RowVectorXcd yq = Y.row(horiz_[static_cast<std::size_t>(j)]).cast<cd>();
        Elow_(j, e) = (yq * D[e].leftCols(static_cast<Index>(bands_.front()))).cwiseAbs2().sum();
        Eref_(j, e) = H[e].row(horiz_[static_cast<std::size_t>(j)]).cwiseAbs2().sum();
      }
    for (Index j = 0; j < J_; ++j) ild_ref_(j) = k10 * std::log(Eref_(j, 0) / Eref_(j, 1));
  }

  /// The variables, per ear and band: K with A = K K' (band energies in
  /// units of the band's mean channel power s), started at K0 = U L^(1/2) for
  /// S / s = U L U' (M = I); eigen-directions below 1e-9 of the largest carry
  /// nothing and are left out. Whitened so, every variable moves energy on
  /// the same scale and L-BFGS converges in a few hundred steps where the raw
  /// mixes M took thousands (the channels' powers span decades).
  void whiten() {
    K0_.resize(static_cast<std::size_t>(EB_));
    back_.resize(static_cast<std::size_t>(EB_));
    scale_.resize(static_cast<std::size_t>(EB_));
    offset_.assign(static_cast<std::size_t>(EB_) + 1, 0);
    for (Index eb = 0; eb < EB_; ++eb) {
      const auto i = static_cast<std::size_t>(eb);
      scale_[i] = std::max(S_[i].trace() / double(C_), 1e-300);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S_[i] / scale_[i]);
      const Eigen::VectorXd lam = es.eigenvalues().cwiseMax(0.0);
      Index kept = 0;  // the eigenvalues ascend: the largest `kept` are the last
      for (Index c = 0; c < C_; ++c) kept += lam(c) > 1e-9 * lam(C_ - 1);
      K0_[i] = es.eigenvectors().rightCols(kept) * lam.tail(kept).cwiseSqrt().asDiagonal();
      back_[i] = lam.tail(kept).cwiseSqrt().cwiseInverse().asDiagonal() * es.eigenvectors().rightCols(kept).transpose();
      offset_[i + 1] = offset_[i] + C_ * kept;
    }
    level_limit_ = Eigen::MatrixXd::Constant(J_, 2, kLevelLimitDb);
    ild_limit_ = Eigen::VectorXd::Constant(J_, kIldLimitDb);
  }

  /// The starting point: K = K0 (MagLS's mixes, M = I).
  [[nodiscard]] Eigen::VectorXd start() const {
    Eigen::VectorXd x(offset_.back());
    for (Index eb = 0; eb < EB_; ++eb) {
      const auto i = static_cast<std::size_t>(eb);
      Eigen::Map<Eigen::MatrixXd>(x.data() + offset_[i], C_, K0_[i].cols()) = K0_[i];
    }
    return x;
  }

  /// Each ear's broadband level error at the horizontal measurements may
  /// grow to max(MagLS's there, 1 dB) and not beyond (a hinge like the
  /// ILD's): the ILD is not bought with a level error MagLS did not have.
  /// MagLS's levels: the band energies at the start (K = K0) and below.
  void magls_limits(const Eigen::MatrixXd& Y) {
    Eigen::MatrixXd E = Elow_;
    for (Index e = 0; e < 2; ++e)
      for (Index b = 0; b < NB_; ++b) {
        const auto i = static_cast<std::size_t>(e * NB_ + b);
        for (Index j = 0; j < J_; ++j) {
          const Eigen::RowVectorXd y = Y.row(horiz_[static_cast<std::size_t>(j)]);
          E(j, e) += y * S_[i] * y.transpose();
        }
      }
    for (Index j = 0; j < J_; ++j)
      for (Index e = 0; e < 2; ++e)
        level_limit_(j, e) = std::max(kLevelLimitDb, std::abs(k10 * std::log(E(j, e) / Eref_(j, e))));
    for (Index j = 0; j < J_; ++j)
      ild_limit_(j) = std::min(kIldLimitDb, std::max(kIldFloorDb, std::abs(k10 * std::log(E(j, 0) / E(j, 1)) - ild_ref_(j))));
  }

  /// The cost at x and its gradient (terms in the order of the comment above).
  double objective(const Eigen::VectorXd& x, Eigen::VectorXd& grad) const {
    grad.setZero(x.size());
    Eigen::MatrixXd gP = Eigen::MatrixXd::Zero(EB_, Zq_.rows());
    const Eigen::MatrixXd P = band_energies(x);
    double value = 0.0;
    add_band_spectra(P, value, gP);
    if (J_ > 0) add_horizontal_levels(P, value, gP);
    add_to_variables(x, gP, value, grad);
    return value;
  }

  /// Every band's energy at every measurement for the mixes x (EB x Q).
  [[nodiscard]] Eigen::MatrixXd band_energies(const Eigen::VectorXd& x) const {
    Eigen::MatrixXd Avec(Mp_, EB_);
    for (Index eb = 0; eb < EB_; ++eb) {
      const auto i = static_cast<std::size_t>(eb);
      const Eigen::Map<const Eigen::MatrixXd> Kb(x.data() + offset_[i], C_, K0_[i].cols());
      const Eigen::MatrixXd A = scale_[i] * (Kb * Kb.transpose());
      for (Index p = 0; p < Mp_; ++p) Avec(p, eb) = A(pairs_[static_cast<std::size_t>(p)].first, pairs_[static_cast<std::size_t>(p)].second);
    }
    return (Zq_ * (T_ * Avec)).transpose();
  }

  /// The band spectra's level errors.
  void add_band_spectra(const Eigen::MatrixXd& P, double& value, Eigen::MatrixXd& gP) const {
    const Index Q = P.cols();
    for (Index eb = 0; eb < EB_; ++eb) {
      if (band_on_(eb) == 0.0) continue;
      for (Index q = 0; q < Q; ++q) {
        const double p = std::max(P(eb, q), 1e-6 * floor_p_(eb, 0));
        const double r = k10 * std::log(p / std::max(Href_(eb, q), floor_p_(eb, 0)));
        const double s = std::sqrt(r * r + kBandErrorSoftDb * kBandErrorSoftDb);
        value += omega_(q) * (s + kBandErrorSquare * r * r) / double(bands_on_);
        gP(eb, q) = omega_(q) * (r / s + 2.0 * kBandErrorSquare * r) * k10 / p / double(bands_on_);
      }
    }
  }

  /// Each ear's broadband level and the ILD at the horizontal measurements.
  void add_horizontal_levels(const Eigen::MatrixXd& P, double& value, Eigen::MatrixXd& gP) const {
    Eigen::MatrixXd E = Elow_, gE = Eigen::MatrixXd::Zero(J_, 2);
    for (Index j = 0; j < J_; ++j)
      for (Index e = 0; e < 2; ++e)
        for (Index b = 0; b < NB_; ++b) E(j, e) += std::max(0.0, P(e * NB_ + b, horiz_[static_cast<std::size_t>(j)]));
    for (Index j = 0; j < J_; ++j) {
      for (Index e = 0; e < 2; ++e) {
        const double lev = k10 * std::log(E(j, e) / Eref_(j, e));
        const double lev_over = std::max(0.0, std::abs(lev) - level_limit_(j, e));
        value += (design_.level_weight * lev * lev + kLimitWeight * lev_over * lev_over) / double(2 * J_);
        gE(j, e) += (design_.level_weight * 2.0 * lev + kLimitWeight * 2.0 * lev_over * (lev < 0 ? -1.0 : 1.0)) /
                    double(2 * J_) * k10 / E(j, e);
      }
      const double err = k10 * std::log(E(j, 0) / E(j, 1)) - ild_ref_(j);
      const double over = std::max(0.0, std::abs(err) - ild_limit_(j));
      value += design_.ild_weight * (std::log1p(err * err / (kIldScaleDb * kIldScaleDb)) + kLimitWeight * over * over) /
               double(J_);
      const double g = design_.ild_weight *
                       (2.0 * err / (kIldScaleDb * kIldScaleDb + err * err) + kLimitWeight * 2.0 * over * (err < 0 ? -1.0 : 1.0)) /
                       double(J_);
      gE(j, 0) += g * k10 / E(j, 0);
      gE(j, 1) -= g * k10 / E(j, 1);
    }
    for (Index j = 0; j < J_; ++j)
      for (Index e = 0; e < 2; ++e)
        for (Index b = 0; b < NB_; ++b) gP(e * NB_ + b, horiz_[static_cast<std::size_t>(j)]) += gE(j, e);
  }

  /// The energies' gradient back to the variables, and the pull towards K0.
  void add_to_variables(const Eigen::VectorXd& x, const Eigen::MatrixXd& gP, double& value, Eigen::VectorXd& grad) const {
    Eigen::MatrixXd GA(C_, C_);
    const Eigen::MatrixXd gAvec = T_.transpose() * (Zq_.transpose() * gP.transpose());  // Mp x EB
    for (Index eb = 0; eb < EB_; ++eb) {
      const auto i = static_cast<std::size_t>(eb);
      const Eigen::Map<const Eigen::MatrixXd> Kb(x.data() + offset_[i], C_, K0_[i].cols());
      Eigen::Map<Eigen::MatrixXd> gK(grad.data() + offset_[i], C_, K0_[i].cols());
      const auto ga = scale_[i] * gAvec.col(eb);
      for (Index p = 0; p < Mp_; ++p) {
        const auto [c1, c2] = pairs_[static_cast<std::size_t>(p)];
        if (c1 == c2)
          GA(c1, c1) = ga(p);
        else
          GA(c1, c2) = GA(c2, c1) = 0.5 * ga(p);
      }
      gK = 2.0 * GA * Kb;
      const Eigen::MatrixXd dK = Kb - K0_[i];
      value += kMixRegularisation * dK.squaredNorm();
      gK += 2.0 * kMixRegularisation * dK;
    }
  }

  /// The mixes: M = K L^(-1/2) U', so M S M' = s K K'.
  void apply(const Eigen::VectorXd& x, Eigen::MatrixXcd (&D)[2]) const {
    for (Index e = 0; e < 2; ++e)
      for (Index b = 0; b < NB_; ++b) {
        const auto i = static_cast<std::size_t>(e * NB_ + b);
        const Eigen::Map<const Eigen::MatrixXd> Kb(x.data() + offset_[i], C_, K0_[i].cols());
        const Eigen::MatrixXd M = Kb * back_[i];
        const Index k0 = static_cast<Index>(bands_[static_cast<std::size_t>(b)]);
        const Index n = static_cast<Index>(bands_[static_cast<std::size_t>(b) + 1]) - k0;
        D[e].middleCols(k0, n) = (M.cast<cd>() * D[e].middleCols(k0, n)).eval();
      }
  }

  const DecoderDesign& design_;
  const std::vector<std::size_t>& bands_;
  Index C_, NB_, EB_;                       // channels, bands, ears x bands
  std::vector<Index> horiz_;                // the horizontal measurements
  Index J_ = 0;                             // how many
  int deg2_ = 0;                            // 2N: the degree of the products' basis
  Index R_ = 0, Mp_ = 0;                    // its size; channel pairs c <= c2
  std::vector<std::pair<Index, Index>> pairs_;
  Eigen::MatrixXd T_, Zq_;                  // pairs -> basis (R x Mp); basis at the measurements (Q x R)
  std::vector<Eigen::MatrixXd> S_;          // per ear and band: the channels' covariance
  Eigen::MatrixXd Href_, floor_p_;          // measured band energies (EB x Q); their floors
  Eigen::VectorXd band_on_, omega_;         // bands in the spectral term; measurement weights
  Index bands_on_ = 0;
  Eigen::MatrixXd Elow_, Eref_;             // horizontal: energy below the bands, measured energy (J x 2)
  Eigen::VectorXd ild_ref_;                 // horizontal: measured ILD
  std::vector<Eigen::MatrixXd> K0_, back_;  // per ear and band: start, K -> M
  std::vector<double> scale_;
  std::vector<Index> offset_;               // where each band's K starts in x
  Eigen::MatrixXd level_limit_;             // the hinges (J x 2, J)
  Eigen::VectorXd ild_limit_;
};

}  // namespace

void fit_ears_jointly(const hrtf::HrtfSet& set, int order, const DecoderDesign& design, const Eigen::MatrixXd& Y,
                      const std::vector<double>& w, const Eigen::MatrixXcd (&H)[2], Eigen::MatrixXcd (&D)[2],
                      const std::vector<std::size_t>& bands) {
  JointEarFit fit(set, order, design, Y, w, H, D, bands);
  fit.run(Y, D);
}

}  // namespace earshot::ambisonics::design_detail
