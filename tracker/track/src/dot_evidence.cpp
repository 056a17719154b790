#include "earshot/tracker/track/dot_evidence.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

#include "earshot/tracker/track/labeller.hpp"
#include "earshot/tracker/solve/lm_refine.hpp"
#include "earshot/tracker/solve/p3p.hpp"

namespace earshot::tracker {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
/// A labelled LED may face up to this far beyond its beam half-angle: the
/// pose of three noisy dots is itself off by a few degrees.
constexpr double kBeamMarginRad = 0.1;
/// A real LED's beam does not end at its half-angle: its intensity falls
/// over a few degrees and the camera's threshold meets it nearer or farther
/// with distance. The share of an LED seen at an angle theta off its axis is
/// modelled as Phi((half - theta) / sigma), sigma combining this softness
/// with the pose's own uncertainty along theta.
constexpr double kBeamEdgeSoftnessRad = 2.0 * std::numbers::pi / 180.0;
/// Explanations whose dots fit worse than this (sum of squared residuals over
/// sigma^2: e^-30 against an exact fit) are not worth scoring.
constexpr double kHopelessChi2 = 60.0;
/// A P3P root whose fourth dot is this far off is not refined on four dots.
constexpr double kFourthDotGatePx = 100.0;

double log_det(const Mat6& m) {
  const Eigen::LDLT<Mat6> ldlt(m);
  return ldlt.vectorD().array().abs().log().sum();
}

/// ln N(x; mu, S + C) + 1/2 ln |C| + 3 ln 2 pi: the pose's predicted density
/// times the volume its own covariance C spans (see the header).
double log_pose_evidence(const Pose& x, const CarriedPose& c, const Mat6& C) {
  Eigen::Matrix<double, 6, 1> nu;
  nu.head<3>() = log_so3(x.R * c.pose.R.transpose());
  nu.tail<3>() = x.t - c.pose.t;
  const Mat6 S = c.spread + C;
  const Eigen::LDLT<Mat6> ldlt(S);
  return 0.5 * (log_det(C) - ldlt.vectorD().array().abs().log().sum() - nu.dot(ldlt.solve(nu)));
}

/// The Kalman update of the prediction c by the measured pose x of
/// covariance C: x + C (S + C)^-1 (prediction - x) in the error state.
Pose fuse(const Pose& x, const Mat6& C, const CarriedPose& c) {
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = log_so3(c.pose.R * x.R.transpose());
  d.tail<3>() = c.pose.t - x.t;
  const Eigen::Matrix<double, 6, 1> k = C * (c.spread + C).ldlt().solve(d);
  return Pose{exp_so3(k.head<3>()) * x.R, x.t + k.tail<3>()};
}

double log_sum_exp(double a, double b) {
  const double m = std::max(a, b);
  return m + std::log(std::exp(a - m) + std::exp(b - m));
}

bool same_pose(const Pose& a, const Pose& b) {
  return rotation_angle_between(a.R, b.R) < 0.02 && (a.t - b.t).norm() < 2.0;
}

}  // namespace

