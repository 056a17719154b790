#include "earshot/tracker/track/labelled_tracker.hpp"

#include <algorithm>
#include <cmath>

#include "earshot/tracker/solve/lm_solver.hpp"
#include "settle_output.hpp"

namespace earshot::tracker {
namespace {
/// ln 100: the odds a rival branch needs to replace the one given out.
constexpr double kBranchLogOdds = 4.605;
}  // namespace

LabelledTracker::LabelledTracker(const Camera& cam, const LedModel& model, TrackerConfig cfg)
    : cam_(cam), model_(model), cfg_(cfg), eskf_(cfg.eskf) {
  hyps_.reserve(4);
}

void LabelledTracker::reset() {
  hyps_.clear();
  output_id_ = 0;
  one_euro_.reset();
  median_.reset();
  eskf_.reset();
  pixel_noise_.reset();
  cv_.reset();
  last_output_.reset();
  last_solve_t_ = -1e300;
}

bool LabelledTracker::fits(const Pose& p, const LabelledDots& dots, double& rms) const {
  rms = rms_reprojection_error(p, dots.view(), cam_, model_);
  return p.finite() && p.t.z() > 0.0 && rms <= cfg_.labeller.fit_gate_px &&
         leds_face_camera(p, model_, dots.view(), model_.half_angle + cfg_.labeller.beam_margin_rad);
}

TrackResult LabelledTracker::process(const DotFrame& frame) {
  TrackResult r;
  r.t = frame.t;
  LabelledDots dots;
  for (std::size_t s = 0; s < kSlots; ++s)
    if (frame.slots[s]) dots.add(static_cast<int>(s), *frame.slots[s]);
  LmSolver solver(cam_, model_);

  bool any = false;
  for (auto& h : hyps_) h.seen = false;
  if (dots.count >= 3)
    for (auto& h : hyps_) {
      const Pose pred = h.cv.predict(frame.t).value_or(h.pose);
      const auto pose = solver.solve({dots.view(), &pred});
      double rms = 0.0;
      if (!pose || !fits(*pose, dots, rms)) continue;
      h.pose = *pose;
      h.cv.observe(*pose, frame.t);
      h.rms = rms;
      h.cost_sum += rms * rms;
      h.ssr_sum += dots.count * rms * rms;
      ++h.frames;
      h.seen = any = true;
    }
  if (any) std::erase_if(hyps_, [](const Hypothesis& h) { return !h.seen; });
  else if (dots.count >= 4 || frame.t - last_solve_t_ > cfg_.predict_timeout_s) hyps_.clear();

  if (hyps_.empty() && dots.count >= 4) {
    // Acquire: the best P3P start refined, and its mirror about the line of
    // sight (the other pose a small planar beacon admits) when it fits too.
    double rms = 0.0;
    if (const auto a = solver.solve({dots.view(), nullptr}); a && fits(*a, dots, rms)) {
      const auto add = [&](const Pose& p, double e) {
        Hypothesis h;
        h.pose = p;
        h.cv.observe(p, frame.t);
        h.rms = e;
        h.cost_sum = e * e;
        h.ssr_sum = dots.count * e * e;
        h.frames = 1;
        h.seen = true;
        h.id = ++next_id_;
        hyps_.push_back(h);
      };
      add(*a, rms);
      const Vec3 v = a->t.normalized();
      const Vec3 n = a->R * model_.axis;
      const Vec3 mirrored = 2.0 * v.dot(n) * v - n;
      Pose b = *a;
      b.R = Quat::FromTwoVectors(n, mirrored).toRotationMatrix() * a->R;
      if (const auto bb = solver.solve({dots.view(), &b});
          bb && fits(*bb, dots, rms) && rotation_angle_between(bb->R, a->R) > 1e-3)
        add(*bb, rms);
      one_euro_.reset();
      median_.reset();
      eskf_.reset();
    }
  }

  const Hypothesis* best = choose_branch();
  if (best) {
    r.state = PoseState::tracking;
    r.raw_pose = best->pose;
    r.rms_px = best->rms;
    r.dots_used = dots.count;
    for (std::size_t s = 0; s < kSlots; ++s)
      if (frame.slots[s]) r.slot_led[s] = static_cast<int>(s);
    if (best->id != output_id_) eskf_.reset();  // another explanation: not the same track
    output_id_ = best->id;
  }
  return finish(r, dots);
}

const LabelledTracker::Hypothesis* LabelledTracker::choose_branch() {
  // Each frame adds a hypothesis's squared residuals over the pixel
  // variance to its log-likelihood (twice over); a rival is 100 : 1 more
  // likely than another once its sum is 2 var ln 100 lower.
  const double var = std::max(1e-2, cfg_.pixel_variance > 0.0 ? cfg_.pixel_variance : pixel_noise_.variance());
  const double margin = 2.0 * var * kBranchLogOdds;
  const Hypothesis* lowest = nullptr;
  const Hypothesis* output = nullptr;
  for (const auto& h : hyps_) {
    if (!h.seen) continue;
    if (!lowest || h.ssr_sum < lowest->ssr_sum) lowest = &h;
    if (h.id == output_id_) output = &h;
  }
  if (!lowest) return nullptr;
  // The branch given out stays while tracking, unless another explains the
  // corners 100 : 1 better: a tag seen small fits its mirror pose about as
  // well, and the cheaper of two near-equal fits changes from frame to frame.
  const Hypothesis* keep = output && !(output->ssr_sum - lowest->ssr_sum >= margin) ? output : lowest;
  // A rival goes once the evidence is 100 : 1 against it, or when the
  // contest has run three times its course without deciding.
  const long keep_id = keep->id;
  const double keep_ssr = keep->ssr_sum;
  const int frames = keep->frames;
  std::erase_if(hyps_, [&](const Hypothesis& h) {
    return h.id != keep_id && (h.ssr_sum - keep_ssr >= margin || frames >= 3 * cfg_.disambiguation_frames);
  });
  for (const auto& h : hyps_)
    if (h.id == keep_id) return &h;
  return nullptr;
}

TrackResult LabelledTracker::finish(TrackResult r, const LabelledDots& dots) {
  if (r.state == PoseState::tracking) {
    cv_.observe(r.raw_pose, r.t);
    last_solve_t_ = r.t;
    switch (cfg_.filter) {
      case FilterKind::none: r.pose = r.raw_pose; break;
      case FilterKind::one_euro: r.pose = one_euro_.filter(r.raw_pose, r.t); break;
      case FilterKind::median5: r.pose = median_.filter(r.raw_pose); break;
      case FilterKind::eskf: {
        pixel_noise_.add(r.rms_px * r.rms_px * dots.count, dots.count);
        const double var = cfg_.pixel_variance > 0.0 ? cfg_.pixel_variance : pixel_noise_.variance();
        const Mat6 cov = pose_covariance(r.raw_pose, dots.view(), cam_, model_, var);
        r.pose = guard(eskf_, eskf_.update(r.raw_pose, cov, r.t), r.raw_pose, cov, cfg_.guard_chi2);
        break;
      }
    }
  } else if (r.t - last_solve_t_ <= cfg_.predict_timeout_s) {
    std::optional<Pose> p = cv_.predict(r.t);
    const bool eskf = cfg_.filter == FilterKind::eskf && eskf_.initialised();
    if (eskf)
      if (auto q = eskf_.predict(r.t)) p = q;
    if (p && last_output_ && detail::within_reach(*p, *last_output_, eskf ? &eskf_ : nullptr, r.t, cfg_.predict_reach_rad)) {
      r.state = PoseState::predicted;
      r.pose = *p;
    }
  }
  detail::settle_output(r, last_output_);
  return r;
}

}  // namespace earshot::tracker
