// A simulated Wii Remote camera watching the beacon on a random walk
// (like the thesis's section 5.1, with the camera's real behaviour):
// perspective projection, pixel quantisation or noise, dots outside the
// image or LEDs turned beyond their beam half-angle are not seen, dots keep
// their camera slot while visible and take a random free slot when they
// (re)appear, optional dropouts and a stray reflection.
//
// Motion profiles (SimulatorConfig::motion). `walk` is the original random
// walk (Ornstein-Uhlenbeck velocity per coordinate, correlation time 1 s,
// over the whole box); the others model a listener in front of the camera:
//
//  seated     OU angular velocity (RMS yaw 30, pitch 15, roll 8 deg/s,
//             correlation time 0.5 s) and slow translation (20 mm/s) in a
//             small box: the slow, continuous exploring head movements of a
//             seated listener (Thurlow et al. 1967, "Head movements during
//             sound localization", JASA 42:489).
//  orienting  a calmer seated head plus quick turns toward a sound (Poisson,
//             0.4/s, 20-60 deg, within +-30 deg of the front): minimum-jerk
//             yaw trajectories whose peak velocity grows with amplitude (the
//             head "main sequence", Zangemeister, Jones & Stark 1981, Exp.
//             Neurol. 71:76), 8 x amplitude per second (+-15 %), capped at
//             500 deg/s, i.e. ~0.23 s per turn (Iwaya & Katz 2019, ICA:
//             orienting speed grows with the rotation needed).
//  nodding    seated plus bouts (0.2/s, 1-3 s) of pitch nods at 1.5-3 Hz,
//             4-10 deg amplitude, under a smooth envelope.
//  walking    walking in place / on a treadmill facing the camera: vertical
//             bob at the step frequency (1.7-2.1 Hz, 15-25 mm), lateral sway
//             at half of it (15-25 mm) and the compensating head pitch / yaw
//             oscillations of a few degrees (Hirasaki et al. 1999, Exp. Brain
//             Res. 127:117; Grossman et al. 1988, Exp. Brain Res. 70:470),
//             over a seated-like OU head and 100 mm/s drift.
//  tremor     seated plus a 4-7 Hz oscillation (mostly yaw, "no-no"), 0.5-1.5
//             deg amplitude, slowly modulated: the range of pathological head
//             tremor (Deuschl et al. 1998, Mov. Disord. 13 S3:2).
//  mixed      10-20 s segments of the five above in random order.
//  sweep      fast and impulsive, written apart from `walk` as a second fast
//             generator: each of yaw (+-50 deg), pitch (+-35), roll (+-90),
//             x, y (+-120 mm) and z (700-1300 mm) sweeps at a constant speed
//             drawn per leg (log-normal: median yaw 145, pitch 90, roll 55
//             deg/s, 150 mm/s; capped at 3x), and reverses in one frame at
//             its range ends (a head stopped by a headrest or the neck's
//             range), with a fresh speed now and then (1/s) mid-leg.
//  listener   the demo's simulated listener (the default of SimSource): the
//             seated head, in view, and now and then a look away: a quick
//             turn of 70-110 deg yaw (minimum jerk, capped at 500 deg/s, as
//             orienting's turns) that takes every LED out of its beam, held
//             1.5-3 s, and back. The first comes 20-30 s in (so a 30 s demo
//             shows the hold and ease of a loss), then one every 60-120 s.
//
// Angular speed, p50 / p99 / max deg/s (seeds 1001-1003, 60 s each):
// walk 59/128/174, seated 28/73/102, orienting 13/180/471, nodding
// 21/105/179, walking 33/67/92, tremor 25/73/106, mixed 23/136/392. The
// bands tests/unit/tracker/test_simulator.cpp holds them to are there;
// `earshot track simulate` prints each file's.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <string_view>
#include <vector>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/led_model.hpp"
#include "earshot/tracker/sim/head_trace.hpp"

