// An error-state Kalman filter for the head pose that knows each frame's
// uncertainty (`--filter eskf`).
//
// State: orientation R and position p (camera frame, mm) with their world-
// frame angular velocity w (rad/s) and velocity v (mm/s). The error state is
// 12-dimensional, [dtheta, dp, dw, dv], with R_true = exp([dtheta]x) R: the
// same left perturbation as the LM solver (lm_refine.hpp), so the LM's
// covariance is the measurement covariance as it stands.
//
// Motion model: constant angular and linear velocity driven by white
// acceleration noise of spectral density q (per axis; rad^2/s^3 and
// mm^2/s^3). q is not a knob per rig: it is a property of heads. An
// Ornstein-Uhlenbeck velocity of RMS s and correlation time tau has
// acceleration spectral density 2 s^2 / tau; a seated listener's exploring
// movements (RMS ~30 deg/s per axis, correlation ~0.5 s: Thurlow et al. 1967;
// Kim et al. 2013, "Head movements made by listeners in experimental and
// real-life listening activities", JAES 61:425) give q ~ 1 rad^2/s^3, and
// head translation (RMS ~50 mm/s, ~1 s) q ~ 5000 mm^2/s^3.
//
// Measurement: each frame's LM pose with covariance sigma^2 (J^T J)^-1 at
// the solution (pose_covariance below), sigma^2 the camera's pixel noise
// variance (1/12 px^2 for integer pixels, 64/12 for the thesis's 8-px
// quantisation): estimated online from the 4-dot residuals unless given
// (PixelNoiseEstimator). So the gain follows the beacon's geometry, the focal
// length, the distance and the quantisation by itself.
//
// Quantised pixels (quantisation_correlation below): a coordinate rounded to
// cells of width Delta has the error e = Q(x) - x, white and of variance
// Delta^2 / 12 only when x moves by much more than Delta between frames
// (Widrow & Kollar, "Quantization Noise", 2008). A dot moving
// r = v / Delta cells a frame shifts its error by r cells: for a random phase
// the sawtooth's correlation at a shift of f cells is 1 - 6 f (1 - f)
// (f mod 1), so from one frame to the next rho = 1 - 6 r (1 - r). A slow
// head (8-px cells at seated speeds, r ~ 0.05) reads the same cell for many
// frames, and a filter that takes each reading as new white noise averages
// little of the error away. The filter models the error as first order
// autoregressive with that rho, r its own prediction of the dots' speed in
// cells (read off cov and the velocity, see update: no camera, beacon or
// quantisation constant enters), and
//  - fuses the differenced measurement z_k - rho z_(k-1), whose error
//    e_k - rho e_(k-1) is white (Bryson & Henrikson, "Estimation using
//    sampled data containing sequentially correlated noise", J. Spacecraft
//    5:662, 1968): with H = [I 0] and the constant-velocity transition it
//    measures (1 - rho) x_k + rho dt v_k with covariance (1 - rho^2) cov,
//    i.e. mostly the velocity when rho ~ 1;
//  - but not when a dot has just crossed into another cell: the difference
//    then jumps by a cell, which the autoregressive model does not describe.
//    A differenced measurement whose NIS exceeds 6 (its dimension; on the
//    tuning seeds thresholds from 3 to 10 gave the same within 0.01 of the
//    limit) is replaced by z_k itself with covariance kappa cov,
//    kappa = (1 + rho) / (1 - rho): the variance of an AR(1) mean over many
//    frames against white noise's (the effective number of independent
//    samples, Bayley & Hammersley, JRSS Suppl. 8:184, 1946);
//  - and with no previous measurement (start, after a skipped one) or during
//    a manoeuvre (the velocity, hence r, is then in doubt) also z_k with
//    kappa cov;
//  - and all of it only while the motion model is consistent (the NIS's
//    mean over the last second at most 6, its expectation): the correlated
//    model leans on the motion model for longer, which helps a seated head
//    the constant-velocity model describes (mean NIS 4-5 on the tuning
//    walks) and hurts heads it does not (the default walk across the whole
//    box, 9-11; walking's 2 Hz bob, 17-29).
// Where rho <= 0 (r above 0.21 cells a frame: integer pixels at most head
// speeds) the error counts as white, as before. The gate below still uses
// cov itself: the correlation changes how much a measurement is believed,
// not how surprising it may be.
//
// Process noise that follows the head (adaptive_process_noise): the
// literature's q is a seated listener's. A listener who walks about moves
// more (the `walk` simulation: ~9x that translation q), and a filter whose q
// is too small trusts its model too long and lags. Each block of the error
// state, rotation and translation, has its own scale lambda on q, set from
// the innovation sequence (covariance matching: Mehra, "On the
// identification of variances and adaptive Kalman filtering", IEEE TAC
// 15:175, 1970; Mohamed & Schwarz, "Adaptive Kalman filtering for INS/GPS",
// J. Geodesy 73:193, 1999):
//  - the block's marginal NIS, nu_b^T S_bb^-1 nu_b, is chi^2(3), mean 3,
//    when the model is right. log lambda moves by (NIS_b / 3 - 1) dt / T
//    (T = adaptation_s, 1 s), which holds the NIS's mean at 3. A sample
//    counts at most 16 (chi^2(3)'s 99.9 % point): a manoeuvre or a stray
//    pose is the business of the tests below.
//  - A NIS above 3 may also mean a measurement noisier than its covariance
//    says (8-px pixels on the near-planar thesis beacon at 1.5 m: 1.4-1.75x
//    in the simulations), which more q does not fix: it only lets more noise
//    through. The two differ in time (Mehra 1970): a model that lags leaves
//    innovations that persist from frame to frame, noise leaves them white.
//    So lambda rises only while the whitened innovations' lag-one
//    correlation (1-s mean of u_k . u_(k-1) / 3) exceeds the correlation the
//    quantisation itself gives the errors (rho below, predicted whether or
//    not the correlated model is in use) by 0.3, about 7 standard deviations
//    of that mean for white innovations. It falls whenever the NIS is below 3.
//    In practice this condition, not the NIS, ends the rise on a walk: the
//    translation block's mean NIS falls from 8-9 to ~5 (held-out `walk`
//    seeds, lambda ~3.5 on average), so the NIS's 1-s mean stays above 6
//    there and the correlated-quantisation model stays off, as before.
//  - lambda stays between 1, the literature q (a still or seated head keeps
//    it), and 10, the manoeuvre test's first step: sustained faster motion
//    is the adaptation's, sudden accelerations the manoeuvre test's, which
//    still tries 10, 100 and 1000 times the literature q.
//  - The correlated-quantisation model (above) is used only while both
//    scales are below 1.5: it leans on the motion model, which a head that
//    moves more than the literature says does not deserve.
// Each step records the q it predicted with (EskfStep::q_rot, q_trans), and
// P_pred includes it, so the smoother uses what the filter used;
// predicted_pose_covariance() uses the current scales.
//
// Manoeuvres and outliers: the innovation's Mahalanobis distance (NIS, chi^2
// with 6 degrees of freedom) tells a measurement the model did not expect.
// When it exceeds manoeuvre_chi2 the filter first asks whether the head
// accelerated: it re-predicts with the process noise scaled up (x10 per try,
// up to x1000: a quick turn toward a sound reaches ~150 rad/s^2) and takes
// the smallest scale that explains the measurement. A measurement no scale
// explains (NIS beyond outlier_chi2 even then) is an outlier and is skipped;
// three in a row mean the model is wrong and the filter restarts from the
// measurement.
//
// A smooth turn's onset (minimum jerk: the acceleration rises over ~0.1 s)
// does not reach that NIS: the filter lags by a few sigma for the turn's
// whole length, and quick turns toward a sound were most of the eskf's
// error on the `orienting` profile (tuning seeds: 9 % of the frames, ~30 %
// of the squared error). What the lag leaves is innovations that keep their
// direction. So the rotation's whitened innovations u (as for the adaptive
// scales) are also averaged over ~3 frames (m <- 0.7 m + 0.3 u); when
// |m|^2 (2 - 0.3) / 0.3, chi^2(3) for white u, exceeds its 99.9 % point
// (16.3; times the quantisation's kappa, at most the mean's memory of
// 2 / 0.3 frames, where the errors themselves are correlated), the
// manoeuvre test starts at 10 times the literature q. Lowering the scales
// below 1 in the still phases instead (covariance matching both ways) was
// measured and made `orienting` worse (tuning, second beacon: 0.84 -> 0.99
// of the ML limit on integer pixels at a floor of 0.1): the still phases
// gained ~1 %, the turns lost more. The thresholds are far beyond chi^2(6)'s 99 % point (16.8)
// because the camera's errors are not Gaussian: with 8-px quantisation the
// Gaussian thresholds took ordinary quantisation errors for manoeuvres and
// made the filter worse than raw LM (tuning seeds, tests/bench/tracker_motion).
#pragma once

