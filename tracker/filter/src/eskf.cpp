#include "earshot/tracker/filter/eskf.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "earshot/tracker/solve/lm_refine.hpp"
#include "earshot/tracker/solve/small_cholesky.hpp"

namespace earshot::tracker {
namespace {

constexpr double kMaxScale = kMaxManoeuvreScale;

// Pixel coordinates behind a pose: four dots, two each.
constexpr double kCoordinates = 8.0;
// A numerical bound only: the velocity's own uncertainty keeps the predicted
// dot speed away from zero (a head held still for a second: rho ~ 0.9).
constexpr double kMaxCorrelation = 0.999;
// The NIS beyond which a differenced measurement is taken for a cell
// crossing (see eskf.hpp).
constexpr double kDifferencedNis = 6.0;
// The motion model's consistency: the NIS's running mean over this long
// must stay within its expectation (its dimension) for the correlated model.
constexpr double kNisAverageS = 1.0;
constexpr double kConsistentNis = 6.0;

// Adaptive process noise (eskf.hpp). Each block's NIS is chi^2(3), mean 3;
// a sample counts at most its 99.9 % point.
constexpr double kBlockDof = 3.0;
constexpr double kBlockNisClip = 16.0;
// The scales span the literature q to the manoeuvre test's first step.
constexpr double kManoeuvreStep = 10.0;
constexpr double kMaxAdaptiveScale = kManoeuvreStep;
// How far the innovations' lag-one correlation must exceed the
// quantisation's for the scale to rise: ~7 standard deviations of a 1-s
// mean of white innovations' (sqrt(0.005 / 3) ~ 0.04 at 100 Hz). 0.1 and
// 0.2 on the tuning seeds let 8-px rows' scales rise on measurement noise.
constexpr double kLagMargin = 0.3;
// The correlated-quantisation model wants the literature's motion model.
constexpr double kQuietScale = 1.5;
// The persistence test (eskf.hpp): the weight of each whitened rotation
// innovation in their running mean (a memory of ~3 frames), and chi^2(3)'s
// 99.9 % point for that mean, scaled to unit variance. On the tuning seeds
// weights 0.15-0.3 and thresholds 11.3-16.3 gave the same within 0.01.
constexpr double kPersistenceWeight = 0.3;
constexpr double kPersistenceChi2 = 16.27;

}  // namespace

Mat12 eskf_transition(const Mat3& exp_w_dt, double dt) {
  Mat12 F = Mat12::Identity();
  F.block<3, 3>(0, 0) = exp_w_dt;  // exp(w dt) exp(d) R = exp(exp(w dt) d) exp(w dt) R
  F.block<3, 3>(0, 6) = dt * Mat3::Identity();
  F.block<3, 3>(3, 9) = dt * Mat3::Identity();
  return F;
}

namespace {

/// F P F^T for the transition above without the dense 12x12 products: F is
/// the identity but for the rotation block and two dt blocks.
Mat12 propagate(const Mat12& P, const Mat3& A, double dt) {
  Mat12 G = P;  // F P: block rows
  G.middleRows<3>(0) = A * P.middleRows<3>(0) + dt * P.middleRows<3>(6);
  G.middleRows<3>(3) += dt * P.middleRows<3>(9);
  Mat12 out = G;  // (F P) F^T: block columns
  out.middleCols<3>(0) = G.middleCols<3>(0) * A.transpose() + dt * G.middleCols<3>(6);
  out.middleCols<3>(3) += dt * G.middleCols<3>(9);
  return out;
}

using detail::cholesky;
using detail::Cholesky;
using detail::forward_solve;
using detail::mahalanobis2;

/// Symmetric inverse: Cholesky when it works, else LDLT's (semi-definite).
template <int N>
Eigen::Matrix<double, N, N> sym_inverse(const Eigen::Matrix<double, N, N>& A) {
  Cholesky<N> f;
  if (cholesky<N>(A, f)) return detail::inverse<N>(f);
  return A.ldlt().solve(Eigen::Matrix<double, N, N>::Identity());
}

/// Adds the process noise of white acceleration (spectral densities qa, ql)
/// over dt to P: per axis [dt^3/3, dt^2/2; dt^2/2, dt] q, on the diagonals of
/// the (angle, angular velocity) and (position, velocity) blocks.
void add_process_noise(Mat12& P, double qa, double ql, double dt) {
  const double a = dt * dt * dt / 3.0, b = dt * dt / 2.0;
  for (int i = 0; i < 3; ++i) {
    P(i, i) += qa * a;
    P(i, 6 + i) += qa * b;
    P(6 + i, i) += qa * b;
    P(6 + i, 6 + i) += qa * dt;
    P(3 + i, 3 + i) += ql * a;
    P(3 + i, 9 + i) += ql * b;
    P(9 + i, 3 + i) += ql * b;
    P(9 + i, 9 + i) += ql * dt;
  }
}

/// One 3 x 3 block of S judged alone: its innovation x whitened (L^-1 x for
/// A = L L^T; zero when A is not positive definite: no evidence either way)
/// and x^T A^-1 x, its NIS (|L^-1 x|^2, or the semi-definite LDLT solve).
struct BlockEvidence {
  Vec3 whitened = Vec3::Zero();
  double nis = 0.0;
};
BlockEvidence block_evidence(const Mat3& A, const Vec3& x) {
  Cholesky<3> f;
  if (cholesky<3>(A, f)) {
    const Vec3 u = forward_solve<3>(f, x);
    return {u, u.squaredNorm()};
  }
  return {Vec3::Zero(), x.dot(A.ldlt().solve(x))};
}

/// The pose an error (dtheta, dp) away from x.
Pose inject(const Pose& x, const Vec3& dtheta, const Vec3& dp) { return {exp_so3(dtheta) * x.R, x.t + dp}; }

}  // namespace

Mat6 pose_covariance(const Pose& pose, std::span<const Correspondence> dots, const Camera& cam,
                     const LedModel& model, double pixel_variance) {
  Mat6 H = Mat6::Zero();
  for (const auto& d : dots) {
    const auto J = reprojection_jacobian(pose, model.leds_mm[static_cast<size_t>(d.led)], cam);
    H.noalias() += J.transpose() * J;
  }
  return pose_covariance_from_jtj(H, pixel_variance);
}

Mat6 pose_covariance_from_jtj(Mat6 jtj, double pixel_variance) {
  // A whisker of regularisation (1e-9 of the largest diagonal entry) keeps a
  // degenerate three-dot geometry invertible: its weak directions come out
  // with a huge variance, which is what they have.
  jtj.diagonal().array() += 1e-9 * jtj.diagonal().maxCoeff() + 1e-300;
  return pixel_variance * sym_inverse<6>(jtj);
}

double quantisation_correlation(double cells_per_frame) {
  const double r = cells_per_frame;
  if (!(r < 0.5)) return 0.0;  // NaN too
  if (!(r > 0.0)) return kMaxCorrelation;
  return std::clamp(1.0 - 6.0 * r * (1.0 - r), 0.0, kMaxCorrelation);
}

double quantisation_inflation(double cells_per_frame) {
  const double rho = quantisation_correlation(cells_per_frame);
  return (1.0 + rho) / (1.0 - rho);
}

void PixelNoiseEstimator::add(double sum_sq_px, int dots) {
  if (dots < 4 || !std::isfinite(sum_sq_px)) return;
  const double sample = sum_sq_px / static_cast<double>(2 * dots - 6);
  ++n_;
  const double a = n_ <= 200 ? 1.0 / static_cast<double>(n_) : 1.0 / 200.0;
  var_ += a * (sample - var_);
}

void PoseEskf::start(const Pose& z, const Mat6& cov, double t) {
  x_ = z;
  have_u_prev_ = false;
  m_rot_.setZero();
  nis_avg_ = 6.0;
  z_prev_ = z;
  have_z_prev_ = true;
  rho_ = 0.0;
  differenced_ = false;
  w_.setZero();
  v_.setZero();
  P_.setZero();
  P_.topLeftCorner<6, 6>() = cov;
  // Velocity unknown: the spread of head speeds (~200 deg/s, ~500 mm/s).
  P_.block<3, 3>(6, 6) = std::pow(200.0 * M_PI / 180.0, 2) * Mat3::Identity();
  P_.block<3, 3>(9, 9) = 500.0 * 500.0 * Mat3::Identity();
  t_ = t;
  have_ = true;
  rejected_run_ = 0;
  nis_ = 0.0;
  q_scale_ = 1.0;
  rejected_ = false;
  step_.t = t;
  step_.pose_pred = step_.pose_upd = z;
  step_.w_pred = step_.w_upd = w_;
  step_.v_pred = step_.v_upd = v_;
  step_.P_pred = step_.P_upd = P_;
  step_.rotation = Mat3::Identity();
  step_.dt = 0.0;
  step_.restart = true;
}

/// What one update carries from step to step: the innovation's covariance
/// (and its factor), the NIS, and the process noise that explained it.
struct PoseEskf::Innovation {
  Mat6 S;
  Cholesky<6> L;
  bool factored = false;
  double nis = 0.0, scale = 1.0, q_rot = 0.0, q_trans = 0.0;
  /// The measurement as fused: H P and its innovation y (z itself: the pose
  /// rows of P_pred and nu; the differenced measurement otherwise).
  Eigen::Matrix<double, 6, 12> HP;
  Eigen::Matrix<double, 6, 1> y;
};

Pose PoseEskf::update(const Pose& z, const Mat6& cov, double t) {
  const double dt = t - t_;
  if (!have_ || !(dt > 0.0) || dt > p_.max_gap_s || !cov.allFinite()) {
    start(z, cov, t);
    return x_;
  }
  const Mat3 A = exp_so3(w_ * dt);
  const Pose x_pred{A * x_.R, x_.t + v_ * dt};
  const double qa = lambda_rot_ * p_.angular_accel_psd, ql = lambda_trans_ * p_.linear_accel_psd;
  const Mat12 FPF = propagate(P_, A, dt);

  Eigen::Matrix<double, 6, 1> nu;
  nu.head<3>() = log_so3(z.R * x_pred.R.transpose());
  nu.tail<3>() = z.t - x_pred.t;

  Innovation in = explain(FPF, cov, nu, dt, qa, ql);
  Mat12 P_pred = FPF;
  add_process_noise(P_pred, in.q_rot, in.q_trans, dt);
  // The correlated model leans on the motion model for longer; that is only
  // right while the motion model is as good as it claims: the NIS averaged
  // over the last second no more than its expectation, the dimension 6 (a
  // time-averaged NIS test of Bar-Shalom, Li & Kirubarajan, "Estimation with
  // Applications to Tracking and Navigation", 2001). Seated heads keep it at
  // 4-5 on 8-px pixels; the default walk at 9-11 and walking, whose 2 Hz bob
  // is beyond the constant-velocity model's q, at 17-29.
  nis_avg_ += std::min(1.0, dt / kNisAverageS) * (std::min(in.nis, p_.manoeuvre_chi2) - nis_avg_);
  quant_rho_ = predicted_quantisation_correlation(cov, dt);
  const bool quiet = lambda_rot_ <= kQuietScale && lambda_trans_ <= kQuietScale;
  const double rho = p_.correlated_quantisation && nis_avg_ <= kConsistentNis && quiet ? quant_rho_ : 0.0;
  in.HP = P_pred.topRows<6>();
  in.y = nu;
  const bool differenced = rho > 0.0 && fuse_correlated(in, P_pred, cov, x_pred, nu, rho, dt);
  rho_ = rho;
  differenced_ = differenced;
  nis_ = in.nis;
  q_scale_ = in.scale;
  step_.t = t;
  step_.pose_pred = x_pred;
  step_.w_pred = w_;
  step_.v_pred = v_;
  step_.P_pred = P_pred;
  step_.rotation = A;
  step_.dt = dt;
  step_.q_rot = in.q_rot;
  step_.q_trans = in.q_trans;
  step_.restart = false;

  if (!(in.nis <= p_.outlier_chi2)) return skip(z, cov, t, x_pred, FPF, qa, ql, dt);
  rejected_ = false;
  rejected_run_ = 0;
  z_prev_ = z;
  have_z_prev_ = true;
  adapt(dt);
  correct(in, P_pred, x_pred, t);
  return x_;
}

PoseEskf::Innovation PoseEskf::explain(const Mat12& FPF, const Mat6& cov, const Eigen::Matrix<double, 6, 1>& nu,
                                       double dt, double qa, double ql) {
  // The smallest process-noise scale that explains the measurement: the
  // adaptive q first, then 10, 100, 1000 times the literature's (never less
  // than the adaptive one). Only the pose block of P_pred enters S: the
  // process noise there is diagonal, q dt^3 / 3 per axis.
  const double dt3 = dt * dt * dt / 3.0;
  bool persistent = false;
  Innovation in;
  in.q_rot = qa;
  in.q_trans = ql;
  for (in.scale = 1.0; in.scale <= kMaxScale; in.scale *= kManoeuvreStep) {
    in.q_rot = std::max(qa, in.scale * p_.angular_accel_psd);
    in.q_trans = std::max(ql, in.scale * p_.linear_accel_psd);
    if (in.scale > 1.0 && in.q_rot == qa && in.q_trans == ql) continue;  // no larger than the adaptive q: tried
    in.S = FPF.topLeftCorner<6, 6>() + cov;
    in.S.diagonal().head<3>().array() += in.q_rot * dt3;
    in.S.diagonal().tail<3>().array() += in.q_trans * dt3;
    in.factored = cholesky<6>(in.S, in.L);
    in.nis = in.factored ? mahalanobis2<6>(in.L, nu) : nu.dot(in.S.ldlt().solve(nu));
    if (in.scale == 1.0) {  // the blocks' evidence for the adaptive scales, at the q the model claims
      const BlockEvidence rot = block_evidence(in.S.topLeftCorner<3, 3>(), nu.head<3>());
      const BlockEvidence trans = block_evidence(in.S.bottomRightCorner<3, 3>(), nu.tail<3>());
      nis_rot_ = rot.nis;
      nis_trans_ = trans.nis;
      u_rot_ = rot.whitened;
      u_trans_ = trans.whitened;
      persistent = p_.persistence_test && rotation_persists();
    }
    if (in.nis <= p_.manoeuvre_chi2 && !(in.scale == 1.0 && persistent)) break;
  }
  in.scale = std::min(in.scale, kMaxScale);
  return in;
}

double PoseEskf::predicted_quantisation_correlation(const Mat6& cov, double dt) const {
  // The dots' predicted speed in quantisation cells (eskf.hpp): with
  // cov = sigma^2 (J^T J)^-1 and sigma^2 = Delta^2 / 12, the pose step
  // d = (w dt, v dt) moves the dots by u = J d, |u|^2 / Delta^2 =
  // d^T cov^-1 d / 12, sqrt(d^T cov^-1 d / (12 * 8)) per coordinate (RMS).
  // The velocity's uncertainty adds dt^2 tr(cov^-1 P_vel) to the expected
  // d^T cov^-1 d: a filter unsure of the speed does not take the dots for still.
  // The correlation is predicted whether or not the correlated model may
  // use it: the adaptive scales compare the innovations' own with it.
  if (!p_.correlated_quantisation && !p_.adaptive_process_noise) return 0.0;
  Cholesky<6> Lc;
  if (!cholesky<6>(cov, Lc)) return 0.0;
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = w_ * dt;
  d.tail<3>() = v_ * dt;
  const double m2 =
      mahalanobis2<6>(Lc, d) + dt * dt * detail::inverse<6>(Lc).cwiseProduct(P_.bottomRightCorner<6, 6>()).sum();
  return quantisation_correlation(std::sqrt(m2 / (12.0 * kCoordinates)));
}

bool PoseEskf::fuse_correlated(Innovation& in, const Mat12& P_pred, const Mat6& cov, const Pose& x_pred,
                               const Eigen::Matrix<double, 6, 1>& nu, double rho, double dt) const {
  if (have_z_prev_ && in.scale == 1.0) {
    // z_(k-1) in the error coordinates at x_pred: x_(k-1) = x_k - (w, v) dt
    // to first order, so z_(k-1) [-] x_pred + (w, v) dt = dx_pose - dt dx_vel + e_(k-1).
    Eigen::Matrix<double, 6, 1> zeta;
    zeta.head<3>() = log_so3(z_prev_.R * x_pred.R.transpose()) + w_ * dt;
    zeta.tail<3>() = z_prev_.t - x_pred.t + v_ * dt;
    const Eigen::Matrix<double, 6, 1> yd = nu - rho * zeta;
    const Eigen::Matrix<double, 6, 12> HPd = (1.0 - rho) * P_pred.topRows<6>() + (rho * dt) * P_pred.bottomRows<6>();
    const Mat6 HPHd = (1.0 - rho) * HPd.leftCols<6>() + (rho * dt) * HPd.rightCols<6>();
    const Mat6 Sd = Mat6(0.5 * (HPHd + HPHd.transpose())) + (1.0 - rho * rho) * cov;
    Cholesky<6> Ld;
    Ld.L.setZero();  // its upper triangle is never written, and the factor is copied whole
    if (cholesky<6>(Sd, Ld) && mahalanobis2<6>(Ld, yd) <= kDifferencedNis) {
      in.S = Sd;
      in.L = Ld;
      in.factored = true;
      in.HP = HPd;
      in.y = yd;
      return true;
    }
  }
  // z itself, worth 1 / kappa of a white measurement: S's cov becomes kappa cov
  in.S += ((1.0 + rho) / (1.0 - rho) - 1.0) * cov;
  in.factored = cholesky<6>(in.S, in.L);
  return false;
}

Pose PoseEskf::skip(const Pose& z, const Mat6& cov, double t, const Pose& x_pred, const Mat12& FPF, double qa,
                    double ql, double dt) {
  // No head motion explains it: skip the measurement.
  rejected_ = true;
  have_z_prev_ = false;  // the next measurement has no neighbour to be differenced with
  have_u_prev_ = false;  // nor innovation to be correlated with
  if (++rejected_run_ >= 3) {
    start(z, cov, t);
    return x_;
  }
  x_ = x_pred;
  P_ = FPF;  // the model's own uncertainty, not the inflated one tried
  add_process_noise(P_, qa, ql, dt);
  step_.P_pred = P_;
  step_.q_rot = qa;
  step_.q_trans = ql;
  t_ = t;
  step_.pose_upd = x_;
  step_.w_upd = w_;
  step_.v_upd = v_;
  step_.P_upd = P_;
  return x_;
}

void PoseEskf::correct(const Innovation& in, Mat12& P_pred, const Pose& x_pred, double t) {
  // With S = L L^T: K = P H^T S^-1 = B^T L^-1 for B = L^-1 (H P) (6 x 12);
  // the correction K y = B^T (L^-1 y) and P = P_pred - K H P_pred =
  // P_pred - B^T B, symmetric by construction.
  Vec12 dx;
  if (in.factored) {
    Eigen::Matrix<double, 6, 12> B;
    for (int c = 0; c < 12; ++c) B.col(c) = forward_solve<6>(in.L, Eigen::Matrix<double, 6, 1>(in.HP.col(c)));
    const Eigen::Matrix<double, 6, 1> Ly = forward_solve<6>(in.L, in.y);
    dx.noalias() = B.transpose() * Ly;
    for (int j = 0; j < 12; ++j)
      for (int i = j; i < 12; ++i) P_pred(i, j) -= B.col(i).dot(B.col(j));
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < j; ++i) P_pred(i, j) = P_pred(j, i);
    P_ = P_pred;
  } else {  // S only semi-definite: its LDLT inverse
    const Mat6 S_inv = sym_inverse<6>(in.S);
    const Eigen::Matrix<double, 12, 6> PHt = in.HP.transpose();
    const Eigen::Matrix<double, 12, 6> K = PHt.lazyProduct(S_inv);
    dx.noalias() = K * in.y;
    P_ = P_pred - K.lazyProduct(PHt.transpose());
    P_ = Mat12(0.5 * (P_ + P_.transpose()));  // a temporary: no aliasing through the transpose
  }
  x_ = inject(x_pred, dx.segment<3>(0), dx.segment<3>(3));
  w_ += dx.segment<3>(6);
  v_ += dx.segment<3>(9);
  t_ = t;
  step_.pose_upd = x_;
  step_.w_upd = w_;
  step_.v_upd = v_;
  step_.P_upd = P_;
}

