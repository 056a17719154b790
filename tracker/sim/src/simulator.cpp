#include "earshot/tracker/sim/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace earshot::tracker {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

std::optional<PixelModel> pixel_model_from(std::string_view name) {
  if (name == "exact") return PixelModel::exact;
  if (name == "integer") return PixelModel::integer;
  if (name == "quantize8") return PixelModel::quantize8;
  if (name == "gaussian") return PixelModel::gaussian;
  return std::nullopt;
}

std::optional<MotionProfile> motion_profile_from(std::string_view name) {
  for (auto m : {MotionProfile::walk, MotionProfile::seated, MotionProfile::orienting, MotionProfile::nodding,
                 MotionProfile::walking, MotionProfile::tremor, MotionProfile::mixed, MotionProfile::listener,
                 MotionProfile::sweep})
    if (name == motion_profile_name(m)) return m;
  return std::nullopt;
}

std::string_view motion_profile_name(MotionProfile m) {
  switch (m) {
    case MotionProfile::walk: return "walk";
    case MotionProfile::seated: return "seated";
    case MotionProfile::orienting: return "orienting";
    case MotionProfile::nodding: return "nodding";
    case MotionProfile::walking: return "walking";
    case MotionProfile::tremor: return "tremor";
    case MotionProfile::mixed: return "mixed";
    case MotionProfile::listener: return "listener";
    case MotionProfile::sweep: return "sweep";
  }
  return "?";
}

void SpeedCollector::add(const Pose& truth, double t) {
  if (have_ && t > prev_t_) deg_s_.push_back(rotation_angle_between(prev_.R, truth.R) / (t - prev_t_) / kDeg);
  prev_ = truth;
  prev_t_ = t;
  have_ = true;
}

SpeedStats SpeedCollector::stats() const {
  SpeedStats s;
  s.count = deg_s_.size();
  if (deg_s_.empty()) return s;
  std::vector<double> v = deg_s_;
  std::sort(v.begin(), v.end());
  auto q = [&](double p) { return v[static_cast<size_t>(std::min(p * static_cast<double>(v.size()), static_cast<double>(v.size() - 1)))]; };
  s.p50 = q(0.5);
  s.p99 = q(0.99);
  s.max = v.back();
  return s;
}

namespace {

/// The OU head and its box for each listener profile (see simulator.hpp).
struct ProfileBox {
  std::array<double, 3> ang_rms_deg_s;  ///< yaw, pitch, roll
  double tau_ang_s;
  double speed_mm_s;
  double tau_trans_s;
  std::array<double, 3> ang_max_deg;  ///< yaw, pitch, roll bounds of the OU head
  double lateral_fraction;
  double z_min_mm, z_max_mm;
};

ProfileBox box_of(MotionProfile m) {
  switch (m) {
    case MotionProfile::orienting: return {{12, 8, 4}, 0.5, 15, 1.0, {6, 15, 10}, 0.3, 800, 1200};
    case MotionProfile::nodding: return {{20, 10, 6}, 0.5, 20, 1.0, {25, 12, 12}, 0.3, 800, 1200};
    case MotionProfile::walking: return {{20, 10, 5}, 0.5, 100, 1.0, {25, 15, 10}, 0.45, 900, 1500};
    case MotionProfile::tremor: return {{25, 12, 6}, 0.5, 20, 1.0, {30, 20, 15}, 0.3, 800, 1200};
    case MotionProfile::seated:
    default: return {{30, 15, 8}, 0.5, 20, 1.0, {30, 20, 15}, 0.3, 800, 1200};
  }
}

constexpr double kTurnYawMaxDeg = 30.0;  ///< quick turns reach at most this far from the front
constexpr double kTau = 2.0 * std::numbers::pi;

}  // namespace

