#include "earshot/tracker/calibration/led_calibration.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include <Eigen/Dense>

#include "earshot/errors.hpp"
#include "earshot/tracker/track/dot_tracker.hpp"

namespace earshot::tracker {
namespace {

constexpr int kMaxStructure = 13;  // 12 LED coordinates + focal
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat6S = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxStructure>;
using MatS = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxStructure, kMaxStructure>;
using VecS = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStructure, 1>;

std::string fmt(const std::string& f, double v) {
  char buf[400];
  std::snprintf(buf, sizeof buf, f.c_str(), v);
  return buf;
}

std::string fmt2(const std::string& f, double a, double b) {
  char buf[400];
  std::snprintf(buf, sizeof buf, f.c_str(), a, b);
  return buf;
}

double huber_cost(double s, double k) { return s <= k ? 0.5 * s * s : k * s - 0.5 * k * k; }
double huber_weight(double s, double k) { return s <= k ? 1.0 : k / s; }

/// The unknowns of the adjustment.
struct State {
  std::array<Vec3, 4> leds;
  double focal = 0.0;
  std::vector<Pose> poses;
};

/// The model scaled so LEDs a and b are `mm` apart, with every pose's
/// translation scaled alike: the projections do not change.
void apply_scale(State& s, const ScaleBar& bar) {
  const double d = (s.leds[static_cast<size_t>(bar.a)] - s.leds[static_cast<size_t>(bar.b)]).norm();
  const double k = bar.mm / d;
  for (auto& x : s.leds) x *= k;
  for (auto& p : s.poses) p.t *= k;
}

class Adjustment {
 public:
  Adjustment(const std::vector<LabelledFrame>& frames, const Camera& cam, const CalibrationOptions& opt)
      : frames_(frames), cam_(cam), opt_(opt), n_(opt.estimate_focal ? 13 : 12) {}

  /// Residual of one dot and its norm; false when behind the camera.
  bool residual(const State& s, size_t i, int j, Vec2& r, Vec3& P) const {
    const Correspondence& c = frames_[i].dots.items[static_cast<size_t>(j)];
    P = s.poses[i].apply(s.leds[static_cast<size_t>(c.led)]);
    if (!(P.z() > 1e-6)) return false;
    r = Vec2(s.focal * P.x() / P.z() + cam_.cx, s.focal * P.y() / P.z() + cam_.cy) - c.pixel;
    return true;
  }

  /// Robust cost (Huber, threshold k px); infinity when a point is behind the camera.
  double cost(const State& s, double k) const {
    double c = 0.0;
    Vec2 r;
    Vec3 P;
    for (size_t i = 0; i < frames_.size(); ++i)
      for (int j = 0; j < frames_[i].dots.count; ++j) {
        if (!residual(s, i, j, r, P)) return INFINITY;
        c += huber_cost(r.norm(), k);
      }
    return c;
  }

  /// Plain RMS reprojection error (px per dot) and the dots beyond k.
  std::pair<double, size_t> rms(const State& s, double k) const {
    double sum = 0.0;
    size_t n = 0, out = 0;
    Vec2 r;
    Vec3 P;
    for (size_t i = 0; i < frames_.size(); ++i)
      for (int j = 0; j < frames_[i].dots.count; ++j) {
        if (!residual(s, i, j, r, P)) continue;
        sum += r.squaredNorm();
        ++n;
        if (r.norm() > k) ++out;
      }
    return {n ? std::sqrt(sum / static_cast<double>(n)) : 0.0, out};
  }

  /// Median absolute residual coordinate scaled to a Gaussian sigma.
  double robust_sigma(const State& s) const {
    std::vector<double> a;
    Vec2 r;
    Vec3 P;
    for (size_t i = 0; i < frames_.size(); ++i)
      for (int j = 0; j < frames_[i].dots.count; ++j)
        if (residual(s, i, j, r, P)) {
          a.push_back(std::abs(r.x()));
          a.push_back(std::abs(r.y()));
        }
    if (a.empty()) return 1.0;
    std::nth_element(a.begin(), a.begin() + static_cast<long>(a.size() / 2), a.end());
    return 1.4826 * a[a.size() / 2];
  }