void PoseEskf::hand_through(const Pose& z, const Mat6& cov) {
  if (!have_ || !cov.allFinite()) return;
  x_ = z;
  const Mat6 vel = P_.bottomRightCorner<6, 6>();
  P_.setZero();
  P_.topLeftCorner<6, 6>() = cov;
  P_.bottomRightCorner<6, 6>() = vel;
  // As at a start: the velocity's spread at least the spread of head speeds.
  for (int i = 0; i < 3; ++i) {
    P_(6 + i, 6 + i) = std::max(P_(6 + i, 6 + i), std::pow(200.0 * M_PI / 180.0, 2));
    P_(9 + i, 9 + i) = std::max(P_(9 + i, 9 + i), 500.0 * 500.0);
  }
  have_z_prev_ = false;  // the next measurement is not differenced against this one
  have_u_prev_ = false;
  m_rot_.setZero();
  step_.pose_upd = x_;
  step_.P_upd = P_;
}

Pose guard(PoseEskf& eskf, const Pose& filtered, const Pose& z, const Mat6& cov, double chi2) {
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = log_so3(filtered.R * z.R.transpose());
  d.tail<3>() = filtered.t - z.t;
  if (eskf.last_rejected() || d.dot(cov.ldlt().solve(d)) <= chi2) return filtered;
  eskf.hand_through(z, cov);
  return z;
}

