// The pose pipeline for one camera: dots in, beacon pose out.
//   label (labeller.hpp) -> solve (solver.hpp) -> filter (filters.hpp)
// It keeps a state per frame: tracking (solved from 3 or 4 dots), predicted
// (too few dots, pose extrapolated for up to `predict_timeout_s` while it stays
// within `predict_reach_rad` of the last tracked pose) or lost (the last
// tracked pose held).
//
// Near-planar beacons (like the thesis's) admit two poses that fit one frame
// almost equally well. After (re)acquisition the tracker follows every
// hypothesis that fits, frame by frame from its own prediction, and keeps the
// one whose reprojection error stays lowest; it never switches between them
// while tracking, so the pose does not flip.
//
// Strays and the roots of three dots are judged by the noise the tracker has
// learnt and by the eskf's prediction with its covariance, not by fixed
// pixel gates: a labelling of four dots must fit within the pixel noise
// (chi-square, 2 degrees of freedom), else the three of them nearest the
// prediction carry the pose; a 3-dot frame takes the P3P root most likely
// given the prediction, and when a second root is about as likely (within
// 100 : 1) the frame is followed but not given out as tracked: a held or
// predicted pose is better than a flip. After a loss, a re-acquisition from
// three dots must also be a pose some head motion explains: the eskf's last
// state carried across the gap (an Ornstein-Uhlenbeck velocity, with the
// largest process noise its manoeuvre test tries) must put it within the
// 99.9 % bound of chi-square with 6 degrees of freedom. When no set of
// three dots gives a single answer near the last pose (the unseen LED must
// be hidden there, so an LED that merely dropped out refuses the truth),
// the eskf's state decides by evidence (dot_evidence.hpp): every labelling
// of the dots, each P3P root or LM minimum, each unseen LED dropped or out of
// view, and two LEDs with strays, scored by the pixel noise, the camera's
// learnt dropout and stray shares and the carried state; the likeliest is
// taken when it is 1000 : 1 against every explanation more than 20 deg from
// it and passes the same reachability test. This holds after any loss: beyond
// the eskf's gap limit, where the carried state has spread over tens of
// degrees, the prior's wide part is where the head usually is (a
// PoseDistribution learnt from the tracked poses), at even weight; the
// beam is in every explanation, its edge soft (an LED is in view with a
// probability that falls over a few degrees about the half-angle, widened by
// the pose's own uncertainty; unseen in view is a dropout, seen beyond the
// edge unlikely), so a return whose fourth LED is at or beyond its beam
// edge is taken from its first three dots.
//
// A 4-dot acquisition, after a loss or in place of a track on three dots,
// must be reachable too when the eskf's state deserves trust: its track was
// acquired from four dots and four dots have fitted it on
// `disambiguation_frames` frames (the span rival explanations compete
// over), four dots fitted it within the eskf's gap limit, and no pose from
// three dots was fed to it since right after a frame it was not fed (a root
// chosen by the prediction alone). A labelling no head motion from that
// state explains (99.9 %, chi-square 6 dof, the labelling's own covariance
// added) is dropped: with 8-px cells three LEDs and a stray, or four LEDs
// under another labelling, fit within the noise at a pose 45-180 deg away.
// A labelling that keeps the last output's labels and adds a fourth dot is
// never dropped (it settles the root a 3-dot track took), and a track that
// does not deserve trust is still replaced by four dots that disagree.
//
// While tracking, the labeller names each dot by the LED projected nearest
// it from the prediction; a naming that differs from the track's own for
// the same lit slots is taken only if it fits better (two dots passing each
// other swap names otherwise). A hypothesis that calls a visible dot a stray
// is charged what a stray costs against an LED's dot (uniform over the image
// at the camera's stray share, against the pixel noise's Gaussian), so three
// dots fitted exactly do not beat four explained.
//
// Rival explanations of four dots (another labelling, or a pose outside the
// best one's own uncertainty) compete on their summed squared residuals; the
// pose is not given out until the evidence for one is 100 : 1 under the
// learnt pixel noise (a sequential probability ratio test) or the rival has
// gone: with coarse pixels a wrong labelling can fit one frame better than
// the truth.
#pragma once

#include <memory>
#include <utility>
#include <optional>
#include <vector>

#include "earshot/tracker/track/dot_evidence.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/filter/eskf.hpp"
#include "earshot/tracker/filter/filters.hpp"
#include "earshot/tracker/track/labeller.hpp"
#include "earshot/tracker/solve/lm_solver.hpp"
#include "earshot/tracker/core/poses_csv.hpp"
#include "earshot/tracker/solve/solver.hpp"