#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/correspondence.hpp"
#include "earshot/tracker/core/geometry.hpp"
#include "earshot/tracker/core/led_model.hpp"

namespace earshot::tracker {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

/// The largest process-noise scale the manoeuvre test tries, times the
/// literature q: q x 1000 ~ 1000 rad^2/s^3 covers a quick turn's ~150 rad/s^2
/// (0.87 rad/s of velocity change in a 10 ms frame) but not a pose that jumps
/// tens of degrees in one frame. The dot tracker's reachability test assumes
/// it too.
inline constexpr double kMaxManoeuvreScale = 1000.0;

struct EskfParams {
  double angular_accel_psd = 1.0;     ///< q, rad^2/s^3 per axis (see above)
  double linear_accel_psd = 5000.0;   ///< q, mm^2/s^3 per axis
  double manoeuvre_chi2 = 100.0;      ///< NIS beyond which larger process noise is tried
  double outlier_chi2 = 400.0;        ///< NIS beyond which, at every scale, a measurement is an outlier
  double max_gap_s = 0.25;            ///< a longer gap restarts the filter
  /// Model quantised pixels' error as correlated from frame to frame at the
  /// predicted dot speed (above); false takes it as white.
  bool correlated_quantisation = true;
  /// Scale q to the head's motion from the innovations (above); false keeps
  /// the literature q.
  bool adaptive_process_noise = true;
  double adaptation_s = 1.0;  ///< time constant of that scale and of its statistics
  /// Take rotation innovations that keep one direction for a few frames for
  /// a manoeuvre (above); false leaves that to the NIS alone.
  bool persistence_test = true;
};

/// The frame-to-frame correlation of the quantisation error of a coordinate
/// that moves `cells_per_frame` quantisation cells a frame, 1 - 6 r (1 - r),
/// where that is positive (r < (1 - 1/sqrt 3) / 2 ~ 0.21), else 0.
[[nodiscard]] double quantisation_correlation(double cells_per_frame);
/// (1 + rho) / (1 - rho) for that correlation: the factor by which a long
/// average of such errors is worse than of white errors of the same variance.
[[nodiscard]] double quantisation_inflation(double cells_per_frame);

/// Covariance (rad, mm; left perturbation (w, t)) of the least-squares pose
/// over these dots: pixel_variance * (J^T J)^-1.
[[nodiscard]] Mat6 pose_covariance(const Pose& pose, std::span<const Correspondence> dots, const Camera& cam,
                                   const LedModel& model, double pixel_variance);
/// The same from J^T J at the pose (LmResult::jtj), without differentiating again.
[[nodiscard]] Mat6 pose_covariance_from_jtj(Mat6 jtj, double pixel_variance);

/// The pixel noise variance, from the residuals of 4-dot solves (2 degrees of
/// freedom each: 8 residuals, 6 pose parameters). Starts at integer pixels'
/// 1/12 px^2; a running mean over the first 200 frames, then slowly tracking.
class PixelNoiseEstimator {
 public:
  /// One solve: the sum of squared residuals over `dots` dots.
  void add(double sum_sq_px, int dots);
  [[nodiscard]] double variance() const { return var_; }
  void reset() { *this = {}; }