std::optional<Pose> PoseEskf::predict(double t) const {
  if (!have_) return std::nullopt;
  const double dt = std::max(0.0, t - t_);
  return Pose{exp_so3(w_ * dt) * x_.R, x_.t + v_ * dt};
}

std::optional<Mat6> PoseEskf::predicted_pose_covariance(double t) const {
  if (!have_) return std::nullopt;
  const double dt = std::max(0.0, t - t_);
  const Mat6 Pxv = P_.block<6, 6>(0, 6);
  Mat6 S = P_.topLeftCorner<6, 6>() + dt * (Pxv + Pxv.transpose()) + (dt * dt) * P_.bottomRightCorner<6, 6>();
  const double dt3 = dt * dt * dt / 3.0;
  S.diagonal().head<3>().array() += lambda_rot_ * p_.angular_accel_psd * dt3;
  S.diagonal().tail<3>().array() += lambda_trans_ * p_.linear_accel_psd * dt3;
  return S;
}

bool PoseEskf::rotation_persists() const {
  // The running mean of white unit innovations has variance a / (2 - a) per
  // axis; errors correlated by the quantisation (the last step's rho) widen
  // it by up to kappa, but by no more than the mean's memory, 2 / a.
  const double a = kPersistenceWeight;
  const Vec3 m = (1.0 - a) * m_rot_ + a * u_rot_;
  const double kappa = std::min((1.0 + quant_rho_) / (1.0 - quant_rho_), 2.0 / a);
  return m.squaredNorm() * (2.0 - a) / a > kPersistenceChi2 * kappa;
}