Simulator::Simulator(const Camera& cam, const LedModel& model, SimulatorConfig cfg)
    : cam_(cam), model_(model), cfg_(cfg), rng_(cfg.seed) {
  // Start in the middle of the walk's box, facing the camera.
  s_ << 0.0, 0.0, 0.5 * (cfg_.z_min_mm + cfg_.z_max_mm), 0.0, 0.0, 0.0;
  active_ = cfg_.motion;
  if (cfg_.motion == MotionProfile::walk) return;  // the walk draws nothing here: old files stay
  if (cfg_.motion == MotionProfile::sweep) {
    s_ << 0.0, 0.0, 1000.0, 0.0, 0.0, 0.0;
    for (size_t i = 0; i < 6; ++i) {
      draw_sweep_speed(i);
      if (uniform_(rng_) < 0.5) sweep_v_[i] = -sweep_v_[i];
    }
    return;
  }
  if (cfg_.motion == MotionProfile::mixed) active_ = MotionProfile::seated;
  const ProfileBox b = box_of(active_);
  s_[2] = 0.5 * (b.z_min_mm + b.z_max_mm);
  // Per-listener constants, drawn once.
  step_f_ = 1.7 + 0.4 * uniform_(rng_);
  bob_mm_ = 15.0 + 10.0 * uniform_(rng_);
  sway_mm_ = 15.0 + 10.0 * uniform_(rng_);
  tremor_f_ = 4.0 + 3.0 * uniform_(rng_);
  tremor_amp_ = (0.5 + 1.0 * uniform_(rng_)) * kDeg;
  next_turn_t_ = 0.5 + 2.0 * uniform_(rng_);
  next_bout_t_ = 0.5 + 2.0 * uniform_(rng_);
  next_switch_t_ = 0.0;
  if (cfg_.motion == MotionProfile::listener) next_look_t_ = 20.0 + 10.0 * uniform_(rng_);  // drawn last: other profiles' walks stay
}

void Simulator::step_profile(double dt, double t) {
  if (cfg_.motion == MotionProfile::mixed && t >= next_switch_t_ && !turning_) {
    static constexpr std::array<MotionProfile, 5> kinds{MotionProfile::seated, MotionProfile::orienting,
                                                        MotionProfile::nodding, MotionProfile::walking,
                                                        MotionProfile::tremor};
    MotionProfile next = active_;
    while (next == active_) next = kinds[std::min<size_t>(4, static_cast<size_t>(uniform_(rng_) * 5.0))];
    active_ = next;
    next_switch_t_ = t + 10.0 + 10.0 * uniform_(rng_);
  }
  step_ou_head(dt);
  step_turns(t);
  step_rhythms(dt, t);
}

void Simulator::step_ou_head(double dt) {
  const ProfileBox b = box_of(active_);
  // The OU head: velocity with the profile's RMS and correlation time,
  // reflected at the box's bounds.
  const double z = s_[2];
  const double x_max = b.lateral_fraction * z * (cam_.cx / cam_.fx);
  const double y_max = b.lateral_fraction * z * (cam_.cy / cam_.fy);
  const std::array<double, 6> hi{x_max, y_max, b.z_max_mm, b.ang_max_deg[0] * kDeg, b.ang_max_deg[1] * kDeg,
                                 b.ang_max_deg[2] * kDeg};
  const std::array<double, 6> lo{-x_max, -y_max, b.z_min_mm, -hi[3], -hi[4], -hi[5]};
  for (size_t i = 0; i < 6; ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const double rms = i < 3 ? b.speed_mm_s : b.ang_rms_deg_s[i - 3] * kDeg;
    const double tau = i < 3 ? b.tau_trans_s : b.tau_ang_s;
    v_[k] += -v_[k] / tau * dt + rms * std::sqrt(2.0 / tau * dt) * normal_(rng_);
    s_[k] += v_[k] * dt;
    // Turn the velocity back at a bound without moving the head: after mixed
    // switches to a smaller box the head drifts back in at OU speed.
    if (s_[k] > hi[i]) v_[k] = -std::abs(v_[k]);
    if (s_[k] < lo[i]) v_[k] = std::abs(v_[k]);
  }
}

void Simulator::start_turn(double to, double t) {
  const double amp = std::abs(to - turn_yaw_) / kDeg;
  const double peak = std::min(500.0, 8.0 * amp * (0.85 + 0.3 * uniform_(rng_)));
  turn_from_ = turn_yaw_;
  turn_to_ = to;
  turn_t0_ = t;
  turn_T_ = std::max(0.05, 1.875 * amp / peak);  // minimum jerk: peak = 1.875 amp / T
  turning_ = true;
}