  /// Builds the per-frame blocks and the reduced (Schur complement) system
  /// for damping lambda. Returns false when a point is behind the camera.
  bool linearise(const State& s, double k) {
    const size_t F = frames_.size();
    U_.resize(F);
    W_.resize(F);
    gp_.resize(F);
    V_ = MatS::Zero(n_, n_);
    gx_ = VecS::Zero(n_);
    Vec2 r;
    Vec3 P;
    for (size_t i = 0; i < F; ++i) {
      Mat6 U = Mat6::Zero();
      Mat6S W = Mat6S::Zero(6, n_);
      Vec6 gp = Vec6::Zero();
      const Pose& pose = s.poses[i];
      for (int j = 0; j < frames_[i].dots.count; ++j) {
        if (!residual(s, i, j, r, P)) return false;
        const int led = frames_[i].dots.items[static_cast<size_t>(j)].led;
        const double w = huber_weight(r.norm(), k);
        const double iz = 1.0 / P.z();
        Eigen::Matrix<double, 2, 3> Jproj;
        Jproj << s.focal * iz, 0.0, -s.focal * P.x() * iz * iz, 0.0, s.focal * iz, -s.focal * P.y() * iz * iz;
        Eigen::Matrix<double, 2, 6> Jp;
        Jp.leftCols<3>() = -Jproj * skew(P - pose.t);
        Jp.rightCols<3>() = Jproj;
        Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, kMaxStructure> Jx =
            Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, kMaxStructure>::Zero(2, n_);
        Jx.block<2, 3>(0, 3 * led) = Jproj * pose.R;
        if (n_ == 13) Jx.col(12) = Vec2(P.x() * iz, P.y() * iz);
        U.noalias() += w * Jp.transpose() * Jp;
        W.noalias() += w * Jp.transpose() * Jx;
        gp.noalias() += w * Jp.transpose() * r;
        V_.noalias() += w * Jx.transpose() * Jx;
        gx_.noalias() += w * Jx.transpose() * r;
      }
      U_[i] = U;
      W_[i] = W;
      gp_[i] = gp;
    }
    return true;
  }

  /// Reduced information matrix (undamped) and right-hand side for damping lambda.
  void reduce(double lambda, MatS& S, VecS& b) {
    S = V_;
    S.diagonal() += lambda * V_.diagonal();
    b = -gx_;
    Uinv_.resize(frames_.size());
    for (size_t i = 0; i < frames_.size(); ++i) {
      Mat6 U = U_[i];
      U.diagonal() += lambda * U_[i].diagonal() + Vec6::Constant(1e-12);
      Uinv_[i] = U.ldlt().solve(Mat6::Identity());
      const Mat6S UW = Uinv_[i] * W_[i];
      S.noalias() -= W_[i].transpose() * UW;
      b.noalias() += UW.transpose() * gp_[i];
    }
  }

  /// Orthonormal basis of the steps that keep the LEDs' centroid, their mean
  /// orientation and the ruler distance (the gauge), as columns.
  MatS gauge_free_basis(const State& s) const {
    Eigen::Matrix<double, Eigen::Dynamic, 7, 0, kMaxStructure, 7> G =
        Eigen::Matrix<double, Eigen::Dynamic, 7, 0, kMaxStructure, 7>::Zero(n_, 7);
    for (int j = 0; j < 4; ++j) {
      G.block<3, 3>(3 * j, 0) = Mat3::Identity();
      G.block<3, 3>(3 * j, 3) = -skew(s.leds[static_cast<size_t>(j)]);
    }
    const Vec3 u = (s.leds[static_cast<size_t>(opt_.scale.a)] - s.leds[static_cast<size_t>(opt_.scale.b)]).normalized();
    G.block<3, 1>(3 * opt_.scale.a, 6) = u;
    G.block<3, 1>(3 * opt_.scale.b, 6) = -u;
    Eigen::HouseholderQR<MatS> qr(G);
    const MatS Qfull = qr.householderQ() * MatS::Identity(n_, n_);
    return Qfull.rightCols(n_ - 7);
  }