void PoseEskf::adapt(double dt) {
  m_rot_ = (1.0 - kPersistenceWeight) * m_rot_ + kPersistenceWeight * u_rot_;
  const double g = std::min(1.0, dt / p_.adaptation_s);
  // The whitened innovations' lag-one correlation: 0 for an optimal filter,
  // positive when it lags (or when the quantisation correlates the errors).
  auto correlate = [&](double& mean, const Vec3& u, const Vec3& u_prev) {
    if (have_u_prev_) mean += g * (std::clamp(u.dot(u_prev) / kBlockDof, -2.0, 2.0) - mean);
  };
  correlate(lag_corr_rot_, u_rot_, u_rot_prev_);
  correlate(lag_corr_trans_, u_trans_, u_trans_prev_);
  u_rot_prev_ = u_rot_;
  u_trans_prev_ = u_trans_;
  have_u_prev_ = true;
  if (!p_.adaptive_process_noise) return;
  // log lambda follows (NIS / 3 - 1) / T: a stochastic approximation of
  // E[NIS] = 3, rising only on persistent (lagging) innovations.
  auto follow = [&](double& lambda, double nis, double lag_corr) {
    double e = std::min(nis, kBlockNisClip) / kBlockDof - 1.0;
    if (lag_corr <= quant_rho_ + kLagMargin) e = std::min(e, 0.0);
    lambda = std::clamp(lambda * std::exp(g * e), 1.0, kMaxAdaptiveScale);
  };
  follow(lambda_rot_, nis_rot_, lag_corr_rot_);
  follow(lambda_trans_, nis_trans_, lag_corr_trans_);
}