namespace earshot::tracker {

/// none: the solver's pose; one_euro, median5: jitter filters (filters.hpp);
/// eskf: the error-state Kalman filter weighing each frame by its own
/// covariance (eskf.hpp).
enum class FilterKind { none, one_euro, median5, eskf };
[[nodiscard]] std::optional<FilterKind> filter_kind_from(std::string_view name);

struct TrackerConfig {
  SolverMethod method = SolverMethod::lm;
  FilterKind filter = FilterKind::none;
  LabellerOptions labeller{};
  double predict_timeout_s = 0.1;  ///< predicted state lasts at most this long
  /// ... and only while the prediction moves the pose at most this far from
  /// the last tracked output, and (eskf) its rotation spread stays within it
  /// (rad): then the output holds the last tracked pose. 1 deg: a frame at
  /// 100 deg/s.
  double predict_reach_rad = 1.0 * 3.14159265358979323846 / 180.0;
  int disambiguation_frames = 30;  ///< frames over which rival hypotheses compete
  double reacquire3_window_s = 1e9;  ///< after a loss, re-acquire from 3 dots this long (any loss)
  EskfParams eskf{};              ///< head-motion model of the eskf filter
  /// The guard (eskf): a filtered pose whose squared Mahalanobis distance
  /// from the frame's measurement, under the measurement's covariance,
  /// exceeds this hands the measurement through (guard(), eskf.hpp). 100:
  /// the eskf's own manoeuvre bound (EskfParams::manoeuvre_chi2), for the
  /// same reason: 8-px cells' errors are not Gaussian, and at chi-square's
  /// 99.9 % (22.5) the guard handed through ordinary quantisation errors
  /// (tuning seeds: seated, thesis, 8-px, 0.72 -> 0.90 of raw LM's RMS).
  double guard_chi2 = 100.0;
  /// Pixel noise variance (px^2) for the eskf's measurement covariance:
  /// 0 estimates it from the residuals (PixelNoiseEstimator).
  double pixel_variance = 0.0;
};

struct TrackResult {
  double t = 0.0;
  PoseState state = PoseState::lost;
  bool has_pose = false;  ///< false only before the first pose ever
  Pose pose;              ///< filtered (or predicted) pose; held when lost
  Pose raw_pose;          ///< solver output before the filter (tracking only)
  double rms_px = 0.0;    ///< reprojection error of the solve (tracking only)
  int dots_used = 0;
  std::array<int, kSlots> slot_led{-1, -1, -1, -1};  ///< LED 0-3 per slot
  /// Frames the output's explanation of the dots has been followed (1: it
  /// was (re)acquired in this frame; tracking only).
  int track_frames = 0;
  int acquired_dots = 0;  ///< dots it was (re)acquired from: 3 or 4 (tracking only)
};

class DotTracker {
 public:
  DotTracker(const Camera& cam, const LedModel& model, TrackerConfig cfg = {});
  ~DotTracker();
  DotTracker(DotTracker&&) noexcept;
  DotTracker& operator=(DotTracker&&) noexcept;

  TrackResult process(const DotFrame& frame);
  /// Constant-velocity prediction of the pose at time t (after a solve): the
  /// eskf's state with that filter, else from the last two raw poses.
  [[nodiscard]] std::optional<Pose> predict(double t) const;
  void reset();

  [[nodiscard]] const TrackerConfig& config() const { return cfg_; }
  /// The eskf filter (its last step feeds the offline smoother).
  [[nodiscard]] const PoseEskf& eskf() const { return eskf_; }
  /// The pixel noise variance the eskf uses now (px^2).
  [[nodiscard]] double pixel_variance() const {
    return cfg_.pixel_variance > 0.0 ? cfg_.pixel_variance : pixel_noise_.variance();
  }