  /// The steps for damping lambda: structure and poses.
  void step(const State& s, double lambda, State& out) {
    MatS S;
    VecS b;
    reduce(lambda, S, b);
    const MatS Q = gauge_free_basis(s);
    const MatS A = Q.transpose() * S * Q;
    const VecS dx = Q * A.ldlt().solve(Q.transpose() * b);
    out = s;
    for (int j = 0; j < 4; ++j) out.leds[static_cast<size_t>(j)] += dx.segment<3>(3 * j);
    if (n_ == 13) out.focal += dx(12);
    for (size_t i = 0; i < frames_.size(); ++i) {
      const Vec6 dp = -Uinv_[i] * (gp_[i] + W_[i] * dx);
      out.poses[i].R = exp_so3(dp.head<3>()) * s.poses[i].R;
      out.poses[i].t = s.poses[i].t + dp.tail<3>();
    }
    last_step_mm_ = dx.head(12).norm();
  }

  /// Undamped reduced information (times sigma^2) in the gauge-free basis.
  void information(const State& s, MatS& Q, MatS& A) {
    MatS S;
    VecS b;
    reduce(0.0, S, b);
    Q = gauge_free_basis(s);
    A = Q.transpose() * S * Q;
  }

  [[nodiscard]] int structure_size() const { return n_; }
  [[nodiscard]] double last_step_mm() const { return last_step_mm_; }

 private:
  const std::vector<LabelledFrame>& frames_;
  Camera cam_;
  const CalibrationOptions& opt_;
  int n_;
  std::vector<Mat6> U_, Uinv_;
  std::vector<Mat6S> W_;
  std::vector<Vec6> gp_;
  MatS V_;
  VecS gx_;
  double last_step_mm_ = 0.0;
};

std::array<Vec3, 4> aligned_to(const std::array<Vec3, 4>& leds, const std::array<Vec3, 4>& ref) {
  const Pose a = rigid_align(leds, ref);
  std::array<Vec3, 4> out;
  for (size_t j = 0; j < 4; ++j) out[j] = a.apply(leds[j]);
  return out;
}

double spread(std::vector<double> v) {
  if (v.size() < 2) return 0.0;
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) { return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1))]; };
  return at(0.95) - at(0.05);
}

MotionSpan motion_span(const std::vector<LabelledFrame>& frames) {
  std::vector<double> yaw, pitch, roll, z, x, y;
  for (const auto& f : frames) {
    const Mat3& R = f.pose.R;
    pitch.push_back(std::asin(std::clamp(-R(1, 2), -1.0, 1.0)));
    yaw.push_back(std::atan2(R(0, 2), R(2, 2)));
    roll.push_back(std::atan2(R(1, 0), R(1, 1)));
    x.push_back(f.pose.t.x());
    y.push_back(f.pose.t.y());
    z.push_back(f.pose.t.z());
  }
  const double deg = 180.0 / std::numbers::pi;
  MotionSpan m;
  m.yaw_deg = spread(yaw) * deg;
  m.pitch_deg = spread(pitch) * deg;
  m.roll_deg = spread(roll) * deg;
  m.depth_mm = spread(z);
  m.lateral_mm = std::max(spread(x), spread(y));
  return m;
}

const char* axis_name(int a) { return a == 0 ? "x" : a == 1 ? "y" : "z"; }