void RtsSmoother::add(const EskfStep& step) {
  if (nodes_.empty() || step.restart) {
    if (!segs_.empty()) {  // the open segment ends at the step before this one
      segs_.back().last = nodes_.size() - 1;
      segs_.back().end = last_end();
    }
    EskfSegment seg;
    seg.first = nodes_.size();
    seg.t_first = step.t;
    seg.first_pose = step.pose_upd;
    seg.first_cov = step.P_upd.topLeftCorner<6, 6>();
    segs_.push_back(seg);
  }
  if (!nodes_.empty() && !step.restart) {
    // C = P_upd(k) F^T P_pred(k+1)^-1, the gain from step k+1 back to k.
    const Mat12 C = last_P_upd_ * eskf_transition(step.rotation, step.dt).transpose() * sym_inverse<12>(step.P_pred);
    nodes_.back().gain = C.cast<float>();
  }
  Node n;
  n.pose_pred = step.pose_pred;
  n.pose_upd = step.pose_upd;
  n.w_pred = step.w_pred;
  n.v_pred = step.v_pred;
  n.w_upd = step.w_upd;
  n.v_upd = step.v_upd;
  n.restart = step.restart;
  nodes_.push_back(n);
  last_P_upd_ = step.P_upd;
  last_t_ = step.t;
}