 private:
  struct Hypothesis;
  struct FrameContext;
  TrackResult process_lm(const DotFrame& frame);
  // The steps of process_lm, in order.
  /// Follows every hypothesis into this frame; true when one was.
  bool follow_hypotheses(const FrameContext& c);
  /// One hypothesis from its own prediction (the eskf's for the output's).
  bool follow(Hypothesis& h, const FrameContext& c);
  /// Four dots every hypothesis explains only three of, or none: acquire;
  /// after a loss, three dots re-acquire.
  void acquire(const FrameContext& c);
  /// Drops rivals clearly worse than the best, or worse once the contest has run.
  void prune_rivals();
  /// The hypothesis given out, if any (learns the pixel noise and the camera).
  const Hypothesis* choose_output(const FrameContext& c);
  /// Sets r from the hypothesis given out; restarts the eskf on a relabelling.
  void give_out(TrackResult& r, const Hypothesis& best);
  // Their parts.
  [[nodiscard]] std::optional<std::pair<Pose, double>> fit_labelling(const Labelling& l, const Pose& pred,
                                                                     const FrameContext& c) const;
  /// A labelling of this frame that renames dots the hypothesis had named:
  /// kept only if it fits better than the hypothesis's own labels.
  void keep_labels_if_better(const Hypothesis& h, std::optional<Labelling>& lab,
                             std::optional<std::pair<Pose, double>>& got, const Pose& pred,
                             const FrameContext& c) const;
  /// Charges a hypothesis for the dots it calls strays (their likelihood).
  void charge_strays(Hypothesis& h, const FrameContext& c) const;
  [[nodiscard]] static double off_prediction(const Pose& p, const Pose& pred, const std::optional<Mat6>& spread);
  /// A 4-dot labelling that fits worse than the noise: the three of its dots
  /// (or the four) whose pose is nearest the prediction.
  void drop_stray(std::optional<Labelling>& lab, std::optional<std::pair<Pose, double>>& got, const Pose& pred,
                  const std::optional<Mat6>& spread, const FrameContext& c) const;
  /// A 3-dot pose: the P3P root most likely given the prediction (pose is
  /// set to it); true when a rival root is about as likely.
  bool choose_root(const Labelling& lab, Pose& pose, const Pose& pred, const Mat6& spread) const;
  [[nodiscard]] bool rival_about_as_likely(const Hypothesis& best, const FrameContext& c) const;
  TrackResult process_thesis(const DotFrame& frame);
  TrackResult finish(TrackResult r, const DotFrame& frame);
  /// A frame not tracked: the predicted pose while it stays near the last
  /// tracked one (TrackerConfig::predict_reach_rad), else nothing (held).
  void predict_output(TrackResult& r);
  /// After a loss, with the eskf's last state: the explanation of the dots
  /// (dot_evidence.hpp) 100 : 1 more likely than any pose more than 20 deg
  /// from it, given that state carried across the gap; nullopt when none is.
  [[nodiscard]] std::optional<Hypothesis> reacquire_by_evidence(const DotFrame& frame, double pixel_variance);
  /// Without the eskf: the one set of three dots whose labelling near the
  /// last raw pose gives a single clear answer (Labeller::reacquire3).
  void reacquire_nearest(const DotFrame& frame, LmSolver& solver);
  /// When the eskf's state deserves trust (see the header comment): drops
  /// the 4-dot labellings of an acquisition that no head motion from that
  /// state explains (motion_reach.hpp, with the labelling's own covariance),
  /// except one that only adds a dot to the last output's labels. After a
  /// loss, what is left (if anything) is acquired, else three of the dots
  /// re-acquire as after any loss; beside a 3-dot track, that track goes on.
  void drop_unreachable(std::vector<Labelling>& acquired, double t, double var) const;
  /// The labelling gives the three or more slots the last output labelled
  /// the same LEDs: the same labels plus a fourth dot, which settles the
  /// root a track on three dots took (never held to the reach).
  [[nodiscard]] bool extends_output_labels(const std::array<int, kSlots>& slot_led) const;
  /// Learns the camera's dropout and stray shares from a tracked frame.
  void observe_camera(const Hypothesis& h, const DotFrame& frame);
  /// Covariance of the eskf's predicted pose at time t (rotation rad,
  /// translation mm); nullopt before the filter has a state.
  [[nodiscard]] std::optional<Mat6> prediction_spread(double t) const;

  Camera cam_;
  LedModel model_;
  TrackerConfig cfg_;
  Labeller labeller_;
  ThesisLabeller thesis_labeller_;
  std::unique_ptr<PoseSolver> thesis_solver_;
  std::vector<Hypothesis> hyps_;
  PoseOneEuro one_euro_;
  MedianPoseFilter median_;
  PoseEskf eskf_;
  long next_hyp_id_ = 0, output_hyp_id_ = 0;
  std::array<int, kSlots> output_slot_led_{-1, -1, -1, -1};
  int last_eskf_dots_ = 4;  ///< dots behind the eskf's last measurement
  double eskf_four_dot_t_ = -1e300;  ///< when four dots last fitted the output's track
  /// The output's track deserves trust: acquired from four dots and fitted
  /// by four dots on disambiguation_frames frames.
  bool eskf_trusted_ = false;
  /// Since its last 4-dot update the eskf took a pose from three dots right
  /// after a frame it was not fed: a root chosen by the prediction alone.
  bool resumed_on_three_ = false;
  double prev_frame_t_ = -1e300;  ///< the previous frame's time

  PixelNoiseEstimator pixel_noise_;
  CameraBehaviour camera_stats_;
  PoseDistribution head_poses_;  ///< where the head usually is (re-acquisition after a long loss)
  long noise_samples_ = 0;  ///< 4-dot fits the pixel noise estimate has seen
  ConstantVelocity cv_;
  std::optional<Pose> last_output_;  ///< the last pose given out as tracked
  std::optional<Pose> last_raw_;
  double last_solve_t_ = -1e300;
};

}  // namespace earshot::tracker
