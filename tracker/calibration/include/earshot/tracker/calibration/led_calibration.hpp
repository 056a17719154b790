// Self-calibration of the LED model: the four LED positions (and optionally
// the focal length) estimated from a recording of the head moving in front
// of the camera, for rigs whose LEDs nobody can measure to a millimetre.
//
// 1. Labels: the session is tracked with the starting model (labeller + LM,
//    raw poses); frames where all four LEDs are labelled are kept, spread
//    evenly over the session. Three-dot frames are not used: three dots fix
//    a pose exactly and leave no residual that could tell about the model.
// 2. Bundle adjustment over the kept frames: unknowns are the 12 LED
//    coordinates [+ focal] and 6 pose parameters per frame, residuals are
//    reprojection errors in pixels under a Huber loss (mislabels, strays).
//    Gauss-Newton / Levenberg-Marquardt with the per-frame 6x6 pose blocks
//    eliminated by the Schur complement, so each step solves a 12 (13)
//    unknown system. The gauge (a rigid motion of the model frame is taken
//    up by the poses, a scale by the depths) is fixed while solving: steps
//    keep the LEDs' centroid and mean orientation and the ruler distance;
//    after solving the model is scaled to the ruler distance and rigidly
//    aligned (Kabsch) to the starting model, so the head frame stays the one
//    the user defined.
// 3. Labels are redone with the first estimate and the adjustment is run
//    again. The result says how good it is: RMS residual before and after,
//    the pixel noise, each LED's standard deviation from the reduced normal
//    matrix, the least determined directions and what motion would help.
//    A recording that cannot determine the model (too few four-dot frames,
//    too little head rotation, an LED too uncertain) is refused with an
//    InputError that says what is missing.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/correspondence.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/led_model.hpp"

namespace earshot::tracker {

/// One ruler measurement: `mm` between LEDs `a` and `b` (0-based, distinct).
struct ScaleBar {
  double mm = 0.0;
  int a = 0, b = 1;
};

/// Parses "D:A-B" (e.g. "170:0-1"). Throws InputError naming `option`.
[[nodiscard]] ScaleBar parse_scale_bar(std::string_view text, std::string_view option = "--scale-mm");

/// One step of the adjustment, for progress lines and convergence plots.
struct CalibrationIteration {
  int round = 0;      ///< 1: labels from the starting model, 2: from the first estimate
  int iteration = 0;  ///< 0: before the first step
  double rms_px = 0.0;
  double focal_px = 0.0;
  std::array<Vec3, 4> leds_mm{};  ///< scaled to the ruler, aligned to the starting model
};

struct CalibrationOptions {
  ScaleBar scale;
  bool estimate_focal = false;
  size_t max_frames = 6000;        ///< four-dot frames used, spread over the session
  size_t min_frames = 300;         ///< fewer four-dot frames than this: refused
  double min_turn_deg = 8.0;       ///< yaw and pitch must each span this (5th-95th percentile)
  double max_led_sigma_mm = 1.0;   ///< an LED coordinate less certain than this: refused
  double label_gate_px = 12.0;     ///< labeller fit gate with the starting model (it may be mm off)
  double huber_px = 1.5;           ///< Huber loss threshold, in units of the pixel noise (at least 1 px)
  int max_iterations = 40;
  /// Called before the first step and after every accepted one.
  std::function<void(const CalibrationIteration&)> on_iteration;
  /// Called with progress lines ("labelled 5800 of 6000 frames ...").
  std::function<void(const std::string&)> on_progress;
};

/// A least determined direction of the model: an eigenvector of the reduced
/// information matrix with one of its smallest eigenvalues.
struct WeakDirection {
  double sigma_mm = 0.0;            ///< standard deviation along it (px where the focal length dominates)
  std::array<Vec3, 4> move{};       ///< unit direction, per LED (model frame)
  double focal_share = 0.0;         ///< squared weight of the focal length in it
  std::string description;          ///< e.g. "LED 3 z (depth) against LED 0 z"
};

/// How far the head moved in the frames used (degrees, mm): the spread
/// between the 5th and 95th percentiles about the median pose.
struct MotionSpan {
  double yaw_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;
  double depth_mm = 0.0, lateral_mm = 0.0;
};

struct CalibrationResult {
  LedModel model;                   ///< calibrated, in the starting model's frame
  double focal_px = 0.0;            ///< estimated, or the one given
  size_t frames_read = 0, frames_four = 0, frames_used = 0;
  size_t outlier_dots = 0;          ///< dots beyond the Huber threshold at the end
  double rms_before_px = 0.0;       ///< starting model, each frame's best pose
  double rms_after_px = 0.0;
  double pixel_sigma_px = 0.0;      ///< noise estimated from the final residuals
  std::array<Vec3, 4> led_sigma_mm{};  ///< per LED and axis (scale from the ruler)
  double focal_sigma_px = 0.0;
  std::vector<WeakDirection> weakest;  ///< the three least determined, weakest first
  MotionSpan motion;
  std::vector<std::string> advice;  ///< what motion would improve it (empty when nothing needs to)
  std::array<double, 4> moved_mm{}; ///< how far each LED moved from the starting model
};

/// Calibrates from a whole session. `origin` names the recording in errors.
/// Ground-truth columns of the frames are ignored.
[[nodiscard]] CalibrationResult calibrate_led_model(const std::vector<DotFrame>& frames, const LedModel& start,
                                                    const Camera& camera, const CalibrationOptions& opt,
                                                    std::string_view origin);

/// A frame whose four dots are labelled, with a pose to start from.
struct LabelledFrame {
  LabelledDots dots;
  Pose pose;
};

/// Step 1 alone: tracks the session with `model` (labeller gate `gate_px`)
/// and returns the four-dot frames.
[[nodiscard]] std::vector<LabelledFrame> label_four_dot_frames(const std::vector<DotFrame>& frames,
                                                               const LedModel& model, const Camera& camera,
                                                               double gate_px);

/// The rigid motion (R, t) that best maps `from` onto `to` (least squares,
/// Kabsch): to_i ~ R from_i + t.
[[nodiscard]] Pose rigid_align(const std::array<Vec3, 4>& from, const std::array<Vec3, 4>& to);

/// How far each LED of `estimate` is from `truth` after the rigid motion
/// that best aligns the two (mm): the gauge of a self-calibration is free,
/// so only the shape and size can be compared.
[[nodiscard]] std::array<double, 4> led_errors_after_alignment(const std::array<Vec3, 4>& estimate,
                                                               const std::array<Vec3, 4>& truth);

/// Writes a Model JSON (leds_mm, axis, half_angle_deg) that load_led_model reads.
void save_led_model(const LedModel& model, const std::string& path);

}  // namespace earshot::tracker
