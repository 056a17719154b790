#include "earshot/tracker/track/dot_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "earshot/tracker/track/dot_evidence.hpp"
#include "earshot/tracker/solve/lm_refine.hpp"
#include "earshot/tracker/solve/lm_solver.hpp"
#include "earshot/tracker/filter/motion_reach.hpp"
#include "earshot/tracker/solve/p3p.hpp"
#include "earshot/tracker/solve/thesis_solver.hpp"
#include "settle_output.hpp"

namespace earshot::tracker {
namespace {
/// The fit gate in standard deviations of the estimated pixel noise.
constexpr double kFitGateSigmas = 3.0;
/// 99.9 % point of chi-square with 2 degrees of freedom: a 4-dot fit has 8
/// residuals and 6 pose parameters, so its sum of squared residuals over the
/// pixel variance beyond this says one dot is not the LED it was given.
constexpr double kChi2TwoDof999 = 13.8;
/// Two poses whose likelihoods given the prediction differ by less than
/// 100 : 1 (half the difference of their squared Mahalanobis distances
/// below ln 100) cannot be told apart by motion continuity.
constexpr double kAmbiguousLogRatio = 4.605;
constexpr double kAmbiguousChi2Gap = 2.0 * kAmbiguousLogRatio;
/// 4-dot fits after which the pixel noise estimate is trusted to judge a fit
/// (its running mean has settled to ~10 %: the variance of a 2-dof chi-square
/// sample mean falls as 1/n).
constexpr long kNoiseKnownSamples = 100;
/// No camera places a dot's centre better than ~0.1 px: the pixel variance
/// a fit is judged by never falls below (0.1 px)^2 (noise-free input would
/// otherwise make the solver's own tolerance look like a stray).
constexpr double kMinPixelVariance = 1e-2;
/// Squared Mahalanobis distance of pose p from the eskf's last state carried
/// to time t (motion_reach.hpp): the pose's distance from every motion the
/// filter would accept. nullopt before the filter has a state.
std::optional<double> carried_mahalanobis2(const PoseEskf& eskf, const EskfParams& q, double t, const Pose& p) {
  if (!eskf.initialised()) return std::nullopt;
  return earshot::tracker::carried_mahalanobis2(eskf.last_step(), q, t, p);
}

/// A tracked pose this far off is a flip: rival explanations of the dots
/// matter only beyond it.
constexpr double kFlipRad = 20.0 * 3.14159265358979323846 / 180.0;
/// Odds (ln 1000) a re-acquisition by evidence needs against every rival
/// more than 20 deg off: ten times the 100 : 1 of the tests above, because the
/// state it is judged by is the tracker's own (the literature's process
/// noise, a velocity that may be stale), not the head's true motion; at
/// 100 : 1 the tuning seeds' fast walks gained 0.26 points tracked for 20
/// more flipped frames, at 1000 : 1 0.22 points for 8.
constexpr double kEvidenceLogOdds = 6.908;
/// After a long loss: the share of the prior at the head's usual poses.
constexpr double kUsualPoseWeight = 0.5;
/// Share of the prediction at the largest manoeuvre the eskf allows: heads
/// reverse or start a turn unseen, which the filter's own noise does not expect.
constexpr double kManoeuvreWeight = 0.1;

/// Distance between two poses without a covariance: radians plus
/// translation at 100 mm per radian (a head's LEDs sit ~100 mm from its centre).
double pose_distance(const Pose& a, const Pose& b) {
  return rotation_angle_between(a.R, b.R) + (a.t - b.t).norm() / 100.0;
}
}  // namespace

std::optional<FilterKind> filter_kind_from(std::string_view name) {
  if (name == "none") return FilterKind::none;
  if (name == "one-euro") return FilterKind::one_euro;
  if (name == "median5") return FilterKind::median5;
  if (name == "eskf") return FilterKind::eskf;
  return std::nullopt;
}

/// One way of explaining the dots, followed frame by frame.
struct DotTracker::Hypothesis {
  Pose pose;
  ConstantVelocity cv;
  double cost_sum = 0.0;  ///< sum of squared RMS reprojection errors
  double ssr_sum = 0.0;   ///< sum of squared residuals over every dot it has explained (px^2)
  int frames = 0;
  long id = 0;  ///< which hypothesis this is (the eskf restarts when the output changes hypothesis)
  double rms = 0.0;
  int dots = 0;
  std::array<int, kSlots> slot_led{-1, -1, -1, -1};
  /// This frame's 3-dot pose has a rival P3P root about as likely given the
  /// prediction: followed, but not given out as tracked.
  bool ambiguous = false;
  double ssr4 = -1.0;  ///< this frame's 4-dot sum of squared residuals (px^2), -1 without one
  int born_dots = 4;  ///< dots it was (re)acquired from
  /// When four dots last fitted it within the pixel noise (acquired from
  /// four, or followed on four): a track on three dots alone may have
  /// drifted to a wrong root since.
  double four_dot_t = -1e300;
  int four_dot_frames = 0;  ///< frames four dots fitted it
};

DotTracker::DotTracker(const Camera& cam, const LedModel& model, TrackerConfig cfg)
    : cam_(cam),
      model_(model),
      cfg_(cfg),
      labeller_(cam, model, cfg.labeller),
      thesis_solver_(std::make_unique<ThesisSolver>(cam, model)),
      eskf_(cfg.eskf) {
  hyps_.reserve(8);
}

DotTracker::~DotTracker() = default;
DotTracker::DotTracker(DotTracker&&) noexcept = default;
DotTracker& DotTracker::operator=(DotTracker&&) noexcept = default;

void DotTracker::reset() {
  hyps_.clear();
  thesis_labeller_.reset();
  thesis_solver_->reset();
  one_euro_.reset();
  median_.reset();
  eskf_.reset();
  pixel_noise_.reset();
  noise_samples_ = 0;
  camera_stats_.reset();
  head_poses_.reset();
  output_hyp_id_ = 0;
  output_slot_led_ = {-1, -1, -1, -1};
  last_eskf_dots_ = 4;
  eskf_trusted_ = false;
  resumed_on_three_ = false;
  prev_frame_t_ = -1e300;
  eskf_four_dot_t_ = -1e300;
  cv_.reset();
  last_output_.reset();
  last_raw_.reset();
  last_solve_t_ = -1e300;
}

std::optional<Mat6> DotTracker::prediction_spread(double t) const {
  // The pose block of the eskf's covariance carried to t by constant
  // velocity, plus the white acceleration's q dt^3 / 3 (fixed-size blocks:
  // a dynamic-size F P F^T here was 7% of `track solve`).
  return eskf_.predicted_pose_covariance(t);
}

std::optional<Pose> DotTracker::predict(double t) const {
  if (cfg_.filter == FilterKind::eskf && eskf_.initialised()) return eskf_.predict(t);
  return cv_.predict(t);
}

TrackResult DotTracker::process(const DotFrame& frame) {
  return finish(cfg_.method == SolverMethod::thesis ? process_thesis(frame) : process_lm(frame), frame);
}

TrackResult DotTracker::process_thesis(const DotFrame& frame) {
  TrackResult r;
  r.t = frame.t;
  const auto dots = thesis_labeller_.label(frame);
  if (!dots) return r;  // state lost: the thesis drops incomplete frames
  const auto pose = thesis_solver_->solve({dots->view(), nullptr});
  if (!pose) return r;
  r.state = PoseState::tracking;
  r.raw_pose = *pose;
  r.dots_used = 4;
  r.rms_px = rms_reprojection_error(*pose, dots->view(), cam_, model_);
  for (int s = 0; s < kSlots; ++s) {
    const auto& d = frame.slots[static_cast<size_t>(s)];
    if (!d) continue;
    for (const auto& c : dots->view())
      if (c.pixel == *d) r.slot_led[static_cast<size_t>(s)] = c.led;
  }
  return r;
}

/// What following the hypotheses through one frame needs.
struct DotTracker::FrameContext {
  const DotFrame& frame;
  LmSolver& solver;
  int visible = 0;
  double fit_gate = 0.0;  ///< px
  double var = 0.0;       ///< pixel noise variance, px^2
  bool noise_known = false;
};

TrackResult DotTracker::process_lm(const DotFrame& frame) {
  TrackResult r;
  r.t = frame.t;
  LmSolver solver(cam_, model_);
  // The fit gate follows the camera's pixel noise: 8-px quantisation leaves
  // residuals of a few pixels on every frame, which a gate set for integer
  // pixels would reject. Never below the configured gate.
  const double fit_gate = std::max(cfg_.labeller.fit_gate_px, kFitGateSigmas * std::sqrt(pixel_noise_.variance()));
  labeller_.set_fit_gate_px(fit_gate);
  const FrameContext c{frame, solver, frame.visible(), fit_gate, std::max(kMinPixelVariance, pixel_noise_.variance()),
                       noise_samples_ >= kNoiseKnownSamples};

  if (follow_hypotheses(c)) {
    std::erase_if(hyps_, [](const Hypothesis& h) { return h.dots == 0; });
  } else if (c.visible >= 4 || frame.t - last_solve_t_ > cfg_.predict_timeout_s) {
    hyps_.clear();  // lost the thread: acquire afresh from this frame
  }
  acquire(c);
  prune_rivals();
  if (const Hypothesis* best = choose_output(c)) give_out(r, *best);
  return r;
}

bool DotTracker::follow_hypotheses(const FrameContext& c) {
  // Follow each hypothesis from its own prediction: the output's from the
  // eskf when it runs (its velocity is filtered; two noisy poses' difference
  // is not, and with coarse pixels it throws the prediction tens of pixels
  // off at speed), the rivals' from their last two poses.
  bool any_ok = false;
  for (auto& h : hyps_) any_ok = follow(h, c) || any_ok;
  return any_ok;
}

std::optional<std::pair<Pose, double>> DotTracker::fit_labelling(const Labelling& l, const Pose& pred,
                                                                 const FrameContext& c) const {
  // The pose of a labelling, if it fits and every LED it sees faces the camera.
  const auto pose = c.solver.solve({l.dots.view(), &pred});
  if (!pose) return std::nullopt;
  const double rms = rms_reprojection_error(*pose, l.dots.view(), cam_, model_);
  if (!(rms <= c.fit_gate)) return std::nullopt;
  if (!leds_face_camera(*pose, model_, l.dots.view(), model_.half_angle + cfg_.labeller.beam_margin_rad))
    return std::nullopt;  // a mirror pose that turned the LEDs away: impossible
  return std::pair{*pose, rms};
}

bool DotTracker::follow(Hypothesis& h, const FrameContext& c) {
  const DotFrame& frame = c.frame;
  h.dots = 0;
  h.ambiguous = false;
  h.ssr4 = -1.0;
  std::optional<Pose> filtered;
  std::optional<Mat6> spread;
  if (cfg_.filter == FilterKind::eskf && h.id == output_hyp_id_ && eskf_.initialised()) {
    filtered = eskf_.predict(frame.t);
    spread = prediction_spread(frame.t);
  }
  const Pose pred = filtered ? *filtered : h.cv.predict(frame.t).value_or(h.pose);
  auto lab = labeller_.follow(frame, pred);
  if (!lab) return false;
  auto got = fit_labelling(*lab, pred, c);
  keep_labels_if_better(h, lab, got, pred, c);
  bool stray_suspect = !got && lab->dots.count == 4;
  if (got && lab->dots.count == 4) {
    h.ssr4 = 4.0 * got->second * got->second;
    // Within the fit gate but not within the pixel noise: one of the four
    // may be a stray taken for an LED (integer pixels fit to ~0.3 px; a
    // stray that lands where the gate lets it in is off by pixels). Which
    // one only a prediction with a known spread can say: the eskf's (two
    // noisy poses' difference would pick a wrong P3P root as often).
    stray_suspect = c.noise_known && spread && h.ssr4 > kChi2TwoDof999 * c.var;
  }
  if (stray_suspect) drop_stray(lab, got, pred, spread, c);
  if (!got) return false;
  if (lab->dots.count == 3 && spread) h.ambiguous = choose_root(*lab, got->first, pred, *spread);
  const auto& [pose, rms] = *got;
  h.pose = pose;
  h.cv.observe(pose, frame.t);
  h.rms = rms;
  h.dots = lab->dots.count;
  if (h.dots >= 4) {
    h.four_dot_t = frame.t;
    ++h.four_dot_frames;
  }
  h.slot_led = lab->slot_led;
  h.cost_sum += rms * rms;
  h.ssr_sum += lab->dots.count * rms * rms;
  charge_strays(h, c);
  ++h.frames;
  return true;
}

void DotTracker::charge_strays(Hypothesis& h, const FrameContext& c) const {
  // Three dots fit a pose exactly, so a hypothesis that calls the fourth dot
  // a stray would win any contest of residuals against one that explains
  // all four (a headband labelling 180 deg off won so, on 8-px cells). The
  // likelihoods say what a stray costs: uniform over the image at the
  // camera's stray share, against an LED dot's Gaussian of the pixel noise,
  // ln(area / (stray share 2 pi sigma^2)) per dot (13 nats at 8-px cells),
  // charged to the sums as the residual that would cost as much.
  const int unexplained = c.visible - h.dots;
  if (unexplained <= 0) return;
  const double nats = std::log(cam_.width * cam_.height / (camera_stats_.stray_share() * 2.0 * std::numbers::pi * c.var));
  const double ssr = 2.0 * c.var * std::max(0.0, nats) * unexplained;
  h.ssr_sum += ssr;
  h.cost_sum += ssr / 4.0;
}

void DotTracker::keep_labels_if_better(const Hypothesis& h, std::optional<Labelling>& lab,
                                       std::optional<std::pair<Pose, double>>& got, const Pose& pred,
                                       const FrameContext& c) const {
  // The labeller names each dot by the LED projected nearest it from the
  // prediction; where two LEDs' dots pass close by each other (a headband's
  // side LEDs as the head turns) that can swap their names while both stay
  // lit. The swapped labelling fits worse, yet with coarse pixels within the
  // gate, and its residuals then teach the pixel-noise estimate a larger
  // noise frame by frame, which widens the gate further (seconds on a pose
  // 30-75 deg off). So a relabelling of the same dots has to fit better
  // than the hypothesis's own labels do on this frame.
  Labelling own;
  for (size_t s = 0; s < kSlots; ++s)
    if (h.slot_led[s] >= 0 && c.frame.slots[s]) {
      own.slot_led[s] = h.slot_led[s];
      own.dots.add(h.slot_led[s], *c.frame.slots[s]);
    }
  if (own.dots.count < lab->dots.count || own.slot_led == lab->slot_led) return;
  auto own_fit = fit_labelling(own, pred, c);
  if (own_fit && (!got || own_fit->second < got->second)) {
    lab = own;
    got = own_fit;
  }
}

double DotTracker::off_prediction(const Pose& p, const Pose& pred, const std::optional<Mat6>& spread) {
  // How far a pose is from the prediction: in the prediction's spread when
  // the eskf gives one (rotation and translation weighed by what the motion
  // allows). The pose's own covariance is left out: three dots leave it
  // near singular along the very direction that separates two roots, and
  // each root fits its dots exactly.
  if (!spread) return pose_distance(p, pred);
  return pose_mahalanobis2(p, pred, *spread);
}

void DotTracker::drop_stray(std::optional<Labelling>& lab, std::optional<std::pair<Pose, double>>& got,
                            const Pose& pred, const std::optional<Mat6>& spread, const FrameContext& c) const {
  // The three that keep the thread are those whose pose is nearest the
  // prediction: three dots always fit exactly, so their fit says nothing,
  // but a stray among them pulls the pose away from where the head is.
  // The four-dot pose stays a candidate: noise alone puts one fit in a
  // thousand beyond the bound, and then no stray pulls it off the track.
  std::optional<Labelling> best_lab;
  if (got) best_lab = *lab;
  double best_off = got ? off_prediction(got->first, pred, spread) : 0.0;
  const Labelling four = *lab;
  for (size_t drop = 0; drop < kSlots; ++drop) {
    if (four.slot_led[drop] < 0) continue;
    Labelling three;
    for (size_t s = 0; s < kSlots; ++s)
      if (s != drop && four.slot_led[s] >= 0) {
        three.slot_led[s] = four.slot_led[s];
        three.dots.add(four.slot_led[s], *c.frame.slots[s]);
      }
    if (auto g = fit_labelling(three, pred, c)) {
      const double d = off_prediction(g->first, pred, spread);
      if (!best_lab || d < best_off) {
        got = g;
        best_lab = three;
        best_off = d;
      }
    }
  }
  if (best_lab) lab = best_lab;
}

bool DotTracker::choose_root(const Labelling& lab, Pose& pose, const Pose& pred, const Mat6& spread) const {
  // Three dots fit up to four poses exactly. Take the P3P root most
  // likely given the prediction; when another is about as likely, the
  // frame cannot say which the head is in: follow it, but do not give
  // it out as tracked (a held or predicted pose is better than a flip).
  std::array<Vec3, 3> bearings, pts;
  for (size_t i = 0; i < 3; ++i) {
    bearings[i] = cam_.bearing(lab.dots.items[i].pixel);
    pts[i] = model_.leds_mm[static_cast<size_t>(lab.dots.items[i].led)];
  }
  const P3PSolutions roots = p3p_lambda_twist(bearings, pts);
  double m_best = INFINITY, m_rival = INFINITY;
  const Pose* best_root = nullptr;
  for (int k = 0; k < roots.count; ++k) {
    const Pose& p = roots.poses[static_cast<size_t>(k)];
    if (!p.finite() || !leds_face_camera(p, model_, lab.dots.view(), model_.half_angle + cfg_.labeller.beam_margin_rad))
      continue;
    bool dup = false;  // a double root reached twice
    for (int j = 0; j < k; ++j) dup = dup || pose_distance(p, roots.poses[static_cast<size_t>(j)]) < 0.02;
    if (dup) continue;
    const double m = off_prediction(p, pred, spread);
    if (m < m_best) {
      m_rival = m_best;
      m_best = m;
      best_root = &p;
    } else {
      m_rival = std::min(m_rival, m);
    }
  }
  // LM (a MAP estimate with the prediction as prior) starts from the root
  // nearest the prediction in plain distance; when the spread puts
  // another root nearer, the MAP estimate is sought from that one.
  const Pose* lm_root = nullptr;
  for (int k = 0; k < roots.count; ++k)
    if (!lm_root || pose_distance(roots.poses[static_cast<size_t>(k)], pose) < pose_distance(*lm_root, pose))
      lm_root = &roots.poses[static_cast<size_t>(k)];
  if (best_root && lm_root && pose_distance(*best_root, *lm_root) > 0.02) {
    const PosePrior prior{pred};
    const LmResult r3 = refine_pose_lm(*best_root, lab.dots.view(), cam_, model_, LmOptions{}, &prior);
    pose = r3.pose.finite() ? r3.pose : *best_root;
  }
  // Ambiguous too when even the likeliest root is one no head motion
  // explains (the eskf's own outlier bound): two LEDs and a stray, or
  // labels gone wrong.
  return !(m_rival - m_best > kAmbiguousChi2Gap);
}

void DotTracker::acquire(const FrameContext& c) {
  const DotFrame& frame = c.frame;
  // Four dots seen but every hypothesis explains only three (calling the
  // fourth a stray): a labelling that explains all four wins if one exists.
  // Once the pixel noise is known, a labelling of four dots must fit within
  // it, not only within the fit gate: three LEDs and a stray fit some pose of
  // a near-planar beacon to a few pixels far more often than to the noise.
  const bool all_partial = std::none_of(hyps_.begin(), hyps_.end(), [](const Hypothesis& h) { return h.dots >= 4; });
  std::vector<Labelling> acquired;
  if (c.visible >= 4 && (hyps_.empty() || all_partial)) {
    acquired = labeller_.acquire(frame);
    if (c.noise_known)
      std::erase_if(acquired, [&](const Labelling& l) { return 4.0 * l.rms_px * l.rms_px > kChi2TwoDof999 * c.var; });
    // A labelling no head motion from a trusted state explains is not
    // acquired: after a short loss, or in place of a 3-dot track.
    drop_unreachable(acquired, frame.t, c.var);
  }
  if (!hyps_.empty() && all_partial && !acquired.empty()) hyps_.clear();

  if (hyps_.empty() && c.visible >= 4) {
    for (const auto& l : acquired) {
      Hypothesis h;
      h.pose = l.pose;
      h.cv.observe(l.pose, frame.t);
      h.rms = l.rms_px;
      h.cost_sum = l.rms_px * l.rms_px;
      h.ssr_sum = l.dots.count * l.rms_px * l.rms_px;
      h.frames = 1;
      h.dots = l.dots.count;
      h.slot_led = l.slot_led;
      h.id = ++next_hyp_id_;
      h.ssr4 = 4.0 * l.rms_px * l.rms_px;
      h.four_dot_t = frame.t;
      h.four_dot_frames = 1;
      hyps_.push_back(h);
    }
    if (!hyps_.empty()) {
      one_euro_.reset();
      median_.reset();
      eskf_.reset();
    }
  }
  if (hyps_.empty() && c.visible >= 3 && last_raw_ && frame.t - last_solve_t_ <= cfg_.reacquire3_window_s) {
    // The nearest single answer first (what the tracker did before); when
    // there is none, the evidence of every explanation of the dots.
    reacquire_nearest(frame, c.solver);
    if (hyps_.empty() && cfg_.filter == FilterKind::eskf && eskf_.initialised())
      if (auto h = reacquire_by_evidence(frame, c.var)) hyps_.push_back(*h);
  }
}

void DotTracker::prune_rivals() {
  // Rival hypotheses compete on accumulated reprojection error; the loser
  // goes once it is clearly worse or the contest has run its course.
  if (hyps_.size() <= 1) return;
  auto best = std::min_element(hyps_.begin(), hyps_.end(), [](const auto& a, const auto& b) {
    return a.cost_sum < b.cost_sum;
  });
  const double best_cost = best->cost_sum;
  const int frames = best->frames;
  std::erase_if(hyps_, [&](const Hypothesis& h) {
    return h.cost_sum > 4.0 * best_cost + 1.0 || (frames >= cfg_.disambiguation_frames && h.cost_sum > best_cost);
  });
}

const DotTracker::Hypothesis* DotTracker::choose_output(const FrameContext& c) {
  const Hypothesis* best = nullptr;
  for (const auto& h : hyps_)
    if (h.dots > 0 && (!best || h.cost_sum < best->cost_sum)) best = &h;
  // A 4-dot fit feeds the pixel noise estimate even when its fourth dot was
  // judged a stray, so that a rig whose model is off by a millimetre or two
  // learns its larger residuals instead of calling every fourth dot a stray;
  // capped at the test's own bound, so a stray moves it by little.
  if (best && best->ssr4 >= 0.0) {
    pixel_noise_.add(c.noise_known ? std::min(best->ssr4, kChi2TwoDof999 * c.var) : best->ssr4, 4);
    ++noise_samples_;
  }
  if (best) observe_camera(*best, c.frame);
  // A 3-dot frame whose P3P roots motion cannot tell apart is not given out.
  if (best && best->ambiguous) return nullptr;
  if (best && rival_about_as_likely(*best, c)) return nullptr;
  return best;
}

bool DotTracker::rival_about_as_likely(const Hypothesis& best, const FrameContext& c) const {
  // Nor is a pose whose rival explanation of the same dots is about as
  // likely and another answer: after a loss, four dots of a near-symmetric
  // beacon can fit two labellings within the pixel noise (on 8-px pixels a
  // 137 deg turn fitting 1.09 px RMS against the truth's 1.41). Each further
  // frame adds its squared residuals over the pixel variance to each
  // hypothesis's log-likelihood; the output waits until the evidence for the
  // best is 100 : 1 (a sequential probability ratio test) or the rival has
  // gone. A rival within the best pose's own uncertainty (chi-square, 6
  // degrees of freedom, 99.9 %) is the same answer: coarse pixels leave two
  // nearby minima of the error, and either is as good as the noise allows.
  std::optional<Mat6> cov;
  for (const auto& h : hyps_) {
    if (&h == &best || h.dots == 0 || (h.ssr_sum - best.ssr_sum) / (2.0 * c.var) >= kAmbiguousLogRatio) continue;
    if (!cov) {
      LabelledDots dots;
      for (size_t s = 0; s < kSlots; ++s)
        if (best.slot_led[s] >= 0 && c.frame.slots[s]) dots.add(best.slot_led[s], *c.frame.slots[s]);
      cov = pose_covariance(best.pose, dots.view(), cam_, model_, c.var);
    }
    if (!(pose_mahalanobis2(h.pose, best.pose, *cov) <= kChi2SixDof999)) return true;
  }
  return false;
}

void DotTracker::give_out(TrackResult& r, const Hypothesis& best) {
  r.state = PoseState::tracking;
  r.raw_pose = best.pose;
  r.rms_px = best.rms;
  r.dots_used = best.dots;
  r.slot_led = best.slot_led;
  // Another explanation of the dots than last frame's (a re-acquisition,
  // the rival winning, or a dot seen under another LED's label): its pose
  // is not a measurement of the same track, so the eskf starts afresh.
  bool relabelled = best.id != output_hyp_id_;
  for (size_t s = 0; s < kSlots; ++s)
    if (best.slot_led[s] >= 0 && output_slot_led_[s] >= 0 && best.slot_led[s] != output_slot_led_[s]) relabelled = true;
  if (relabelled) eskf_.reset();
  r.track_frames = best.frames;
  r.acquired_dots = best.born_dots;
  output_hyp_id_ = best.id;
  output_slot_led_ = best.slot_led;
  // Trusted: acquired from four dots, and fitted by four dots on as many
  // frames as rival explanations compete for (disambiguation_frames). Not
  // a track that merely passed the reachability test at acquisition: after
  // a gap of 0.17 s a 165 deg turn passes it, and a wrong labelling trusted
  // so would refuse the right one.
  eskf_trusted_ = best.born_dots >= 4 && best.four_dot_frames >= cfg_.disambiguation_frames;
  eskf_four_dot_t_ = best.four_dot_t;
}

void DotTracker::drop_unreachable(std::vector<Labelling>& acquired, double t, double var) const {
  // The state deserves trust only from a trusted track that four dots
  // fitted within the eskf's gap limit, and that has not since taken a root
  // of three dots by the prediction alone: such a track may sit on a wrong
  // root, and then four dots far from it are the correction, not the error.
  // Beyond the gap limit the eskf's state says nothing.
  if (cfg_.filter != FilterKind::eskf || !eskf_.initialised() || !eskf_trusted_ || resumed_on_three_) return;
  const EskfStep& st = eskf_.last_step();
  if (t - st.t > cfg_.eskf.max_gap_s || t - eskf_four_dot_t_ > cfg_.eskf.max_gap_s) return;
  // The labelling's pose is an estimate too: its own covariance from the
  // four dots (large on 8-px cells) adds to the carried spread.
  std::erase_if(acquired, [&](const Labelling& l) {
    if (extends_output_labels(l.slot_led)) return false;
    const Mat6 cov = pose_covariance(l.pose, l.dots.view(), cam_, model_, var);
    return !(earshot::tracker::carried_mahalanobis2(st, cfg_.eskf, t, l.pose, cov) <= kChi2SixDof999);
  });
}

bool DotTracker::extends_output_labels(const std::array<int, kSlots>& slot_led) const {
  int same = 0;
  for (size_t s = 0; s < kSlots; ++s) {
    if (slot_led[s] < 0 || output_slot_led_[s] < 0) continue;
    if (slot_led[s] != output_slot_led_[s]) return false;
    ++same;
  }
  return same >= 3;
}

void DotTracker::reacquire_nearest(const DotFrame& frame, LmSolver& solver) {
  const int visible = frame.visible();
  // Three LEDs, perhaps beside a stray: re-acquire near the last pose from
  // the one set of three dots that gives a single clear answer.
  std::optional<Labelling> found;
  int answers = 0;
  for (int drop = (visible == 3 ? -1 : 0); drop < (visible == 3 ? 0 : kSlots); ++drop) {
    DotFrame three = frame;
    if (drop >= 0) {
      if (!three.slots[static_cast<size_t>(drop)]) continue;
      three.slots[static_cast<size_t>(drop)].reset();
    }
    if (auto l = labeller_.reacquire3(three, *last_raw_)) {
      found = l;
      ++answers;
    }
  }
  // The answer must be a pose some head motion explains: the filter's
  // last state, carried across the gap, at the largest process noise its
  // manoeuvre test tries. Beyond the eskf's own gap limit its state says
  // nothing; then nearness to the last pose alone decides, as before.
  const bool recent = cfg_.filter == FilterKind::eskf && eskf_.initialised() &&
                      frame.t - eskf_.last_step().t <= cfg_.eskf.max_gap_s;
  if (answers == 1 && recent)
    if (const auto m2 = carried_mahalanobis2(eskf_, cfg_.eskf, frame.t, found->pose); m2 && *m2 > kChi2SixDof999)
      answers = 0;
  if (answers == 1) {
    const auto& l = found;
    if (const auto pose = solver.solve({l->dots.view(), &l->pose})) {
      Hypothesis h;
      h.pose = *pose;
      h.cv.observe(*pose, frame.t);
      h.frames = 1;
      h.dots = 3;
      h.born_dots = 3;
      h.slot_led = l->slot_led;
      h.id = ++next_hyp_id_;
      hyps_.push_back(h);
    }
  }
}

std::optional<DotTracker::Hypothesis> DotTracker::reacquire_by_evidence(const DotFrame& frame, double var) {
  // The eskf's last state carried across the gap: at its own process noise,
  // and at the largest manoeuvre it allows (a head that reverses or starts a
  // turn while unseen).
  const EskfStep& st = eskf_.last_step();
  const OuMotion nominal{st.q_rot, st.q_trans, kHeadRotationTauS, kHeadTranslationTauS};
  const OuMotion wide = head_motion(cfg_.eskf, kMaxManoeuvreScale);
  MotionPrior prior{carry_ou(st, frame.t, nominal), carry_ou(st, frame.t, wide)};
  EvidenceModel m{var, camera_stats_.dropped_share(), camera_stats_.stray_share(), kManoeuvreWeight};
  // Beyond the eskf's gap limit the carried state has spread over tens of
  // degrees: where the head usually is (PoseDistribution) takes the place of
  // the manoeuvre, at even weight.
  const auto usual = head_poses_.prior();
  if (frame.t - st.t > cfg_.eskf.max_gap_s && usual) {
    prior.wide = *usual;
    m.wide_weight = kUsualPoseWeight;
  }
  std::vector<DotExplanation> all = explain_dots(frame, cam_, model_, var);
  for (auto& e : all) score_explanation(e, cam_, model_, m, prior);
  const EvidenceChoice c = choose_explanation(all, kFlipRad);
  if (c.best < 0 || !(c.log_odds >= kEvidenceLogOdds)) return std::nullopt;
  const DotExplanation& e = all[static_cast<size_t>(c.best)];
  // The odds are relative: when every explanation is one no head motion
  // explains, the least bad still is not an answer (the reachability test
  // of reacquire_nearest, as there within the eskf's gap limit).
  if (frame.t - st.t <= cfg_.eskf.max_gap_s)
    if (const auto m2 = carried_mahalanobis2(eskf_, cfg_.eskf, frame.t, e.pose); m2 && *m2 > kChi2SixDof999) return std::nullopt;
  Hypothesis h;
  h.pose = e.pose;
  h.cv.observe(e.pose, frame.t);
  h.frames = 1;
  h.dots = e.dots.count;
  h.born_dots = e.dots.count;
  h.slot_led = e.slot_led;
  h.id = ++next_hyp_id_;
  return h;
}

void DotTracker::observe_camera(const Hypothesis& h, const DotFrame& frame) {
  const double cos_half = std::cos(model_.half_angle);
  int in_view = 0;
  for (size_t led = 0; led < 4; ++led) {
    const Vec3 P = h.pose.apply(model_.leds_mm[led]);
    in_view += P.z() > 1.0 && (h.pose.R * model_.axis).dot(-P.normalized()) >= cos_half && cam_.inside(cam_.project(P));
  }
  camera_stats_.observe(std::max(in_view, h.dots), h.dots, frame.visible() > h.dots);
}

TrackResult DotTracker::finish(TrackResult r, const DotFrame& frame) {
  // A pose from fewer than four dots right after frames not given out (held
  // as ambiguous, or lost) chose its root with nothing but the prediction.
  const bool resumed = last_solve_t_ < prev_frame_t_;
  prev_frame_t_ = r.t;
  if (r.state == PoseState::tracking) {
    cv_.observe(r.raw_pose, r.t);
    head_poses_.add(r.raw_pose);
    if (cfg_.method == SolverMethod::thesis)  // the LM path adds its own in process_lm
      pixel_noise_.add(r.rms_px * r.rms_px * r.dots_used, r.dots_used);
    last_solve_t_ = r.t;
    last_raw_ = r.raw_pose;
    switch (cfg_.filter) {
      case FilterKind::none: r.pose = r.raw_pose; break;
      case FilterKind::one_euro: r.pose = one_euro_.filter(r.raw_pose, r.t); break;
      case FilterKind::median5: r.pose = median_.filter(r.raw_pose); break;
      case FilterKind::eskf: {
        LabelledDots dots;
        for (size_t s = 0; s < kSlots; ++s)
          if (r.slot_led[s] >= 0 && frame.slots[s]) dots.add(r.slot_led[s], *frame.slots[s]);
        const Mat6 cov = pose_covariance(r.raw_pose, dots.view(), cam_, model_, pixel_variance());
        r.pose = eskf_.update(r.raw_pose, cov, r.t);
        // Three dots can fit two poses far apart, which no covariance
        // describes; when a fourth dot settles it away from the filter's
        // track, the four-dot pose is the truth: restart from it.
        if (eskf_.last_rejected() && dots.count >= 4 && last_eskf_dots_ < 4) {
          eskf_.reset();
          r.pose = eskf_.update(r.raw_pose, cov, r.t);
        }
        r.pose = guard(eskf_, r.pose, r.raw_pose, cov, cfg_.guard_chi2);
        last_eskf_dots_ = dots.count;
        if (dots.count >= 4) resumed_on_three_ = false;
        else if (resumed) resumed_on_three_ = true;
        break;
      }
    }
  } else if (r.t - last_solve_t_ <= cfg_.predict_timeout_s && cfg_.method == SolverMethod::lm) {
    predict_output(r);
  }
  detail::settle_output(r, last_output_);  // hold the last tracked pose when lost; never pass a bad number on
  return r;
}

void DotTracker::predict_output(TrackResult& r) {
  auto p = cv_.predict(r.t);
  if (cfg_.filter == FilterKind::eskf)
    if (auto q = eskf_.predict(r.t)) p = q;  // the filter's velocities, not two noisy poses
  if (!p || !last_output_) return;
  // Only while the prediction stays within what the camera last saw: what
  // it adds beyond the last tracked pose, and (with the eskf) its own
  // spread, each within TrackerConfig::predict_reach_rad. Past it the output holds the
  // last tracked pose (settle_output): a head that was turning when its
  // dots went may have stopped, and a coasted pose held for a loss of
  // seconds is off by all it coasted.
  if (!detail::within_reach(*p, *last_output_, cfg_.filter == FilterKind::eskf ? &eskf_ : nullptr, r.t,
                            cfg_.predict_reach_rad))
    return;
  r.state = PoseState::predicted;
  r.pose = cfg_.filter == FilterKind::one_euro ? one_euro_.filter(*p, r.t) : *p;
}

}  // namespace earshot::tracker