void Simulator::step_turns(double t) {
  // Quick turns: toward a sound while orienting; back to the front otherwise.
  if (turning_) {
    const double u = std::min(1.0, (t - turn_t0_) / turn_T_);
    turn_yaw_ = turn_from_ + (turn_to_ - turn_from_) * u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
    if (u >= 1.0) {
      turning_ = false;
      next_turn_t_ = t + 0.3 - 2.5 * std::log(1.0 - uniform_(rng_) * 0.999);
    }
  } else if (active_ == MotionProfile::orienting && t >= next_turn_t_) {
    double to = (2.0 * uniform_(rng_) - 1.0) * kTurnYawMaxDeg * kDeg;
    if (std::abs(to - turn_yaw_) < 20.0 * kDeg) to = turn_yaw_ + std::copysign(20.0 * kDeg, -turn_yaw_);
    start_turn(to, t);
  } else if (active_ == MotionProfile::listener && !looking_away_ && t >= next_look_t_) {
    // A look away: far enough that no LED stays in its beam.
    const double side = uniform_(rng_) < 0.5 ? -1.0 : 1.0;
    start_turn(side * (70.0 + 40.0 * uniform_(rng_)) * kDeg, t);
    looking_away_ = true;
    look_back_t_ = t + turn_T_ + 1.5 + 1.5 * uniform_(rng_);
  } else if (active_ == MotionProfile::listener && looking_away_ && t >= look_back_t_) {
    start_turn(0.0, t);
    looking_away_ = false;
    next_look_t_ = t + 60.0 + 60.0 * uniform_(rng_);
  } else if (active_ != MotionProfile::orienting && active_ != MotionProfile::listener && std::abs(turn_yaw_) > 1e-6) {
    start_turn(0.0, t);
  }
}

void Simulator::step_rhythms(double dt, double t) {
  // Nodding bouts (a bout under way finishes whatever the profile).
  if (bout_t0_ >= 0.0 && t - bout_t0_ >= bout_T_) {
    bout_t0_ = -1.0;
    next_bout_t_ = t - 5.0 * std::log(1.0 - uniform_(rng_) * 0.999);
  }
  if (bout_t0_ < 0.0 && active_ == MotionProfile::nodding && t >= next_bout_t_) {
    bout_t0_ = t;
    bout_T_ = 1.0 + 2.0 * uniform_(rng_);
    nod_f_ = 1.5 + 1.5 * uniform_(rng_);
    nod_amp_ = (4.0 + 6.0 * uniform_(rng_)) * kDeg;
    nod_phase_ = 0.0;
  }
  nod_phase_ += kTau * nod_f_ * dt;

  // Gait and tremor fade in and out (time constant 0.5 s) with their profile.
  const double ease = 1.0 - std::exp(-dt / 0.5);
  gait_level_ += ease * ((active_ == MotionProfile::walking ? 1.0 : 0.0) - gait_level_);
  tremor_level_ += ease * ((active_ == MotionProfile::tremor ? 1.0 : 0.0) - tremor_level_);
  gait_phase_ += kTau * 0.5 * step_f_ * dt;  // stride phase: half the step frequency
  tremor_phase_ += kTau * tremor_f_ * dt;
  tremor_mod_phase_ += kTau * 0.1 * dt;
}

namespace {
/// sweep: the ranges (x, y, z mm; yaw, pitch, roll deg) and median speeds
/// per axis (mm/s, deg/s); see simulator.hpp.
constexpr std::array<double, 6> kSweepLo{-120, -120, 700, -50, -35, -90};
constexpr std::array<double, 6> kSweepHi{120, 120, 1300, 50, 35, 90};
constexpr std::array<double, 6> kSweepMedian{150, 150, 150, 145, 90, 55};
constexpr double kSweepSpread = 0.6;    ///< sigma of the log-normal speed
constexpr double kSweepCap = 3.0;       ///< speeds at most this many medians
constexpr double kSweepRedrawHz = 1.0;  ///< a fresh speed mid-leg this often
}  // namespace

void Simulator::draw_sweep_speed(size_t i) {
  const double sign = sweep_v_[i] < 0.0 ? -1.0 : 1.0;
  const double v = std::min(kSweepCap, std::exp(kSweepSpread * normal_(rng_))) * kSweepMedian[i];
  sweep_v_[i] = sign * (i < 3 ? v : v * kDeg);
}