/// "LED 3 z, LED 0 z (and focal)": the coordinates a direction moves most.
std::string describe(const WeakDirection& w) {
  std::vector<std::pair<double, int>> parts;
  for (int j = 0; j < 4; ++j)
    for (int a = 0; a < 3; ++a) parts.emplace_back(std::abs(w.move[static_cast<size_t>(j)][a]), 3 * j + a);
  std::sort(parts.begin(), parts.end(), [](const auto& p, const auto& q) { return p.first > q.first; });
  std::string s;
  double covered = 0.0;
  if (w.focal_share > 0.5) s = fmt("the focal length (share %.2f)", w.focal_share);
  for (const auto& [v, idx] : parts) {
    if (v < 0.2 || (!s.empty() && covered > 0.8)) break;
    covered += v * v;
    if (!s.empty()) s += ", ";
    s += "LED " + std::to_string(idx / 3) + " " + axis_name(idx % 3) + fmt(" (%.2f)", v);
  }
  if (w.focal_share > 0.2 && w.focal_share <= 0.5) s += fmt(", the focal length (share %.2f)", w.focal_share);
  return s;
}

std::vector<std::string> advise(const CalibrationResult& r, double max_sigma) {
  std::vector<std::string> a;
  double worst = 0.0;
  for (const auto& s : r.led_sigma_mm) worst = std::max(worst, s.maxCoeff());
  const bool weak = worst > 0.2 * max_sigma;
  if (r.motion.yaw_deg < 20.0)
    a.push_back(fmt("turn your head further left and right: yaw spans only %.1f deg (aim for 30 or more)", r.motion.yaw_deg));
  if (r.motion.pitch_deg < 12.0)
    a.push_back(fmt("nod further up and down: pitch spans only %.1f deg (aim for 20 or more)", r.motion.pitch_deg));
  if (!r.weakest.empty() && weak) {
    const WeakDirection& w = r.weakest.front();
    double depth = 0.0;
    for (const auto& m : w.move) depth += m.z() * m.z();
    if (w.focal_share > 0.3)
      a.push_back(fmt("move closer to and further from the camera: the focal length trades against distance "
                      "(depth spans only %.0f mm)", r.motion.depth_mm));
    else if (depth > 0.5)
      a.push_back("turn further left/right and up/down: the LEDs' depths (z) are the least determined (" +
                  w.description + "); the parallax of a turning head shows them");
    else
      a.push_back("record longer with the head moving over the whole view: the least determined direction is " +
                  w.description);
  }
  // Under weak perspective the image fixes only focal / distance; the
  // focal length shows in perspective: near the camera, toward the edges.
  if (r.focal_sigma_px > 0.002 * r.focal_px)
    a.push_back(fmt("sit closer to the camera and move your head toward the edges of its view: the focal length is "
                    "uncertain by %.2f %% (it scales every distance by as much)",
                    100.0 * r.focal_sigma_px / r.focal_px));
  if (r.frames_used < 1000)
    a.push_back("record longer: only " + std::to_string(r.frames_used) + " frames had all four LEDs in view");
  return a;
}

/// One adjustment round from `s`; calls back per accepted step.
void adjust(Adjustment& adj, State& s, int round, const CalibrationOptions& opt,
            const std::array<Vec3, 4>& reference, double& k_out) {
  const double k = std::max(1.0, opt.huber_px * adj.robust_sigma(s));
  k_out = k;
  auto report = [&](int it) {
    if (!opt.on_iteration) return;
    CalibrationIteration ci;
    ci.round = round;
    ci.iteration = it;
    ci.rms_px = adj.rms(s, k).first;
    ci.focal_px = s.focal;
    ci.leds_mm = aligned_to(s.leds, reference);
    opt.on_iteration(ci);
  };
  report(0);
  double c = adj.cost(s, k);
  double lambda = 1e-4;
  State trial;
  for (int it = 1; it <= opt.max_iterations; ++it) {
    if (!adj.linearise(s, k)) break;
    bool accepted = false;
    for (int tries = 0; tries < 12 && !accepted; ++tries) {
      adj.step(s, lambda, trial);
      apply_scale(trial, opt.scale);
      const double ct = adj.cost(trial, k);
      if (ct < c) {
        const double gain = (c - ct) / c;
        s = std::move(trial);
        c = ct;
        lambda = std::max(lambda / 3.0, 1e-9);
        accepted = true;
        report(it);
        if (gain < 1e-10 || adj.last_step_mm() < 1e-6) return;
      } else {
        lambda *= 5.0;
      }
    }
    if (!accepted) return;
  }
}

}  // namespace

