// A simulated Wii Remote camera watching the beacon on a random walk
// (like the thesis's section 5.1, with the camera's real behaviour):
// perspective projection, pixel quantisation or noise, dots outside the
// image or LEDs turned beyond their beam half-angle are not seen, dots keep
// their camera slot while visible and take a random free slot when they
// (re)appear, optional dropouts and a stray reflection.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string_view>

#include "earshot/tracker/camera.hpp"
#include "earshot/tracker/dots_csv.hpp"
#include "earshot/tracker/led_model.hpp"

namespace earshot::tracker {

enum class PixelModel { exact, integer, quantize8, gaussian };
[[nodiscard]] std::optional<PixelModel> pixel_model_from(std::string_view name);

struct SimulatorConfig {
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
  int stray_left_ = 0;
  Vec2 stray_px_ = Vec2::Zero();
};

}  // namespace earshot::tracker
