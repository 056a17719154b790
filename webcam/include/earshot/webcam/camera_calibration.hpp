// A webcam's intrinsics and lens distortion, from the YAML file OpenCV's
// calibration writes (cv::FileStorage):
//
//   %YAML:1.0
//   image_width: 640            (optional, with image_height)
//   image_height: 480
//   camera_matrix: !!opencv-matrix
//      rows: 3
//      cols: 3
//      dt: d
//      data: [ fx, 0, cx, 0, fy, cy, 0, 0, 1 ]
//   distortion_coefficients: !!opencv-matrix
//      rows: 1
//      cols: 5
//      dt: d
//      data: [ k1, k2, p1, p2, k3 ]
//
// Distortion has 4, 5, 8, 12 or 14 coefficients in OpenCV's order
// (k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4 [tx ty]]]]); the tilted-sensor
// terms tx, ty must be 0. Undistortion inverts the model until it holds
// (Newton's method from cv::undistortPoints' fixed point, stopped by a
// convergence test: the ideal pixel distorts back to the measured one
// within kUndistortTolerancePx) and returns pixels of the ideal pinhole
// camera with the same matrix: what the pose solver expects. Where the
// model folds over (no ideal pixel maps there, or several) there is none.
//
// Pixels: centres at whole numbers, the image's first pixel centred on
// (0, 0), so the centre of a W-pixel-wide image is (W - 1) / 2.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "earshot/tracker/core/camera.hpp"

namespace earshot::webcam {

/// How close distort(undistort(p)) must come back to p, pixels.
inline constexpr double kUndistortTolerancePx = 1e-6;

struct CameraCalibration {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  /// k1 k2 p1 p2 k3 k4 k5 k6 s1 s2 s3 s4 (missing ones are 0).
  std::array<double, 12> distortion{};
  int image_width = 0, image_height = 0;  ///< 0: not given (assumed to be the capture size)

  [[nodiscard]] bool distorted() const;
  /// The same lens at another capture size (the sensor scaled, not cropped).
  /// Throws earshot::InputError naming `origin` when the aspect ratio differs.
  [[nodiscard]] CameraCalibration scaled_to(int width, int height, std::string_view origin) const;
  [[nodiscard]] tracker::Camera camera(int width, int height) const;

  /// The ideal (undistorted) pixel of a measured one: distort() of it gives
  /// `px` back within kUndistortTolerancePx, on the model's unfolded branch.
  /// nullopt where there is none (the model folds there, or `px` is not
  /// finite). Without distortion, `px` itself.
  [[nodiscard]] std::optional<tracker::Vec2> undistort(const tracker::Vec2& px) const;
  /// cv::undistortPoints' own fixed point, `iterations` times, without a
  /// convergence test (comparisons with OpenCV). Stays finite; gives up
  /// (returns the input) where an iteration goes astray.
  [[nodiscard]] tracker::Vec2 undistort_fixed_point(const tracker::Vec2& px, int iterations) const;
  /// The measured pixel of an ideal one (OpenCV's forward model; for tests).
  [[nodiscard]] tracker::Vec2 distort(const tracker::Vec2& px) const;
};

/// Parses OpenCV calibration YAML text. Throws earshot::InputError naming
/// `origin` and the field (camera_matrix, distortion_coefficients, ...).
[[nodiscard]] CameraCalibration parse_camera_calibration(std::string_view yaml_text, std::string_view origin);
/// Reads a calibration file (errors name the file).
[[nodiscard]] CameraCalibration load_camera_calibration(const std::filesystem::path& path);

/// Focal length in pixels for a horizontal field of view (degrees).
[[nodiscard]] double focal_from_fov(int width, double horizontal_fov_deg);

}  // namespace earshot::webcam