 private:
  double var_ = 1.0 / 12.0;
  long n_ = 0;
};

/// The eskf's 12 x 12 error-state transition over dt for the constant-
/// velocity model, its rotation block `rotation` = exp(w dt).
[[nodiscard]] Mat12 eskf_transition(const Mat3& rotation, double dt);

/// One filter step, kept for the RTS smoother.
struct EskfStep {
  double t = 0.0;
  Pose pose_pred, pose_upd;
  Vec3 w_pred = Vec3::Zero(), v_pred = Vec3::Zero(), w_upd = Vec3::Zero(), v_upd = Vec3::Zero();
  Mat12 P_pred = Mat12::Zero(), P_upd = Mat12::Zero();
  /// The error-state transition from the previous step to this one is
  /// eskf_transition(rotation, dt): kept as its two parameters, not formed
  /// each frame.
  Mat3 rotation = Mat3::Identity();    ///< exp(w dt) over the step
  double dt = 0.0;
  /// The process noise P_pred was formed with (rad^2/s^3, mm^2/s^3 per
  /// axis): the literature q times the adaptive scale, or the manoeuvre's.
  double q_rot = 0.0, q_trans = 0.0;
  bool restart = false;  ///< the filter (re)started here: no link to the previous step
};

class PoseEskf {
 public:
  explicit PoseEskf(EskfParams p = {}) : p_(p) {}

