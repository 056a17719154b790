// Synthetic webcam video: 8-bit grey frames rendered from a ground-truth
// head walk (the tracker's motion profiles, simulator.hpp), for testing the
// detectors and the webcam source without a camera.
//
// The camera: a pinhole of the given size and horizontal field of view
// (principal point at the image centre, square pixels), static, watching the
// head as the tracker's Simulator places it (the beacon's model frame faces
// the camera at the identity pose). What a frame shows, in the order light
// meets it:
//   - a static scene: a dim textured background (smooth value noise and a few
//     flat shapes), optionally a bright lamp (a disc much larger than an LED,
//     for the detector to reject);
//   - the beacon at each instant of the exposure:
//       leds      the LedModel's LEDs as Gaussian spots whose size follows
//                 the LED's emitting disc at its distance and whose flux
//                 follows 1/distance^2 and the beam's falloff (cos^m, half
//                 power at 60 % of the model's half-angle, dark beyond it);
//       apriltag  the tag's real printed pattern (tag_pattern.hpp) on white
//                 paper, warped by its pose's homography with supersampling,
//                 under a lighting gradient;
//     averaged over the exposure (motion blur);
//   - the lens: a Gaussian blur;
//   - the sensor: auto-exposure gain drifting over seconds, shot noise
//     (variance proportional to the signal) and read noise, clipped to
//     0..255 (bright LEDs saturate into flat-topped blobs).
// Ground truth is the pose at the middle of the exposure and the projection
// of the beacon's four points (LED k, or tag corner k in tag_corners_mm's
// label order) under it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/led_model.hpp"
#include "earshot/tracker/sim/simulator.hpp"
#include "earshot/webcam/dot_detector.hpp"
#include "earshot/webcam/tag_pattern.hpp"

namespace earshot::webcam {

enum class BeaconKind { leds, apriltag };

struct VideoSimConfig {
  BeaconKind beacon = BeaconKind::leds;
  int width = 640, height = 480;
  double fps = 30.0;
  double hfov_deg = 60.0;  ///< horizontal field of view
  tracker::MotionProfile motion = tracker::MotionProfile::seated;
  std::uint64_t seed = 1;

  // LEDs
  tracker::LedModel leds = tracker::LedModel::thesis();
  double led_radius_mm = 1.5;     ///< emitting disc (a 3 mm LED's die and lens glow)
  double led_radiance = 1400.0;   ///< grey levels at full gain on the beam axis (> 255: saturated)

  // AprilTag: the tag's outer black square, centred on the model frame's
  // origin (where the LED beacon's centre is), facing the camera at the
  // identity pose (tag_corners_mm).
  std::string family = "tag36h11";
  int id = 0;
  double tag_size_mm = 80.0;
  double paper_margin_cells = 1.0;  ///< white paper beyond the tag's own white border
  double paper_white = 190.0;       ///< grey level of the paper at full gain
  double ink_black = 18.0;          ///< grey level of the printed black
  int supersample = 4;              ///< per axis, tag pixels

  // Camera and scene
  double exposure_s = 1.0 / 60.0;   ///< motion blur window (<= 1 / fps)
  int motion_samples = 9;           ///< sub-frame renders per exposure (odd)
  double blur_sigma_px = 0.7;       ///< optics
  double read_noise = 1.5;          ///< grey levels RMS
  double shot_noise = 0.08;         ///< variance per grey level of signal
  bool auto_exposure = true;        ///< gain drifts between ~0.75 and ~1.3 over seconds
  double background = -1.0;         ///< mean grey level of the scene; < 0: 22 (leds), 90 (apriltag)
  bool lamp = false;                ///< a bright lamp disc in the upper left of the scene
};

/// One rendered frame.
struct VideoFrame {
  long index = 0;
  double t = 0.0;            ///< seconds, middle of the exposure
  tracker::Pose truth;       ///< beacon pose (camera frame, mm) at t
  /// Projected truth of the beacon's points (LED k / tag corner k) at t;
  /// nullopt when that point is out of the image or turned away.
  std::array<std::optional<tracker::Vec2>, 4> points;
  double gain = 1.0;         ///< auto-exposure gain of this frame
  std::vector<std::uint8_t> pixels;  ///< width * height, row by row

  [[nodiscard]] GrayView view(int width, int height) const {
    return {pixels, width, height, width};
  }
  /// The truth as a Dots CSV frame: the projected points in label order
  /// (slot k = point k) and the pose, so `track solve` can read it.
  [[nodiscard]] tracker::DotFrame dot_frame() const;
};

/// The camera a config describes: f = (width / 2) / tan(hfov / 2).
[[nodiscard]] tracker::Camera video_camera(const VideoSimConfig& cfg);

/// The model the tracker solves with: the LEDs, or the tag's corners
/// (tag_corners_mm) with a 75-degree visibility half-angle.
[[nodiscard]] tracker::LedModel video_model(const VideoSimConfig& cfg);

class VideoSimulator {
 public:
  /// Throws std::invalid_argument naming the bad setting (size, fps,
  /// exposure, family, ...).
  explicit VideoSimulator(VideoSimConfig cfg);

  /// Renders the next frame into `frame` (its buffer is reused).
  void next(VideoFrame& frame);
  [[nodiscard]] VideoFrame next() {
    VideoFrame f;
    next(f);
    return f;
  }

  [[nodiscard]] const VideoSimConfig& config() const { return cfg_; }
  [[nodiscard]] const tracker::Camera& camera() const { return cam_; }
  [[nodiscard]] const tracker::LedModel& model() const { return model_; }

 private:
  void render_static();
  void add_leds(const tracker::Pose& pose, double weight);
  void add_tag(const std::vector<tracker::Pose>& poses);
  void blur();
  [[nodiscard]] double gain_at(double t) const;

  VideoSimConfig cfg_;
  tracker::Camera cam_;
  tracker::LedModel model_;
  tracker::Simulator motion_;
  int substeps_ = 1;       // simulator steps per frame period
  int exposure_steps_ = 0; // simulator steps per exposure (even)
  std::vector<tracker::Pose> window_;  // poses of the current exposure
  std::optional<TagPattern> tag_;
  std::vector<float> scene_;  // static scene, grey levels at gain 1
  std::vector<float> acc_;    // this frame's radiance
  std::vector<float> tmp_;
  std::vector<float> kernel_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::array<double, 3> ae_phase_{};
  long frame_ = 0;
  long step_ = 0;
};

}  // namespace earshot::webcam