void Simulator::step_sweep(double dt) {
  for (size_t i = 0; i < 6; ++i) {
    if (uniform_(rng_) < kSweepRedrawHz * dt) draw_sweep_speed(i);
    const double lo = i < 3 ? kSweepLo[i] : kSweepLo[i] * kDeg, hi = i < 3 ? kSweepHi[i] : kSweepHi[i] * kDeg;
    s_[static_cast<Eigen::Index>(i)] += sweep_v_[i] * dt;
    double& x = s_[static_cast<Eigen::Index>(i)];
    // The range end: the velocity flips sign within this frame.
    if (x > hi || x < lo) {
      x = std::clamp(2.0 * (x > hi ? hi : lo) - x, lo, hi);
      sweep_v_[i] = -sweep_v_[i];
      draw_sweep_speed(i);
    }
  }
}

Pose Simulator::profile_pose(double t) const {
  double x = s_[0], y = s_[1], zz = s_[2];
  double yaw = s_[3] + turn_yaw_, pitch = s_[4], roll = s_[5];
  if (bout_t0_ >= 0.0) {
    const double env = std::sin(std::numbers::pi * std::clamp((t - bout_t0_) / bout_T_, 0.0, 1.0));
    pitch += nod_amp_ * env * env * std::sin(nod_phase_);
  }
  if (gait_level_ > 0.0) {
    const double g = gait_level_;
    y += g * bob_mm_ * std::sin(2.0 * gait_phase_);
    x += g * sway_mm_ * std::sin(gait_phase_);
    pitch += g * 2.5 * kDeg * std::sin(2.0 * gait_phase_ + 0.5 * std::numbers::pi);
    yaw += g * 3.0 * kDeg * std::sin(gait_phase_);
    roll += g * 2.0 * kDeg * std::sin(gait_phase_ + 0.3);
  }
  if (tremor_level_ > 0.0) {
    const double a = tremor_level_ * tremor_amp_ * (0.75 + 0.25 * std::sin(tremor_mod_phase_));
    yaw += a * std::sin(tremor_phase_);
    pitch += 0.3 * a * std::sin(tremor_phase_ + 1.0);
  }
  return {rotation_from_ypr(yaw, pitch, roll), Vec3(x, y, zz)};
}

void Simulator::step(double dt) {
  // Each coordinate follows an Ornstein-Uhlenbeck velocity (correlation time
  // one second) whose stationary RMS is the configured speed, and reflects at
  // the walk's bounds.
  const double k = 1.0;
  const double z = s_[2];
  const double x_max = cfg_.lateral_fraction * z * (cam_.cx / cam_.fx);
  const double y_max = cfg_.lateral_fraction * z * (cam_.cy / cam_.fy);
  const std::array<double, 6> lo{-x_max, -y_max, cfg_.z_min_mm, -cfg_.yaw_max_deg * kDeg,
                                 -cfg_.pitch_max_deg * kDeg, -cfg_.roll_max_deg * kDeg};
  const std::array<double, 6> hi{x_max, y_max, cfg_.z_max_mm, cfg_.yaw_max_deg * kDeg,
                                 cfg_.pitch_max_deg * kDeg, cfg_.roll_max_deg * kDeg};
  for (int i = 0; i < 6; ++i) {
    const double rms = i < 3 ? cfg_.speed_mm_s : cfg_.angular_speed_deg_s * kDeg;
    const double sigma = rms * std::sqrt(2.0 * k);
    v_[i] += -k * v_[i] * dt + sigma * std::sqrt(dt) * normal_(rng_);
    s_[i] += v_[i] * dt;
    const auto u = static_cast<size_t>(i);
    if (i == 5 && cfg_.roll_max_deg >= 180.0) {  // full circle: wrap
      s_[i] = std::remainder(s_[i], 2.0 * std::numbers::pi);
      continue;
    }
    if (s_[i] > hi[u]) {
      s_[i] = 2.0 * hi[u] - s_[i];
      v_[i] = -std::abs(v_[i]);
    } else if (s_[i] < lo[u]) {
      s_[i] = 2.0 * lo[u] - s_[i];
      v_[i] = std::abs(v_[i]);
    }
    s_[i] = std::clamp(s_[i], lo[u], hi[u]);
  }
}

double Simulator::round_pixel(double v) {
  switch (cfg_.pixels) {
    case PixelModel::exact: return v;
    case PixelModel::integer: return std::floor(v + 0.5);
    case PixelModel::quantize8: return 8.0 * std::floor(v / 8.0 + 0.5);
    case PixelModel::gaussian: return v + cfg_.noise_px * normal_(rng_);
  }
  return v;
}