EskfStep RtsSmoother::last_end() const {
  EskfStep e;
  e.t = last_t_;
  e.pose_upd = nodes_.back().pose_upd;
  e.w_upd = nodes_.back().w_upd;
  e.v_upd = nodes_.back().v_upd;
  e.P_upd = last_P_upd_;
  return e;
}

std::vector<EskfSegment> RtsSmoother::segments() const {
  std::vector<EskfSegment> out = segs_;
  if (!out.empty()) {
    out.back().last = nodes_.size() - 1;
    out.back().end = last_end();
  }
  return out;
}

std::vector<Pose> RtsSmoother::smooth() const {
  const size_t n = nodes_.size();
  std::vector<Pose> out(n);
  if (n == 0) return out;
  // Smoothed state of step k+1, walking backwards. Only the mean is carried:
  // the output is poses, and the smoothed covariance does not feed the mean.
  Pose xs = nodes_[n - 1].pose_upd;
  Vec3 ws = nodes_[n - 1].w_upd, vs = nodes_[n - 1].v_upd;
  out[n - 1] = xs;
  for (size_t k = n - 1; k-- > 0;) {
    const Node& cur = nodes_[k];
    const Node& nxt = nodes_[k + 1];
    if (nxt.restart) {  // no model links k to k+1: the filter's answer stands
      xs = cur.pose_upd;
      ws = cur.w_upd;
      vs = cur.v_upd;
      out[k] = xs;
      continue;
    }
    Vec12 d;
    d.segment<3>(0) = log_so3(xs.R * nxt.pose_pred.R.transpose());
    d.segment<3>(3) = xs.t - nxt.pose_pred.t;
    d.segment<3>(6) = ws - nxt.w_pred;
    d.segment<3>(9) = vs - nxt.v_pred;
    const Vec12 dx = cur.gain.cast<double>() * d;
    xs = inject(cur.pose_upd, dx.segment<3>(0), dx.segment<3>(3));
    ws = cur.w_upd + dx.segment<3>(6);
    vs = cur.v_upd + dx.segment<3>(9);
    out[k] = xs;
  }
  return out;
}

