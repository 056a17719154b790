#include "earshot/tracker/live/live_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace earshot::tracker {
namespace {

double smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

Pose interpolate(const Pose& a, const Pose& b, double u) {
  const Quat qa(a.R), qb(b.R);
  return {qa.slerp(u, qb).normalized().toRotationMatrix(), a.t + u * (b.t - a.t)};
}

}  // namespace

double steady_clock_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

Mat3 camera_to_audio() { return Vec3(-1.0, -1.0, 1.0).asDiagonal(); }

Mat3 leveling_rotation(const Vec3& down) {
  if (!(down.norm() > 1e-9) || !down.allFinite()) return Mat3::Identity();
  return Quat::FromTwoVectors(down.normalized(), Vec3::UnitY()).toRotationMatrix();
}

LiveConfig with_source_model(LiveConfig cfg, const FrameSource& source) {
  if (auto c = source.camera()) cfg.camera = *c;
  if (auto m = source.model()) cfg.model = *m;
  return cfg;
}

LivePipeline::LivePipeline(LiveConfig cfg)
    : cfg_(cfg), tracker_(cfg.camera, cfg.model, cfg.tracker), labelled_(cfg.camera, cfg.model, cfg.tracker) {}

void LivePipeline::use_camera(const Camera& c, const std::optional<LedModel>& model) {
  const Camera& o = cfg_.camera;
  bool same = c.fx == o.fx && c.fy == o.fy && c.cx == o.cx && c.cy == o.cy && c.width == o.width && c.height == o.height;
  if (model) same = same && model->leds_mm == cfg_.model.leds_mm && model->axis == cfg_.model.axis &&
                    model->half_angle == cfg_.model.half_angle;
  if (same) return;
  cfg_.camera = c;
  if (model) cfg_.model = *model;
  tracker_ = DotTracker(cfg_.camera, cfg_.model, cfg_.tracker);
  labelled_ = LabelledTracker(cfg_.camera, cfg_.model, cfg_.tracker);
}

std::optional<HeadPose> LivePipeline::process(const SourceEvent& e, double now_s) {
  if (const auto* f = std::get_if<CameraFrame>(&e)) return on_frame(*f);
  if (const auto* p = std::get_if<HeadPose>(&e)) return on_pose(*p);
  return on_note(std::get<SourceNote>(e), now_s);
}

void LivePipeline::update_level(const Vec3& a) {
  // The accelerometer reads gravity alone only while the remote is still:
  // level from a steady reading near 1 g, and only when it moved noticeably.
  if (!a.allFinite()) return;
  const bool steady = (a - accel_mean_).norm() < cfg_.still_tolerance_g && std::abs(a.norm() - 1.0) < 0.1;
  if (!steady) {
    still_count_ = 0;
    accel_mean_ = a;
    return;
  }
  accel_mean_ = 0.9 * accel_mean_ + 0.1 * a;
  if (++still_count_ < cfg_.still_frames) return;
  // The accelerometer reads the reaction to gravity (up); down is its opposite.
  const Mat3 next = leveling_rotation(-accel_mean_);
  if (rotation_angle_between(next, level_) > 0.5 * std::numbers::pi / 180.0) level_ = next;
}