ScaleBar parse_scale_bar(std::string_view text, std::string_view option) {
  auto bad = [&](const std::string& why) {
    return InputError::at(option, 0, "", "'" + std::string(text) + "': " + why);
  };
  const auto colon = text.find(':');
  const auto dash = text.find('-', colon == std::string_view::npos ? 0 : colon + 1);
  if (colon == std::string_view::npos || dash == std::string_view::npos)
    throw bad("expected D:A-B, the distance in mm between LEDs A and B (0-3), e.g. 170:0-1");
  ScaleBar s;
  const std::string d(text.substr(0, colon));
  char* end = nullptr;
  s.mm = std::strtod(d.c_str(), &end);
  if (d.empty() || end != d.c_str() + d.size() || !std::isfinite(s.mm) || !(s.mm > 0.0))
    throw bad("the distance '" + d + "' is not a positive number of mm");
  auto led = [&](std::string_view v) {
    int x = -1;
    const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || p != v.data() + v.size() || x < 0 || x > 3)
      throw bad("LED '" + std::string(v) + "' is not one of 0, 1, 2, 3");
    return x;
  };
  s.a = led(text.substr(colon + 1, dash - colon - 1));
  s.b = led(text.substr(dash + 1));
  if (s.a == s.b) throw bad("the two LEDs must differ (a distance between LED " + std::to_string(s.a) + " and itself)");
  return s;
}

Pose rigid_align(const std::array<Vec3, 4>& from, const std::array<Vec3, 4>& to) {
  Vec3 cf = Vec3::Zero(), ct = Vec3::Zero();
  for (size_t j = 0; j < 4; ++j) {
    cf += from[j] / 4.0;
    ct += to[j] / 4.0;
  }
  Mat3 H = Mat3::Zero();
  for (size_t j = 0; j < 4; ++j) H += (from[j] - cf) * (to[j] - ct).transpose();
  const Eigen::JacobiSVD<Mat3> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  Pose p;
  p.R = svd.matrixV() * D * svd.matrixU().transpose();
  p.t = ct - p.R * cf;
  return p;
}

std::array<double, 4> led_errors_after_alignment(const std::array<Vec3, 4>& estimate,
                                                 const std::array<Vec3, 4>& truth) {
  const Pose a = rigid_align(estimate, truth);
  std::array<double, 4> e{};
  for (size_t j = 0; j < 4; ++j) e[j] = (a.apply(estimate[j]) - truth[j]).norm();
  return e;
}

std::vector<LabelledFrame> label_four_dot_frames(const std::vector<DotFrame>& frames, const LedModel& model,
                                                 const Camera& camera, double gate_px) {
  TrackerConfig cfg;
  cfg.filter = FilterKind::none;
  cfg.labeller.fit_gate_px = gate_px;
  DotTracker tracker(camera, model, cfg);
  std::vector<LabelledFrame> out;
  for (const DotFrame& in : frames) {
    DotFrame f;  // the dots only: calibration must not see ground truth
    f.t = in.t;
    f.slots = in.slots;
    const TrackResult r = tracker.process(f);
    if (r.state != PoseState::tracking || r.dots_used != 4) continue;
    LabelledFrame lf;
    lf.pose = r.raw_pose;
    for (size_t s = 0; s < kSlots; ++s)
      if (r.slot_led[s] >= 0 && f.slots[s]) lf.dots.add(r.slot_led[s], *f.slots[s]);
    if (lf.dots.count == 4) out.push_back(lf);
  }
  return out;
}