std::vector<Pose> rts_smooth(std::span<const EskfStep> steps) {
  RtsSmoother s;
  s.reserve(steps.size());
  for (const auto& st : steps) s.add(st);
  return s.smooth();
}

double ou_displacement_variance(double q, double tau, double dt) {
  const double x = dt / tau;
  return 0.5 * q * tau * tau * tau * (2.0 * x - 3.0 + 4.0 * std::exp(-x) - std::exp(-2.0 * x));
}

CarriedPose carry_ou(const EskfStep& st, double t, const OuMotion& m) {
  const double dt = std::max(0.0, t - st.t);
  // The mean velocity decays as exp(-dt / tau): the displacement is v tau (1 - exp(-dt / tau)).
  const double kr = m.tau_rot_s * (1.0 - std::exp(-dt / m.tau_rot_s));
  const double kt = m.tau_trans_s * (1.0 - std::exp(-dt / m.tau_trans_s));
  CarriedPose c;
  c.pose = Pose{exp_so3(st.w_upd * kr) * st.pose_upd.R, st.pose_upd.t + st.v_upd * kt};
  Eigen::Matrix<double, 6, 12> A = Eigen::Matrix<double, 6, 12>::Zero();
  A.leftCols<6>().setIdentity();
  A.block<3, 3>(0, 6) = kr * Mat3::Identity();
  A.block<3, 3>(3, 9) = kt * Mat3::Identity();
  c.spread = A * st.P_upd * A.transpose();
  c.spread.diagonal().head<3>().array() += ou_displacement_variance(m.q_rot, m.tau_rot_s, dt);
  c.spread.diagonal().tail<3>().array() += ou_displacement_variance(m.q_trans, m.tau_trans_s, dt);
  return c;
}

}  // namespace earshot::tracker