namespace earshot::tracker {

enum class PixelModel { exact, integer, quantize8, gaussian };
[[nodiscard]] std::optional<PixelModel> pixel_model_from(std::string_view name);

enum class MotionProfile { walk, seated, orienting, nodding, walking, tremor, mixed, listener, sweep };
[[nodiscard]] std::optional<MotionProfile> motion_profile_from(std::string_view name);
[[nodiscard]] std::string_view motion_profile_name(MotionProfile m);

struct SimulatorConfig {
  /// How the head moves. `walk` uses the box and speeds below; the other
  /// profiles use their own (documented above) and ignore them.
  MotionProfile motion = MotionProfile::walk;
  std::uint64_t seed = 1;
  double rate_hz = 100.0;
  double z_min_mm = 600.0, z_max_mm = 1600.0;  ///< distance from the camera
  double lateral_fraction = 0.7;  ///< beacon centre stays in this part of the image
  double yaw_max_deg = 45.0, pitch_max_deg = 30.0;
  double roll_max_deg = 30.0;     ///< >= 180 lets roll turn the full circle
  double speed_mm_s = 150.0;      ///< typical (RMS) translation speed
  double angular_speed_deg_s = 40.0;  ///< typical (RMS) angular speed
  PixelModel pixels = PixelModel::integer;
  double noise_px = 0.5;          ///< sigma for PixelModel::gaussian
  double dropout_rate = 0.0;      ///< per LED and frame: chance a dropout starts
  double stray_rate = 0.0;        ///< per frame: chance a stray reflection appears
  /// A recorded head (head_trace.hpp): when set, it moves the beacon instead
  /// of `motion`.
  std::shared_ptr<const HeadTrace> trace{};
};

/// Angular speed statistics of a motion (deg/s), from consecutive
/// ground-truth poses: what `track simulate` prints.
struct SpeedStats {
  double p50 = 0.0, p99 = 0.0, max = 0.0;
  size_t count = 0;
};

class SpeedCollector {
 public:
  /// The next frame's true pose at time t (seconds).
  void add(const Pose& truth, double t);
  [[nodiscard]] SpeedStats stats() const;

 private:
  std::vector<double> deg_s_;
  Pose prev_;
  double prev_t_ = 0.0;
  bool have_ = false;
};

class Simulator {
 public:
  Simulator(const Camera& cam, const LedModel& model, SimulatorConfig cfg);
  /// The next frame, with ground truth.
  DotFrame next();
  /// Dots of a given pose at time t under this camera's rules (slots kept from
  /// the previous call). Exposed for tests.
  DotFrame observe(const Pose& pose, double t);

 private:
  void step(double dt);
  void step_profile(double dt, double t);
  // The steps of step_profile, in order.
  void step_ou_head(double dt);
  void step_turns(double t);
  void start_turn(double to, double t);
  void step_rhythms(double dt, double t);
  void step_sweep(double dt);
  void draw_sweep_speed(size_t axis);
  [[nodiscard]] Pose profile_pose(double t) const;
  double round_pixel(double v);

  Camera cam_;
  LedModel model_;
  SimulatorConfig cfg_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  long frame_ = 0;
  // walk state: x, y, z (mm), yaw, pitch, roll (rad) and their velocities
  Eigen::Matrix<double, 6, 1> s_ = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> v_ = Eigen::Matrix<double, 6, 1>::Zero();
  std::array<int, kSlots> slot_led_{0, 0, 0, 0};  // 1-4 LED, 0 empty, -1 stray
  std::array<int, 4> dropout_left_{0, 0, 0, 0};
  // listener profiles: the profile in force (mixed switches it), quick
  // turns (yaw added to the OU head), nodding bouts, walking and tremor phases
  MotionProfile active_ = MotionProfile::walk;
  double next_switch_t_ = 0.0;
  double turn_yaw_ = 0.0, turn_from_ = 0.0, turn_to_ = 0.0, turn_t0_ = 0.0, turn_T_ = 0.0;
  bool turning_ = false;
  double next_turn_t_ = 0.0;
  bool looking_away_ = false;
  double next_look_t_ = 1e300, look_back_t_ = 0.0;
  double bout_t0_ = -1.0, bout_T_ = 0.0, nod_f_ = 2.0, nod_amp_ = 0.0, nod_phase_ = 0.0, next_bout_t_ = 0.0;
  double step_f_ = 1.9, bob_mm_ = 20.0, sway_mm_ = 20.0, gait_phase_ = 0.0;
  double gait_level_ = 0.0, tremor_level_ = 0.0;
  double tremor_f_ = 5.0, tremor_amp_ = 0.0, tremor_phase_ = 0.0, tremor_mod_phase_ = 0.0;
  // sweep: each axis's speed (signed: its direction)
  std::array<double, 6> sweep_v_{};
  int stray_left_ = 0;
  Vec2 stray_px_ = Vec2::Zero();
};

}  // namespace earshot::tracker