std::vector<DotExplanation> explain_dots(const DotFrame& f, const Camera& cam, const LedModel& model, double pixel_variance) {
  std::vector<Vec2> px;
  std::vector<int> slot;
  for (size_t s = 0; s < kSlots; ++s)
    if (f.slots[s]) {
      px.push_back(*f.slots[s]);
      slot.push_back(static_cast<int>(s));
    }
  const int n = static_cast<int>(px.size());
  std::vector<DotExplanation> out;
  const double max_beam = model.half_angle + kBeamMarginRad;
  auto add = [&](const Pose& p, const LabelledDots& d, const std::array<int, kSlots>& slot_led) {
    if (!p.finite() || !leds_face_camera(p, model, d.view(), max_beam)) return;
    for (const auto& e : out)
      if (e.dots.count == d.count && std::equal(e.dots.items.begin(), e.dots.items.begin() + d.count, d.items.begin(),
                                                [](const auto& a, const auto& b) { return a.led == b.led && a.pixel == b.pixel; }) &&
          same_pose(e.pose, p))
        return;
    DotExplanation e;
    e.pose = p;
    e.dots = d;
    e.slot_led = slot_led;
    e.strays = n - d.count;
    out.push_back(e);
  };
  // Every set of 3 or 4 dots, every injective labelling of it.
  for (int mask = 0; mask < (1 << n); ++mask) {
    const int k = std::popcount(static_cast<unsigned>(mask));
    if (k < 2) continue;
    std::vector<int> which;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) which.push_back(i);
    std::array<int, 4> leds{0, 1, 2, 3};
    do {
      // Each permutation's first k entries: every ordered choice of k of the
      // four LEDs once (4 x 3 x 2 = 4! for three).
      LabelledDots d;
      std::array<int, kSlots> slot_led{-1, -1, -1, -1};
      for (int i = 0; i < k; ++i) {
        const auto w = static_cast<size_t>(which[static_cast<size_t>(i)]);
        d.add(leds[static_cast<size_t>(i)], px[w]);
        slot_led[static_cast<size_t>(slot[w])] = leds[static_cast<size_t>(i)];
      }
      if (k == 2) {
        // Two LEDs fix no pose: the explanation that the other dots are
        // strays, scored against the prediction alone (score_explanation).
        if (leds[3] < leds[2]) continue;  // each ordered pair once
        DotExplanation e;
        e.partial = true;
        for (const auto& c : d.view()) e.dots.add(c.led, c.pixel);
        e.slot_led = slot_led;
        e.strays = n - 2;
        out.push_back(e);
        continue;
      }
      std::array<Vec3, 3> bearings, pts;
      for (size_t i = 0; i < 3; ++i) {
        bearings[i] = cam.bearing(d.items[i].pixel);
        pts[i] = model.leds_mm[static_cast<size_t>(d.items[i].led)];
      }
      const P3PSolutions roots = p3p_lambda_twist(bearings, pts);
      for (int r = 0; r < roots.count; ++r) {
        Pose p = roots.poses[static_cast<size_t>(r)];
        if (k == 4) {
          const Vec3 P = p.apply(model.leds_mm[static_cast<size_t>(d.items[3].led)]);
          if (P.z() <= 1.0 || (cam.project(P) - d.items[3].pixel).norm() > kFourthDotGatePx) continue;
          p = refine_pose_lm(p, d.view(), cam, model).pose;
          const double rms = rms_reprojection_error(p, d.view(), cam, model);
          if (!(4.0 * rms * rms <= kHopelessChi2 * pixel_variance)) continue;
        }
        add(p, d, slot_led);
      }
    } while (std::next_permutation(leds.begin(), leds.end()));
  }
  return out;
}