CalibrationResult calibrate_led_model(const std::vector<DotFrame>& frames, const LedModel& start,
                                      const Camera& camera, const CalibrationOptions& opt, std::string_view origin) {
  const ScaleBar& bar = opt.scale;
  if (bar.a < 0 || bar.a > 3 || bar.b < 0 || bar.b > 3 || bar.a == bar.b || !(bar.mm > 0.0))
    throw InputError::at("--scale-mm", 0, "", "needs a positive distance between two distinct LEDs (0-3)");
  const double d0 = (start.leds_mm[static_cast<size_t>(bar.a)] - start.leds_mm[static_cast<size_t>(bar.b)]).norm();
  if (std::abs(bar.mm - d0) > 0.25 * d0)
    throw InputError::at("--scale-mm", 0, "",
                         fmt2("%.1f mm between LEDs " + std::to_string(bar.a) + " and " + std::to_string(bar.b) +
                                  ", but the starting model has them %.1f mm apart: measure again (in mm) or fix the model",
                              bar.mm, d0));
  auto progress = [&](const std::string& s) {
    if (opt.on_progress) opt.on_progress(s);
  };
  CalibrationResult res;
  res.frames_read = frames.size();
  Camera cam = camera;
  State s;
  s.leds = start.leds_mm;
  s.focal = camera.fx;
  double k = 1.0;
  std::vector<LabelledFrame> used;
  for (int round = 1; round <= 2; ++round) {
    LedModel current = start;
    current.leds_mm = aligned_to(s.leds, start.leds_mm);
    cam = Camera::with_focal(s.focal, camera.width, camera.height);
    cam.cx = camera.cx;
    cam.cy = camera.cy;
    std::vector<LabelledFrame> four =
        label_four_dot_frames(frames, current, cam, round == 1 ? opt.label_gate_px : LabellerOptions{}.fit_gate_px);
    if (round == 1) {
      res.frames_four = four.size();
      if (four.size() < opt.min_frames)
        throw InputError::at(origin, 0, "",
                             "too few frames with all four LEDs labelled to calibrate: " + std::to_string(four.size()) +
                                 " of " + std::to_string(frames.size()) + " (need " + std::to_string(opt.min_frames) +
                                 "); record with all four LEDs in the camera's view, facing it, and check that the "
                                 "starting model is within a few mm of the rig");
    }
    used.clear();
    const size_t n = std::min(four.size(), opt.max_frames);
    for (size_t i = 0; i < n; ++i) used.push_back(four[i * four.size() / n]);
    if (round == 1) {
      res.motion = motion_span(used);
      if (std::max(res.motion.yaw_deg, res.motion.pitch_deg) < opt.min_turn_deg)
        throw InputError::at(origin, 0, "",
                             fmt2("too little motion to calibrate: the head turned over only %.1f deg of yaw and "
                                  "%.1f deg of pitch",
                                  res.motion.yaw_deg, res.motion.pitch_deg) +
                                 fmt(" (need %.0f deg); record again turning your head left and right and nodding "
                                     "up and down while all four LEDs stay in view",
                                     opt.min_turn_deg));
    }
    progress("round " + std::to_string(round) + ": " + std::to_string(four.size()) + " of " +
             std::to_string(frames.size()) + " frames with four LEDs labelled, adjusting over " +
             std::to_string(used.size()));
    // The model as it stands, in the ruler's scale; the poses start from
    // the labelling's (which used that model aligned to the start).
    s.leds = current.leds_mm;
    s.poses.clear();
    for (const auto& f : used) s.poses.push_back(f.pose);
    apply_scale(s, bar);
    Adjustment adj(used, cam, opt);
    if (round == 1) res.rms_before_px = adj.rms(s, 1e300).first;
    adjust(adj, s, round, opt, start.leds_mm, k);
    progress(fmt2("round " + std::to_string(round) + ": RMS residual %.3f px, focal %.1f px",
                  adj.rms(s, k).first, s.focal));
  }
  // How well the result is determined.
  Adjustment adj(used, cam, opt);
  adj.linearise(s, k);
  const auto [rms_after, outliers] = adj.rms(s, k);
  res.rms_after_px = rms_after;
  res.frames_used = used.size();
  res.outlier_dots = outliers;
  const int nS = adj.structure_size();
  const double dof = 2.0 * 4.0 * static_cast<double>(used.size()) - 6.0 * static_cast<double>(used.size()) - (nS - 7);
  res.pixel_sigma_px = std::sqrt(2.0 * adj.cost(s, k) / std::max(dof, 1.0));
  MatS Q, A;
  adj.information(s, Q, A);
  const double var = res.pixel_sigma_px * res.pixel_sigma_px;
  const MatS cov = var * Q * A.ldlt().solve(Q.transpose());
  const Pose align = rigid_align(s.leds, start.leds_mm);
  res.model = start;
  for (size_t j = 0; j < 4; ++j) {
    res.model.leds_mm[j] = align.apply(s.leds[j]);
    res.moved_mm[j] = (res.model.leds_mm[j] - start.leds_mm[j]).norm();
    const Mat3 c = align.R * cov.block<3, 3>(3 * static_cast<long>(j), 3 * static_cast<long>(j)) * align.R.transpose();
    res.led_sigma_mm[j] = c.diagonal().cwiseMax(0.0).cwiseSqrt();
  }
  res.focal_px = s.focal;
  if (nS == 13) res.focal_sigma_px = std::sqrt(std::max(cov(12, 12), 0.0));
  const Eigen::SelfAdjointEigenSolver<MatS> eig(A / var);
  for (int e = 0; e < std::min<int>(3, static_cast<int>(A.rows())); ++e) {
    WeakDirection w;
    const double lam = eig.eigenvalues()(e);
    w.sigma_mm = lam > 0.0 ? 1.0 / std::sqrt(lam) : INFINITY;
    const VecS v = Q * eig.eigenvectors().col(e);
    for (size_t j = 0; j < 4; ++j) w.move[j] = align.R * v.segment<3>(3 * static_cast<long>(j));
    if (nS == 13) w.focal_share = v(12) * v(12);
    w.description = describe(w);
    res.weakest.push_back(w);
  }
  res.advice = advise(res, opt.max_led_sigma_mm);
  double worst = 0.0;
  int worst_led = 0;
  for (int j = 0; j < 4; ++j)
    if (res.led_sigma_mm[static_cast<size_t>(j)].maxCoeff() > worst) {
      worst = res.led_sigma_mm[static_cast<size_t>(j)].maxCoeff();
      worst_led = j;
    }
  if (!(worst <= opt.max_led_sigma_mm)) {
    std::string msg = fmt("the recording does not determine the model: LED " + std::to_string(worst_led) +
                              " is uncertain by %.2f mm",
                          worst) +
                      fmt(" (1 sigma; at most %.2f mm accepted)", opt.max_led_sigma_mm);
    if (!res.weakest.empty()) msg += "; least determined: " + res.weakest.front().description;
    for (const auto& a : res.advice) msg += "; " + a;
    throw InputError::at(origin, 0, "", msg);
  }
  return res;
}

void save_led_model(const LedModel& model, const std::string& path) {
  auto round4 = [](double v) { return std::round(v * 1e4) / 1e4; };
  nlohmann::json j;
  j["leds_mm"] = nlohmann::json::array();
  for (const auto& p : model.leds_mm) j["leds_mm"].push_back({round4(p.x()), round4(p.y()), round4(p.z())});
  j["axis"] = {model.axis.x(), model.axis.y(), model.axis.z()};
  j["half_angle_deg"] = model.half_angle * 180.0 / std::numbers::pi;
  std::ofstream out(path);
  if (!out) throw InputError::at(path, 0, "", "cannot create file");
  out << j.dump(2) << "\n";
  out.flush();
  if (!out) throw InputError::at(path, 0, "", "write failed");
}

}  // namespace earshot::tracker