  /// Fuses a measured pose with its covariance at time t; returns the
  /// filtered pose.
  Pose update(const Pose& z, const Mat6& cov, double t);
  /// The pose predicted to time t (>= the last update) by the motion model.
  [[nodiscard]] std::optional<Pose> predict(double t) const;
  /// The covariance of that pose (rotation rad, translation mm): the pose
  /// block of F P F^T + Q over dt = t - the last update, in fixed-size 6x6
  /// blocks, P_xx + dt (P_xv + P_vx) + dt^2 P_vv + q dt^3 / 3 with q the
  /// literature's times the current adaptive scales (the rotation
  /// block of F is exp(w dt) ~ I to first order, as a gate wants it);
  /// nullopt before the first update.
  [[nodiscard]] std::optional<Mat6> predicted_pose_covariance(double t) const;
  void reset() { have_ = false; }
  /// The trackers' guard (dot_tracker.hpp: never worse than no filter): the
  /// filter takes measurement z as its pose, with z's covariance and no
  /// correlation to the velocity, whose spread widens to that of a fresh
  /// start while its mean stays. The step stays linked to the one before
  /// (no restart): the smoother runs through it.
  void hand_through(const Pose& z, const Mat6& cov);

  [[nodiscard]] bool initialised() const { return have_; }
  [[nodiscard]] const Vec3& angular_velocity() const { return w_; }
  [[nodiscard]] const Vec3& velocity() const { return v_; }
  [[nodiscard]] const Mat12& covariance() const { return P_; }
  /// What the last update did: NIS, the process-noise scale it used, and
  /// whether it skipped the measurement as an outlier.
  [[nodiscard]] double last_nis() const { return nis_; }
  [[nodiscard]] double last_q_scale() const { return q_scale_; }
  [[nodiscard]] bool last_rejected() const { return rejected_; }
  /// The correlation the last update assumed between its measurement's error
  /// and the one before (0: white), and whether it fused the differenced
  /// measurement (else z itself, its covariance scaled by quantisation_inflation).
  [[nodiscard]] double last_error_correlation() const { return rho_; }
  [[nodiscard]] bool last_differenced() const { return differenced_; }
  /// The last NIS's rotation and translation blocks (each marginal, chi^2
  /// with 3 degrees of freedom when the model is right), at the adaptive
  /// scales, before any manoeuvre scale.
  [[nodiscard]] double last_rotation_nis() const { return nis_rot_; }
  [[nodiscard]] double last_translation_nis() const { return nis_trans_; }
  /// The scales the next prediction multiplies the literature q by, 1..10
  /// (1 while the head moves as the literature says). A restart keeps them:
  /// they describe the head, not the state.
  [[nodiscard]] double rotation_noise_scale() const { return lambda_rot_; }
  [[nodiscard]] double translation_noise_scale() const { return lambda_trans_; }
  /// The last step's record (for the smoother).
  [[nodiscard]] const EskfStep& last_step() const { return step_; }

