#include "listener_scores.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "earshot/tracker/filter/eskf.hpp"
#include "earshot/tracker/filter/segment_vetting.hpp"
#include "earshot/tracker/track/accuracy.hpp"
#include "earshot/tracker/track/labelled_tracker.hpp"

namespace earshot::tracker::bench {



namespace {
constexpr double kDeg = 180.0 / M_PI;
constexpr double kStillDegS = 5.0;

double ratio(double a2, double b2) { return b2 > 0.0 ? std::sqrt(a2 / b2) : NAN; }

/// One row's output for every frame: state and pose (has_pose false before the first).
struct Out {
  PoseState state = PoseState::lost;
  bool has_pose = false;
  Pose pose;
};

/// A tracker of either kind.
class AnyTracker {
 public:
  AnyTracker(const Camera& cam, const LedModel& model, const TrackerConfig& cfg, bool labelled) {
    if (labelled) lab_.emplace(cam, model, cfg);
    else dot_.emplace(cam, model, cfg);
  }
  TrackResult process(const DotFrame& f) { return dot_ ? dot_->process(f) : lab_->process(f); }
  [[nodiscard]] const PoseEskf& eskf() const { return dot_ ? dot_->eskf() : lab_->eskf(); }

 private:
  std::optional<DotTracker> dot_;
  std::optional<LabelledTracker> lab_;
};

/// The row's live output, and with `smoothed` the offline one too.
std::vector<Out> run_row(const Camera& cam, const LedModel& model, const std::vector<DotFrame>& walk, bool labelled,
                         const TrackerConfig& cfg, std::vector<Out>* smoothed = nullptr) {
  const bool smooth = smoothed != nullptr;
  AnyTracker tr(cam, model, cfg, labelled);
  std::vector<Out> out(walk.size());
  RtsSmoother smoother;
  std::vector<size_t> step_frame;
  for (size_t i = 0; i < walk.size(); ++i) {
    const TrackResult r = tr.process(walk[i]);
    out[i] = {r.state, r.has_pose, r.pose};
    if (smooth && r.state == PoseState::tracking) {
      smoother.add(tr.eskf().last_step());
      step_frame.push_back(i);
    }
  }
  if (!smooth) return out;
  const std::vector<Out> live = out;
  // As `track solve --smooth`: smoothed tracked frames; segments no head
  // motion connects are lost, holding the last kept pose, as is every frame
  // the live tracker did not track.
  const std::vector<Pose> sm = smoother.smooth();
  const std::vector<bool> vouched = vet_segments(smoother.segments(), sm.size(), cfg.eskf);
  std::vector<bool> kept(walk.size(), false);
  for (size_t k = 0; k < sm.size(); ++k) {
    Out& o = out[step_frame[k]];
    if (vouched[k]) {
      o.pose = sm[k];
      kept[step_frame[k]] = true;
    } else {
      o.state = PoseState::lost;
    }
  }
  std::optional<Pose> held;
  for (size_t i = 0; i < walk.size(); ++i) {
    Out& o = out[i];
    if (o.state == PoseState::tracking && kept[i]) {
      held = o.pose;
    } else if (o.state != PoseState::predicted) {
      o.state = o.state == PoseState::tracking ? PoseState::lost : o.state;
      if (held) o.pose = *held;
    } else if (held) {
      o.pose = *held;  // offline there is no need to extrapolate: the smoothed last pose holds
    }
    o.has_pose = held.has_value();
  }
  *smoothed = out;
  return live;
}

/// Raw LM's tracked poses, the last one held through every other frame.
std::vector<Out> hold_row(const std::vector<Out>& raw) {
  std::vector<Out> out(raw.size());
  std::optional<Pose> held;
  for (size_t i = 0; i < raw.size(); ++i) {
    if (raw[i].state == PoseState::tracking) held = raw[i].pose;
    out[i].state = raw[i].state == PoseState::tracking ? PoseState::tracking : PoseState::lost;
    out[i].has_pose = held.has_value();
    if (held) out[i].pose = *held;
  }
  return out;
}

Vec3 rot_err(const Pose& est, const Pose& truth) { return log_so3(est.R * truth.R.transpose()); }

}  // namespace

double RowScore::tracked_pct() const { return frames3 ? 100.0 * static_cast<double>(tracked3) / static_cast<double>(frames3) : NAN; }
double RowScore::rms_rot_ratio() const { return ratio(rot2, raw_rot2); }
double RowScore::rms_trans_ratio() const { return ratio(trans2, raw_trans2); }
double RowScore::jitter_ratio() const { return ratio(jitter2, raw_jitter2); }
double RowScore::known_quantile(double q) const {
  if (known_err_deg.empty()) return NAN;
  std::vector<double> v = known_err_deg;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}
void RowScore::merge(const RowScore& o) {
  frames3 += o.frames3;
  tracked3 += o.tracked3;
  rot2 += o.rot2;
  trans2 += o.trans2;
  raw_rot2 += o.raw_rot2;
  raw_trans2 += o.raw_trans2;
  common += o.common;
  jitter2 += o.jitter2;
  raw_jitter2 += o.raw_jitter2;
  still += o.still;
  flips += o.flips;
  known_err_deg.insert(known_err_deg.end(), o.known_err_deg.begin(), o.known_err_deg.end());
}
void WalkScores::merge(const WalkScores& o) {
  for (size_t k = 0; k < kLsRows; ++k) rows[k].merge(o.rows[k]);
}

WalkScores score_walk(const Camera& cam, const LedModel& model, const std::vector<DotFrame>& walk, bool labelled,
                      const TrackerConfig& base) {
  TrackerConfig raw_cfg = base, eskf_cfg = base;
  raw_cfg.filter = FilterKind::none;
  eskf_cfg.filter = FilterKind::eskf;
  std::array<std::vector<Out>, kLsRows> out;
  out[kLsRaw] = run_row(cam, model, walk, labelled, raw_cfg);
  out[kLsDefault] = run_row(cam, model, walk, labelled, eskf_cfg, &out[kLsSmooth]);
  out[kLsHold] = hold_row(out[kLsRaw]);
  WalkScores s;
  std::optional<Pose> known;  // what the camera could know
  for (size_t i = 0; i < walk.size(); ++i) {
    const DotFrame& f = walk[i];
    const Pose& truth = f.truth->pose;
    const int leds = labelled ? f.visible() : leds_seen(f);
    if (leds >= 3) known = truth;
    const bool still = i > 0 && rotation_angle_between(truth.R, walk[i - 1].truth->pose.R) * kDeg /
                                        (f.t - walk[i - 1].t) < kStillDegS;
    const Out& raw = out[kLsRaw][i];
    for (size_t k = 0; k < kLsRows; ++k) {
      RowScore& rs = s.rows[k];
      const Out& o = out[k][i];
      const bool tracking = o.state == PoseState::tracking;
      if (leds >= 3) {
        ++rs.frames3;
        if (tracking) ++rs.tracked3;
        if (tracking && rotation_angle_between(o.pose.R, truth.R) * kDeg > kFlipDeg) ++rs.flips;
      }
      if (o.has_pose && known) rs.known_err_deg.push_back(rotation_angle_between(o.pose.R, known->R) * kDeg);
      if (leds == 4 && tracking && raw.state == PoseState::tracking) {
        ++rs.common;
        rs.rot2 += std::pow(rotation_angle_between(o.pose.R, truth.R) * kDeg, 2);
        rs.trans2 += (o.pose.t - truth.t).squaredNorm();
        rs.raw_rot2 += std::pow(rotation_angle_between(raw.pose.R, truth.R) * kDeg, 2);
        rs.raw_trans2 += (raw.pose.t - truth.t).squaredNorm();
      }
      if (still && tracking && raw.state == PoseState::tracking && out[k][i - 1].state == PoseState::tracking &&
          out[kLsRaw][i - 1].state == PoseState::tracking) {
        const Pose& prev_truth = walk[i - 1].truth->pose;
        ++rs.still;
        rs.jitter2 += (rot_err(o.pose, truth) - rot_err(out[k][i - 1].pose, prev_truth)).squaredNorm() * kDeg * kDeg;
        rs.raw_jitter2 +=
            (rot_err(raw.pose, truth) - rot_err(out[kLsRaw][i - 1].pose, prev_truth)).squaredNorm() * kDeg * kDeg;
      }
    }
  }
  return s;
}

void print_header() {
  std::printf("| walk | 3+ LED frames | tracked %% default / smooth / raw | RMS rot default / smooth vs raw | "
              "RMS trans default / smooth vs raw | raw RMS rot (deg) / trans (mm) | still jitter default / smooth vs raw "
              "(raw deg) | every row vs what the camera knew, p99 / max (deg): default | smooth | hold-last | raw | flips default / smooth / raw |\n");
  std::printf("|---|---:|---|---|---|---|---|---|---|---|---|---|\n");
}

void print_row(const std::string& name, const WalkScores& s) {
  const auto& d = s.rows[kLsDefault];
  const auto& sm = s.rows[kLsSmooth];
  const auto& raw = s.rows[kLsRaw];
  const auto& h = s.rows[kLsHold];
  const double n = static_cast<double>(std::max(1L, raw.common)), ns = static_cast<double>(std::max(1L, raw.still));
  std::printf("| %s | %ld | %.2f / %.2f / %.2f | %.2f / %.2f | %.2f / %.2f | %.2f / %.1f | %.2f / %.2f (%.3f) | "
              "%.1f / %.1f | %.1f / %.1f | %.1f / %.1f | %.1f / %.1f | %ld / %ld / %ld |\n",
              name.c_str(), d.frames3, d.tracked_pct(), sm.tracked_pct(), raw.tracked_pct(), d.rms_rot_ratio(),
              sm.rms_rot_ratio(), d.rms_trans_ratio(), sm.rms_trans_ratio(), std::sqrt(raw.raw_rot2 / n), std::sqrt(raw.raw_trans2 / n),
              d.jitter_ratio(), sm.jitter_ratio(), std::sqrt(raw.raw_jitter2 / ns), d.known_quantile(0.99), d.known_quantile(1.0),
              sm.known_quantile(0.99), sm.known_quantile(1.0), h.known_quantile(0.99), h.known_quantile(1.0),
              raw.known_quantile(0.99), raw.known_quantile(1.0), d.flips, sm.flips, raw.flips);
  std::fflush(stdout);
}

}  // namespace earshot::tracker::bench
