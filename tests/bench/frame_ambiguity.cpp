#include "frame_ambiguity.hpp"

#include <cmath>
#include <numbers>

#include "earshot/tracker/track/accuracy.hpp"
#include "earshot/tracker/solve/lm_refine.hpp"

namespace earshot::tracker::bench {
namespace {
/// ln 100: the odds the dot tracker asks of one explanation over another.
constexpr double kDecidedLogRatio = 4.605;
constexpr double kFlipRad = kFlipDeg * std::numbers::pi / 180.0;
}  // namespace

GenerativeModel walk_model(double pixel_variance, double ang_rms_deg_s, double speed_mm_s, double dropped_share,
                           double stray_share) {
  GenerativeModel g;
  g.evidence = EvidenceModel{pixel_variance, dropped_share, stray_share, 0.1};
  // Simulator::step: each coordinate's velocity is OU with correlation time
  // 1 s and stationary RMS `rms`, i.e. acceleration density 2 rms^2 / tau.
  const double w = ang_rms_deg_s * std::numbers::pi / 180.0;
  g.motion = OuMotion{2.0 * w * w, 2.0 * speed_mm_s * speed_mm_s, 1.0, 1.0};
  return g;
}

AmbiguityOracle::AmbiguityOracle(const Camera& cam, const LedModel& model, GenerativeModel g, StateFeed feed)
    : cam_(cam), model_(model), g_(g), feed_(feed), state_([&] {
        EskfParams p;
        p.angular_accel_psd = g.motion.q_rot;
        p.linear_accel_psd = g.motion.q_trans;
        p.adaptive_process_noise = false;  // the model is known: nothing to adapt
        p.persistence_test = false;
        return p;
      }()) {}

std::optional<DotExplanation> AmbiguityOracle::truth(const DotFrame& f) const {
  DotExplanation e;
  int n = 0;
  for (size_t s = 0; s < kSlots; ++s) {
    if (!f.slots[s]) continue;
    ++n;
    if (f.truth->slot_led[s] > 0) {
      e.dots.add(f.truth->slot_led[s] - 1, *f.slots[s]);
      e.slot_led[s] = f.truth->slot_led[s] - 1;
    }
  }
  if (e.dots.count < 3) return std::nullopt;
  e.pose = refine_pose_lm(f.truth->pose, e.dots.view(), cam_, model_).pose;
  e.strays = n - e.dots.count;
  return e;
}

FrameJudgement AmbiguityOracle::judge(const DotFrame& f) {
  FrameJudgement j;
  auto t = truth(f);
  if (!t) return j;
  std::optional<MotionPrior> prior;
  if (state_.initialised()) {
    const OuMotion& m = g_.motion;
    prior = MotionPrior{carry_ou(state_.last_step(), f.t, m),
                        carry_ou(state_.last_step(), f.t, OuMotion{kMaxManoeuvreScale * m.q_rot, kMaxManoeuvreScale * m.q_trans, m.tau_rot_s, m.tau_trans_s})};
  }
  score_explanation(*t, cam_, model_, g_.evidence, prior);
  t->log_evidence += slots_.log_prior(t->slot_led);
  const bool truth_near = rotation_angle_between(t->fused.R, f.truth->pose.R) <= kFlipRad;
  double near = truth_near ? t->log_evidence : -INFINITY, far = truth_near ? -INFINITY : t->log_evidence;
  double best = t->log_evidence;
  std::vector<DotExplanation> all = explain_dots(f, cam_, model_, g_.evidence.pixel_variance);
  for (auto& e : all) {
    score_explanation(e, cam_, model_, g_.evidence, prior);
    e.log_evidence += slots_.log_prior(e.slot_led);
    // Two LEDs and strays: a tracker that believes it gives out nothing,
    // and a pose from three of the dots may be wrong.
    const bool flip = e.partial || rotation_angle_between(e.fused.R, f.truth->pose.R) > kFlipRad;
    (flip ? far : near) = std::max(flip ? far : near, e.log_evidence);
    best = std::max(best, e.log_evidence);
  }
  for (const auto& e : all) j.explanations += e.log_evidence > best - 20.0;
  j.log_ratio = near - far;
  j.verdict = near == -INFINITY            ? Verdict::none_near
              : j.log_ratio >= kDecidedLogRatio ? Verdict::decided
              : j.log_ratio >= 0.0              ? Verdict::within_100
                                                : Verdict::rival_ahead;
  if (j.verdict == Verdict::decided || feed_ == StateFeed::every_frame) {
    state_.update(t->pose, t->cov, f.t);
    slots_.label(t->slot_led);
  }
  return j;
}

}  // namespace earshot::tracker::bench