namespace {
/// The chance that `led` is in view at `pose` (covariance C): inside the
/// image, in front, and within its beam (kBeamEdgeSoftnessRad). The
/// off-axis angle theta = acos(a . u), a = R axis, u = -P/|P|, changes
/// under the left perturbation (omega, dt) of the pose by
///   d cos(theta) = omega . (a x u - (R L) x v) - v . dt,  v = (I - p p^T) a / |P|,
/// p = P/|P|, which gives theta's variance from C.
double chance_in_view(const Pose& pose, const Mat6& C, const LedModel& model, const Camera& cam, size_t led) {
  const Vec3 RL = pose.R * model.leds_mm[led];
  const Vec3 P = RL + pose.t;
  if (!(P.z() > 1.0) || !cam.inside(cam.project(P))) return 0.0;
  const double r = P.norm();
  const Vec3 p = P / r, u = -p, a = pose.R * model.axis;
  const double c = std::clamp(a.dot(u), -1.0, 1.0);
  const double theta = std::acos(c);
  const Vec3 v = (a - p * p.dot(a)) / r;
  Eigen::Matrix<double, 6, 1> g;
  g.head<3>() = a.cross(u) - RL.cross(v);
  g.tail<3>() = -v;
  const double sin_theta = std::max(std::sqrt(1.0 - c * c), 1e-6);
  const double var = g.dot(C * g) / (sin_theta * sin_theta) + kBeamEdgeSoftnessRad * kBeamEdgeSoftnessRad;
  return 0.5 * std::erfc((theta - model.half_angle) / std::sqrt(2.0 * var));
}

/// ln N(dots; their projection at the prediction, J P J^T + sigma^2 I): two
/// LEDs' dots under a prediction of spread P, the pose integrated out.
double log_dots_given_prediction(const LabelledDots& d, const CarriedPose& c, const Camera& cam, const LedModel& model,
                                 double var) {
  Eigen::Matrix<double, 4, 6> J;
  Eigen::Vector4d nu;
  for (int i = 0; i < 2; ++i) {
    const auto& led = model.leds_mm[static_cast<size_t>(d.items[static_cast<size_t>(i)].led)];
    const Vec3 P = c.pose.apply(led);
    if (P.z() <= 1.0) return -INFINITY;
    J.block<2, 6>(2 * i, 0) = reprojection_jacobian(c.pose, led, cam);
    nu.segment<2>(2 * i) = d.items[static_cast<size_t>(i)].pixel - cam.project(P);
  }
  const Eigen::Matrix4d S = J * c.spread * J.transpose() + var * Eigen::Matrix4d::Identity();
  const Eigen::LDLT<Eigen::Matrix4d> ldlt(S);
  return -0.5 * (nu.dot(ldlt.solve(nu)) + ldlt.vectorD().array().abs().log().sum() + 4.0 * std::log(kTwoPi));
}
}  // namespace

void score_explanation(DotExplanation& e, const Camera& cam, const LedModel& model, const EvidenceModel& g,
                       const std::optional<MotionPrior>& prior) {
  const double var = g.pixel_variance;
  if (e.partial) {
    if (!prior) return;  // nothing to score two dots against
    e.pose = e.fused = prior->nominal.pose;
  }
  double ssr = 0.0;
  for (const auto& c : e.dots.view()) {
    const Vec3 P = e.pose.apply(model.leds_mm[static_cast<size_t>(c.led)]);
    ssr += P.z() > 1.0 ? (cam.project(P) - c.pixel).squaredNorm() : 1e12;
  }
  double l = -e.dots.count * std::log(kTwoPi * var) - 0.5 * ssr / var;
  // Strays: uniform over the image; none: the frames without one.
  l += e.strays > 0 ? e.strays * std::log(g.stray_share / (cam.width * cam.height)) : std::log(1.0 - g.stray_share);
  // Every LED is seen (in view and not dropped out) or unseen (out of view
  // or dropped out); whether it is in view is uncertain near its beam edge.
  if (!e.partial) e.cov = pose_covariance(e.pose, e.dots.view(), cam, model, var);
  const Mat6& pose_cov = e.partial ? prior->nominal.spread : e.cov;
  for (int led = 0; led < 4; ++led) {
    bool seen = false;
    for (const auto& c : e.dots.view()) seen = seen || c.led == led;
    const double seen_share = (1.0 - g.dropped_share) * chance_in_view(e.pose, pose_cov, model, cam, static_cast<size_t>(led));
    l += std::log(std::max(seen ? seen_share : 1.0 - seen_share, 1e-12));
  }
  if (e.partial) {
    // The dots' own term is the pose-integrated density, not a fit.
    l += e.dots.count * std::log(kTwoPi * var) + 0.5 * ssr / var;
    l += log_sum_exp(std::log(1.0 - g.wide_weight) + log_dots_given_prediction(e.dots, prior->nominal, cam, model, var),
                     std::log(g.wide_weight) + log_dots_given_prediction(e.dots, prior->wide, cam, model, var));
    e.log_evidence = l;
    return;
  }
  if (prior) {
    e.fused = fuse(e.pose, e.cov, prior->nominal);
    l += log_sum_exp(std::log(1.0 - g.wide_weight) + log_pose_evidence(e.pose, prior->nominal, e.cov),
                     std::log(g.wide_weight) + log_pose_evidence(e.pose, prior->wide, e.cov));
  } else {
    e.fused = e.pose;
    l += 0.5 * log_det(e.cov);  // a flat prior: only the volume each pose spans
  }
  e.log_evidence = l;
}