 private:
  struct Innovation;
  void start(const Pose& z, const Mat6& cov, double t);
  // The steps of update, in order.
  /// The smallest process-noise scale that explains the innovation nu.
  Innovation explain(const Mat12& FPF, const Mat6& cov, const Eigen::Matrix<double, 6, 1>& nu, double dt, double qa,
                     double ql);
  /// The quantisation error's predicted frame-to-frame correlation (above).
  [[nodiscard]] double predicted_quantisation_correlation(const Mat6& cov, double dt) const;
  /// With correlated errors: the differenced measurement when it fits
  /// (true), else z with its covariance inflated.
  bool fuse_correlated(Innovation& in, const Mat12& P_pred, const Mat6& cov, const Pose& x_pred,
                       const Eigen::Matrix<double, 6, 1>& nu, double rho, double dt) const;
  /// An outlier: the prediction stands (three in a row restart).
  Pose skip(const Pose& z, const Mat6& cov, double t, const Pose& x_pred, const Mat12& FPF, double qa, double ql,
            double dt);
  /// The Kalman correction of the state and covariance.
  void correct(const Innovation& in, Mat12& P_pred, const Pose& x_pred, double t);
  void adapt(double dt);
  [[nodiscard]] bool rotation_persists() const;

  EskfParams p_;
  bool have_ = false;
  Pose x_;
  Vec3 w_ = Vec3::Zero(), v_ = Vec3::Zero();
  Mat12 P_ = Mat12::Identity();
  double t_ = 0.0;
  double nis_ = 0.0, q_scale_ = 1.0, rho_ = 0.0;
  bool rejected_ = false, differenced_ = false;
  Pose z_prev_;           ///< the last fused measurement (for differencing)
  bool have_z_prev_ = false;
  double nis_avg_ = 6.0;  ///< the NIS's running mean over ~1 s (consistency of the motion model)
  // Adaptive process noise: the blocks' NIS and whitened innovations (this
  // step's and the last accepted one's), the innovations' lag-one
  // correlation over ~1 s, the quantisation's predicted correlation, and the scales.
  double nis_rot_ = 0.0, nis_trans_ = 0.0;
  Vec3 u_rot_ = Vec3::Zero(), u_trans_ = Vec3::Zero(), u_rot_prev_ = Vec3::Zero(), u_trans_prev_ = Vec3::Zero();
  bool have_u_prev_ = false;
  double lag_corr_rot_ = 0.0, lag_corr_trans_ = 0.0, quant_rho_ = 0.0;
  double lambda_rot_ = 1.0, lambda_trans_ = 1.0;
  Vec3 m_rot_ = Vec3::Zero();  ///< running mean of the whitened rotation innovations (persistence test)
  int rejected_run_ = 0;
  EskfStep step_;
};

/// The guard that keeps the filter never worse than no filter where its
/// motion model is wrong: when the filtered pose lies beyond `chi2` in
/// squared Mahalanobis distance from measurement z under z's covariance (an
/// impulsive reversal the filter lags behind), z is handed through
/// (PoseEskf::hand_through) and returned; else the filtered pose. A
/// measurement the eskf skipped as an outlier is not handed through: on the
/// fast walks those are strays and wrong roots far more often than heads
/// (held-out, thesis, integer: 0.86 -> 1.11 of raw LM's RMS when they were).
[[nodiscard]] Pose guard(PoseEskf& eskf, const Pose& filtered, const Pose& z, const Mat6& cov, double chi2);

/// A filter step's pose carried across a gap with an Ornstein-Uhlenbeck
/// velocity: over a loss longer than the velocity's correlation time a
/// constant-velocity extrapolation overshoots, an OU velocity decays to rest.
/// `spread` is the carried covariance (rotation rad, translation mm) with the
/// displacement the acceleration noise q (rad^2/s^3, mm^2/s^3 per axis) adds.
struct CarriedPose {
  Pose pose;
  Mat6 spread = Mat6::Zero();
};
/// Correlation times of head velocity (rotation, translation), seconds: the
/// figures the eskf's q comes from (above).
inline constexpr double kHeadRotationTauS = 0.5;
inline constexpr double kHeadTranslationTauS = 1.0;
struct OuMotion {
  /// Acceleration spectral densities (the literature's, as EskfParams).
  double q_rot = EskfParams{}.angular_accel_psd, q_trans = EskfParams{}.linear_accel_psd;
  double tau_rot_s = kHeadRotationTauS, tau_trans_s = kHeadTranslationTauS;  ///< velocity correlation times
};
[[nodiscard]] CarriedPose carry_ou(const EskfStep& step, double t, const OuMotion& m);
/// Variance per axis of the displacement over dt of an OU velocity whose
/// acceleration spectral density is q (stationary velocity variance q tau / 2);
/// q dt^3 / 3 for dt << tau, as the eskf's white acceleration.
[[nodiscard]] double ou_displacement_variance(double q, double tau, double dt);

/// One stretch of the filter between restarts, as the smoother saw it: what
/// judging it against its neighbours needs (segment_vetting.hpp).
struct EskfSegment {
  std::size_t first = 0, last = 0;  ///< indices of its first and last step
  double t_first = 0.0;
  Pose first_pose;                ///< the filter's pose at its first step
  Mat6 first_cov = Mat6::Zero();  ///< and its covariance (the measurement's: a restart takes it as it is)
  /// Its last step's time, updated state and covariance (the rest of the
  /// step is not kept).
  EskfStep end;
};

/// Fixed-interval Rauch-Tung-Striebel smoothing (offline: `track solve
/// --smooth`), fed the filter's steps as they happen. It keeps of each step
/// only what the backward pass over the mean needs: the predicted and
/// updated states and the smoother gain C_k = P_upd(k) F^T P_pred(k+1)^-1,
/// formed when step k+1 arrives and stored as float (the gain multiplies a
/// correction of a few pixels' worth; float's 1e-7 is far below it). About
/// 0.8 KB a step instead of the 3.5 KB of an EskfStep.
class RtsSmoother {
 public:
  void add(const EskfStep& step);
  void reserve(size_t steps) { nodes_.reserve(steps); }
  [[nodiscard]] size_t size() const { return nodes_.size(); }
  /// One smoothed pose per step added, in order.
  [[nodiscard]] std::vector<Pose> smooth() const;
  /// The stretches between restarts, in order (each closed when the next
  /// restart arrives: nothing more is copied per step).
  [[nodiscard]] std::vector<EskfSegment> segments() const;

 private:
  struct Node {
    Pose pose_pred, pose_upd;
    Vec3 w_pred, v_pred, w_upd, v_upd;
    Eigen::Matrix<float, 12, 12> gain = Eigen::Matrix<float, 12, 12>::Zero();  ///< to the next step
    bool restart = false;
  };
  /// The last step's end of a segment, from what add() keeps anyway.
  [[nodiscard]] EskfStep last_end() const;

  std::vector<Node> nodes_;
  Mat12 last_P_upd_ = Mat12::Zero();
  double last_t_ = 0.0;
  std::vector<EskfSegment> segs_;  ///< the segments so far, the last one open (its end not yet filled)
};

/// rts_smooth over a run of kept steps (RtsSmoother fed all of them).
[[nodiscard]] std::vector<Pose> rts_smooth(std::span<const EskfStep> steps);

}  // namespace earshot::tracker
