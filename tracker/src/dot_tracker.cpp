#include "earshot/tracker/dot_tracker.hpp"

#include <algorithm>
#include <cmath>

#include "earshot/tracker/lm_solver.hpp"
#include "earshot/tracker/thesis_solver.hpp"
#include "settle_output.hpp"

namespace earshot::tracker {
namespace {
/// The fit gate in standard deviations of the estimated pixel noise.
constexpr double kFitGateSigmas = 3.0;
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
  int frames = 0;
  long id = 0;  ///< which hypothesis this is (the eskf restarts when the output changes hypothesis)
  double rms = 0.0;
  int dots = 0;
  std::array<int, kSlots> slot_led{-1, -1, -1, -1};
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
  output_hyp_id_ = 0;
  output_slot_led_ = {-1, -1, -1, -1};
  last_eskf_dots_ = 4;
  cv_.reset();
  last_output_.reset();
  last_raw_.reset();
  last_solve_t_ = -1e300;
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

TrackResult DotTracker::process_lm(const DotFrame& frame) {
  TrackResult r;
  r.t = frame.t;
  LmSolver solver(cam_, model_);
  const int visible = frame.visible();

  // The fit gate follows the camera's pixel noise: 8-px quantisation leaves
  // residuals of a few pixels on every frame, which a gate set for integer
  // pixels would reject. Never below the configured gate.
  const double fit_gate = std::max(cfg_.labeller.fit_gate_px, kFitGateSigmas * std::sqrt(pixel_noise_.variance()));
  labeller_.set_fit_gate_px(fit_gate);

  // Follow each hypothesis from its own prediction: the output's from the
  // eskf when it runs (its velocity is filtered; two noisy poses' difference
  // is not, and with coarse pixels it throws the prediction tens of pixels
  // off at speed), the rivals' from their last two poses.
  bool any_ok = false;
  for (auto& h : hyps_) {
    h.dots = 0;
    std::optional<Pose> filtered;
    if (cfg_.filter == FilterKind::eskf && h.id == output_hyp_id_ && eskf_.initialised()) filtered = eskf_.predict(frame.t);
    const Pose pred = filtered ? *filtered : h.cv.predict(frame.t).value_or(h.pose);
    auto lab = labeller_.follow(frame, pred);
    if (!lab) continue;
    // The pose of a labelling, if it fits and every LED it sees faces the camera.
    auto fit = [&](const Labelling& l) -> std::optional<std::pair<Pose, double>> {
      const auto pose = solver.solve({l.dots.view(), &pred});
      if (!pose) return std::nullopt;
      const double rms = rms_reprojection_error(*pose, l.dots.view(), cam_, model_);
      if (!(rms <= fit_gate)) return std::nullopt;
      if (!leds_face_camera(*pose, model_, l.dots.view(), model_.half_angle + cfg_.labeller.beam_margin_rad))
        return std::nullopt;  // a mirror pose that turned the LEDs away: impossible
      return std::pair{*pose, rms};
    };
    auto got = fit(*lab);
    if (!got && lab->dots.count == 4) {
      // Four matched but they do not fit: a stray inside the match gate taken
      // for an LED, or one dot far off. The best-fitting three, near the
      // prediction (the LM's prior), keep the thread.
      for (size_t drop = 0; drop < kSlots; ++drop) {
        if (lab->slot_led[drop] < 0) continue;
        Labelling three;
        for (size_t s = 0; s < kSlots; ++s)
          if (s != drop && lab->slot_led[s] >= 0) {
            three.slot_led[s] = lab->slot_led[s];
            three.dots.add(lab->slot_led[s], *frame.slots[s]);
          }
        if (auto g = fit(three); g && (!got || g->second < got->second)) {
          got = g;
          *lab = three;
        }
      }
    }
    if (!got) continue;
    const auto& [pose, rms] = *got;
    h.pose = pose;
    h.cv.observe(pose, frame.t);
    h.rms = rms;
    h.dots = lab->dots.count;
    h.slot_led = lab->slot_led;
    h.cost_sum += rms * rms;
    ++h.frames;
    any_ok = true;
  }
  if (any_ok) {
    std::erase_if(hyps_, [](const Hypothesis& h) { return h.dots == 0; });
  } else if (visible >= 4 || frame.t - last_solve_t_ > cfg_.predict_timeout_s) {
    hyps_.clear();  // lost the thread: acquire afresh from this frame
  }

  // Four dots seen but every hypothesis explains only three (calling the
  // fourth a stray): a labelling that explains all four wins if one exists.
  const bool all_partial = std::none_of(hyps_.begin(), hyps_.end(), [](const Hypothesis& h) { return h.dots >= 4; });
  if (!hyps_.empty() && visible >= 4 && all_partial && !labeller_.acquire(frame, 1).empty()) hyps_.clear();

  if (hyps_.empty() && visible >= 4) {
    for (const auto& l : labeller_.acquire(frame)) {
      Hypothesis h;
      h.pose = l.pose;
      h.cv.observe(l.pose, frame.t);
      h.rms = l.rms_px;
      h.cost_sum = l.rms_px * l.rms_px;
      h.frames = 1;
      h.dots = l.dots.count;
      h.slot_led = l.slot_led;
      h.id = ++next_hyp_id_;
      hyps_.push_back(h);
    }
    if (!hyps_.empty()) {
      one_euro_.reset();
      median_.reset();
      eskf_.reset();
    }
  }
  if (hyps_.empty() && visible >= 3 && last_raw_ && frame.t - last_solve_t_ <= cfg_.reacquire3_window_s) {
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
    if (answers == 1) {
      const auto& l = found;
      if (const auto pose = solver.solve({l->dots.view(), &l->pose})) {
        Hypothesis h;
        h.pose = *pose;
        h.cv.observe(*pose, frame.t);
        h.frames = 1;
        h.dots = 3;
        h.slot_led = l->slot_led;
        h.id = ++next_hyp_id_;
        hyps_.push_back(h);
      }
    }
  }

  // Rival hypotheses compete on accumulated reprojection error; the loser
  // goes once it is clearly worse or the contest has run its course.
  if (hyps_.size() > 1) {
    auto best = std::min_element(hyps_.begin(), hyps_.end(), [](const auto& a, const auto& b) {
      return a.cost_sum < b.cost_sum;
    });
    const double best_cost = best->cost_sum;
    const int frames = best->frames;
    std::erase_if(hyps_, [&](const Hypothesis& h) {
      return h.cost_sum > 4.0 * best_cost + 1.0 || (frames >= cfg_.disambiguation_frames && h.cost_sum > best_cost);
    });
  }

  const Hypothesis* best = nullptr;
  for (const auto& h : hyps_)
    if (h.dots > 0 && (!best || h.cost_sum < best->cost_sum)) best = &h;
  if (best) {
    r.state = PoseState::tracking;
    r.raw_pose = best->pose;
    r.rms_px = best->rms;
    r.dots_used = best->dots;
    r.slot_led = best->slot_led;
    // Another explanation of the dots than last frame's (a re-acquisition,
    // the rival winning, or a dot seen under another LED's label): its pose
    // is not a measurement of the same track, so the eskf starts afresh.
    bool relabelled = best->id != output_hyp_id_;
    for (size_t s = 0; s < kSlots; ++s)
      if (best->slot_led[s] >= 0 && output_slot_led_[s] >= 0 && best->slot_led[s] != output_slot_led_[s]) relabelled = true;
    if (relabelled) eskf_.reset();
    output_hyp_id_ = best->id;
    output_slot_led_ = best->slot_led;
  }
  return r;
}

TrackResult DotTracker::finish(TrackResult r, const DotFrame& frame) {
  if (r.state == PoseState::tracking) {
    cv_.observe(r.raw_pose, r.t);
    pixel_noise_.add(r.rms_px * r.rms_px * r.dots_used, r.dots_used);  // every filter: it sets the fit gate
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
        last_eskf_dots_ = dots.count;
        break;
      }
    }
  } else if (r.t - last_solve_t_ <= cfg_.predict_timeout_s && cfg_.method == SolverMethod::lm) {
    if (auto p = cv_.predict(r.t)) {
      r.state = PoseState::predicted;
      if (cfg_.filter == FilterKind::eskf)
        if (auto q = eskf_.predict(r.t)) p = q;  // the filter's velocities, not two noisy poses
      r.pose = cfg_.filter == FilterKind::one_euro ? one_euro_.filter(*p, r.t) : *p;
    }
  }
  detail::settle_output(r, last_output_);  // hold the last pose when lost; never pass a bad number on
  return r;
}

}  // namespace earshot::tracker