DotFrame Simulator::observe(const Pose& pose, double t) {
  DotFrame f;
  f.t = t;
  GroundTruth gt;
  gt.pose = pose;

  std::array<std::optional<Vec2>, 4> led_px;
  const double cos_half = std::cos(model_.half_angle);
  for (size_t l = 0; l < 4; ++l) {
    if (dropout_left_[l] > 0) {
      --dropout_left_[l];
      continue;
    }
    if (cfg_.dropout_rate > 0.0 && uniform_(rng_) < cfg_.dropout_rate) {
      dropout_left_[l] = 1 + static_cast<int>(uniform_(rng_) * 10.0);
      continue;
    }
    const Vec3 P = pose.apply(model_.leds_mm[l]);
    if (P.z() <= 1.0) continue;
    const Vec3 axis = pose.R * model_.axis;
    if (axis.dot(-P.normalized()) < cos_half) continue;  // turned away beyond the beam
    Vec2 px = cam_.project(P);
    px = {round_pixel(px.x()), round_pixel(px.y())};
    if (!cam_.inside(px)) continue;
    led_px[l] = px;
  }

  // Slots: a dot keeps its slot while visible; a new dot takes a random free one.
  std::array<int, kSlots> slots = slot_led_;
  for (auto& s : slots)
    if (s > 0 && !led_px[static_cast<size_t>(s - 1)]) s = 0;
  if (stray_left_ > 0) --stray_left_;
  for (auto& s : slots)
    if (s == -1 && stray_left_ == 0) s = 0;
  auto place = [&](int who) {
    std::array<int, kSlots> free{};
    int nfree = 0;
    for (int s = 0; s < kSlots; ++s)
      if (slots[static_cast<size_t>(s)] == 0) free[static_cast<size_t>(nfree++)] = s;
    if (nfree == 0) return false;
    const int pick = free[static_cast<size_t>(std::min(nfree - 1, static_cast<int>(uniform_(rng_) * nfree)))];
    slots[static_cast<size_t>(pick)] = who;
    return true;
  };
  for (int l = 0; l < 4; ++l) {
    if (!led_px[static_cast<size_t>(l)]) continue;
    if (std::find(slots.begin(), slots.end(), l + 1) == slots.end()) place(l + 1);
  }
  if (cfg_.stray_rate > 0.0 && stray_left_ == 0 && uniform_(rng_) < cfg_.stray_rate) {
    // A reflection somewhere near the beacon, staying a few frames.
    const Vec2 c = cam_.project(pose.t);
    stray_px_ = c + Vec2((uniform_(rng_) - 0.5) * 300.0, (uniform_(rng_) - 0.5) * 300.0);
    stray_px_ = {std::floor(stray_px_.x() + 0.5), std::floor(stray_px_.y() + 0.5)};
    if (cam_.inside(stray_px_) && place(-1)) stray_left_ = 1 + static_cast<int>(uniform_(rng_) * 20.0);
  }
  slot_led_ = slots;
  for (size_t s = 0; s < kSlots; ++s) {
    if (slots[s] > 0) f.slots[s] = led_px[static_cast<size_t>(slots[s] - 1)];
    if (slots[s] == -1) f.slots[s] = stray_px_;
  }
  gt.slot_led = slots;
  f.truth = gt;
  return f;
}

DotFrame Simulator::next() {
  const double dt = 1.0 / cfg_.rate_hz;
  const double t = static_cast<double>(frame_) * dt;
  if (cfg_.trace) {
    ++frame_;
    return observe(cfg_.trace->at(t), t);
  }
  if (cfg_.motion == MotionProfile::sweep) {
    if (frame_ > 0) step_sweep(dt);
    ++frame_;
    return observe({rotation_from_ypr(s_[3], s_[4], s_[5]), s_.head<3>()}, t);
  }
  if (cfg_.motion != MotionProfile::walk) {
    if (frame_ > 0) step_profile(dt, t);
    ++frame_;
    return observe(profile_pose(t), t);
  }
  if (frame_ > 0) step(dt);
  ++frame_;
  const Pose pose{rotation_from_ypr(s_[3], s_[4], s_[5]), s_.head<3>()};
  return observe(pose, t);
}

}  // namespace earshot::tracker