std::optional<HeadPose> LivePipeline::on_frame(const CameraFrame& f) {
  ++counters_.frames;
  if (!std::isfinite(f.dots.t)) {
    ++counters_.rejected_dots;
    return std::nullopt;  // no time, no pose: the frame is garbage
  }
  DotFrame dots = f.dots;
  for (auto& s : dots.slots)
    if (s && (!s->allFinite() || !cfg_.camera.inside(*s))) {
      s.reset();
      ++counters_.rejected_dots;
    }
  if (cfg_.recenter_buttons && (f.buttons & cfg_.recenter_buttons) && !(buttons_ & cfg_.recenter_buttons))
    recenter_pending_ = true;  // on the press, not while held
  buttons_ = f.buttons;
  if (cfg_.level_from_accel && f.accel_g) update_level(*f.accel_g);

  last_track_ = f.labelled ? labelled_.process(dots) : tracker_.process(dots);
  const TrackResult& r = last_track_;
  if (r.state == PoseState::lost || !r.pose.finite()) return lost_pose(dots.t);

  const Pose& head = r.pose;  // camera frame, mm
  if (recenter_pending_ || !reference_ || direct_) {
    reference_ = Pose{head.R, head.t};
    direct_ = false;
    recenter_pending_ = false;
  }
  const Mat3 A = camera_to_audio() * level_;
  const Mat3 rel = head.R * reference_->R.transpose();
  const Pose w{A * rel * A.transpose(), A * (head.t - reference_->t) * 1e-3};
  HeadPose h = good(dots.t, w, r.state);
  // The eskf's velocities, for the audio side to carry the pose on to when
  // it is heard. World pose A R Rref^T A^T: exp(w dt) R becomes
  // exp((A w) dt) (A R Rref^T A^T), so the angular velocity turns by A (a
  // rotation) and the velocity too (mm/s to m/s). Not while blending back in
  // after a loss (the output is not the filter's state then), nor for tags.
  if (h.state == PoseState::tracking && !resuming_ && !f.labelled && cfg_.tracker.filter == FilterKind::eskf &&
      tracker_.eskf().initialised()) {
    // As the filter has them: shrinking them by its velocity covariance
    // (the least-squares gain for a noisy velocity) did worse on slow turns
    // (tests/unit/tracker/test_head_prediction.cpp), the covariance being
    // ~3x the velocity's actual error.
    const Vec3 wa = A * tracker_.eskf().angular_velocity(), va = A * tracker_.eskf().velocity() * 1e-3;
    if (wa.allFinite() && va.allFinite()) {
      h.angular_velocity = to_common(wa);
      h.velocity = to_common(va);
    }
  }
  return h;
}

std::optional<HeadPose> LivePipeline::on_pose(const HeadPose& p) {
  ++counters_.frames;
  const Pose head{to_eigen(p.orientation).normalized().toRotationMatrix(), to_eigen(p.position)};
  if (!std::isfinite(p.t)) return std::nullopt;
  if (!head.finite()) return lost_pose(p.t);
  if (recenter_pending_ || !direct_) {
    // Direct sources have a meaningful zero of their own: identity until recentered.
    reference_ = recenter_pending_ ? head : Pose{};
    direct_ = true;
    recenter_pending_ = false;
  }
  const Pose w{head.R * reference_->R.transpose(), head.t - reference_->t};
  return good(p.t, w, PoseState::tracking);
}

HeadPose LivePipeline::on_note(const SourceNote& n, double now) {
  ++counters_.notes;
  using K = SourceNote::Kind;
  if (n.kind == K::recenter) recenter_pending_ = true;
  if (n.kind == K::disconnected || n.kind == K::connected) {
    tracker_.reset();
    labelled_.reset();
  }
  const bool fresh = now - last_good_t_ <= (direct_ ? cfg_.direct_timeout_s : cfg_.tracker.predict_timeout_s);
  if ((state_ == PoseState::tracking || state_ == PoseState::predicted) && fresh &&
      (n.kind == K::timeout || n.kind == K::recenter))
    return emit(now, out_, PoseState::predicted);  // a short gap: hold, say so
  return lost_pose(now);
}

HeadPose LivePipeline::good(double t, const Pose& target, PoseState s) {
  if (!target.finite()) return lost_pose(t);
  if (state_ == PoseState::lost) {
    resuming_ = true;  // blend from wherever the held/eased pose is now
    resume_t_ = t;
    resume_from_ = out_;
  }
  last_good_t_ = t;
  Pose w = target;
  if (resuming_) {
    const double u = cfg_.resume_s > 0.0 ? (t - resume_t_) / cfg_.resume_s : 1.0;
    if (u >= 1.0) resuming_ = false;
    else w = interpolate(resume_from_, target, smoothstep(u));
  }
  return emit(t, w, s);
}

HeadPose LivePipeline::lost_pose(double t) {
  if (state_ == PoseState::searching) return emit(t, Pose{}, PoseState::searching);
  if (state_ != PoseState::lost) resume_from_ = out_;  // the pose to hold
  resuming_ = false;
  const double since = t - last_good_t_;
  const double u = cfg_.ease_s > 0.0 ? (since - cfg_.hold_s) / cfg_.ease_s : (since > cfg_.hold_s ? 1.0 : 0.0);
  return emit(t, interpolate(resume_from_, Pose{}, smoothstep(u)), PoseState::lost);
}

HeadPose LivePipeline::emit(double t, const Pose& w, PoseState s) {
  state_ = s;
  out_ = w.finite() ? w : out_;
  ++counters_.poses;
  HeadPose h;
  h.t = t;
  h.position = to_common(out_.t);
  Quat q(out_.R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  h.orientation = to_common(q);
  h.state = s;
  h.steady_s = steady_clock_();
  return h;
}

}  // namespace earshot::tracker