EvidenceChoice choose_explanation(const std::vector<DotExplanation>& all, double far_rad) {
  EvidenceChoice c;
  for (size_t i = 0; i < all.size(); ++i)
    if (!all[i].partial && (c.best < 0 || all[i].log_evidence > all[static_cast<size_t>(c.best)].log_evidence))
      c.best = static_cast<int>(i);
  if (c.best < 0) return c;
  const DotExplanation& b = all[static_cast<size_t>(c.best)];
  // Two LEDs and strays give no pose to give out: always a rival.
  double rival = -INFINITY;
  for (const auto& e : all)
    if (e.partial || rotation_angle_between(e.pose.R, b.pose.R) > far_rad) rival = std::max(rival, e.log_evidence);
  c.log_odds = b.log_evidence - rival;
  return c;
}

void SlotMemory::see(const DotFrame& f) {
  for (size_t s = 0; s < kSlots; ++s)
    if (!f.slots[s]) led_[s] = -1;
}

void SlotMemory::label(const std::array<int, kSlots>& slot_led) { led_ = slot_led; }

double SlotMemory::log_prior(const std::array<int, kSlots>& slot_led) const {
  constexpr double kLogSlotTaken = -4.605;  // ln 0.01
  double l = 0.0;
  for (size_t s = 0; s < kSlots; ++s)
    if (led_[s] >= 0 && slot_led[s] != led_[s]) l += kLogSlotTaken;
  return l;
}

void CameraBehaviour::observe(int leds_in_view, int leds_seen, bool stray) {
  led_frames_ += leds_in_view;
  dropped_ += std::max(0, leds_in_view - leds_seen);
  frames_ += 1.0;
  strays_ += stray ? 1.0 : 0.0;
}

// Never certain either way: a share of 0 or 1 would make an explanation impossible.
double CameraBehaviour::dropped_share() const { return std::clamp(dropped_ / led_frames_, 0.002, 0.5); }
double CameraBehaviour::stray_share() const { return std::clamp(strays_ / frames_, 0.002, 0.5); }

void PoseDistribution::add(const Pose& p) {
  if (!p.finite()) return;
  n_ += 1.0;
  if (n_ <= 1.0) {
    mean_ = p;
    return;
  }
  const double a = 1.0 / std::min(n_, memory_);
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = log_so3(p.R * mean_.R.transpose());
  d.tail<3>() = p.t - mean_.t;
  mean_ = Pose{exp_so3(a * d.head<3>()) * mean_.R, mean_.t + a * d.tail<3>()};
  cov_ = (1.0 - a) * cov_ + a * (1.0 - a) * d * d.transpose();
}

std::optional<CarriedPose> PoseDistribution::prior() const {
  if (n_ < 100.0) return std::nullopt;
  CarriedPose c;
  c.pose = mean_;
  c.spread = cov_;
  constexpr double kMinRot = 5.0 * 3.14159265358979323846 / 180.0, kMinTrans = 20.0;
  for (int i = 0; i < 3; ++i) {
    c.spread(i, i) = std::max(c.spread(i, i), kMinRot * kMinRot);
    c.spread(3 + i, 3 + i) = std::max(c.spread(3 + i, 3 + i), kMinTrans * kMinTrans);
  }
  return c;
}

}  // namespace earshot::tracker
