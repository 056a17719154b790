// The webcam source: frames from a V4L2 camera (or a .y4m file standing in
// for one) -> grey -> the beacon detector (webcam/dot_detector.hpp) ->
// undistorted dots -> camera frames for the live tracker, with the camera
// model (resolution, focal length, principal point) the tracker must use.
//
//   - LEDs: up to four unlabelled dots, labelled by the tracker as the Wii
//     Remote's are.
//   - AprilTag: the tag's four corners, labelled (CameraFrame::labelled), and
//     the tag as the beacon model (model()): corners of a size_mm square
//     facing the camera at the identity pose.
//
// The camera model: calib=FILE (OpenCV YAML, scaled to the capture size;
// lens distortion undone on the dots), focal=F (pixels; overrides the
// file's), or else a guess from a 60 degree horizontal field of view, said in
// the `connected` note. Pixel centres are at whole numbers, so a lens
// without a calibration is centred on ((W - 1) / 2, (H - 1) / 2). With a
// distorting lens, camera() is the ideal (undistorted) camera, its image
// grown to hold every raw pixel's undistorted place (a barrel lens moves the
// corners out: a tag near the edge keeps all four corners), shifted to start
// at (0, 0); the dots are in its pixels. A camera that cannot be opened before it ever
// worked throws (or, with WebcamOptions::wait_for_device, gives `searching`
// notes and keeps trying); one that disappears while streaming gives a
// `disconnected` note and is reopened every retry interval.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "earshot/webcam/camera_calibration.hpp"
#include "earshot/tracker/core/frame_source.hpp"
#include "earshot/webcam/v4l2_camera.hpp"
#include "earshot/webcam/webcam_spec.hpp"
#include "earshot/webcam/y4m_reader.hpp"
#include "earshot/webcam/dot_detector.hpp"

namespace earshot::webcam {

/// The field of view the focal length is guessed from when none is given.
inline constexpr double kGuessedFovDeg = 60.0;

/// A tag's corners as a beacon model (tag_corners_mm, facing the camera).
[[nodiscard]] tracker::LedModel tag_model(double size_mm);

/// A camera of focal length `f` pixels centred on its image under the
/// pixel convention above: principal point ((W - 1) / 2, (H - 1) / 2).
[[nodiscard]] tracker::Camera centred_camera(double f, int width, int height);

/// Where a lens sends a W x H raw image: the bounding box of its border's
/// undistorted places (and the raw rectangle), as an image starting at
/// (0, 0): `offset` added to an undistorted pixel gives its place in it.
struct UndistortedImage {
  tracker::Vec2 offset = tracker::Vec2::Zero();
  int width = 0, height = 0;
};
[[nodiscard]] UndistortedImage undistorted_image(const CameraCalibration& lens, int width, int height);

/// How to run a webcam source beyond its spec.
struct WebcamOptions {
  tracker::Pacing pacing = tracker::Pacing::real_time;  ///< a .y4m file: at its frame rate, or as fast as read
  /// No camera yet is a `searching` note instead of an error (for hosts
  /// that play on and show how to connect one).
  bool wait_for_device = false;
};

class WebcamSource final : public tracker::FrameSource {
 public:
  /// Opens the device or file named in `spec` and watches for the beacon
  /// with `detector` (make_webcam_source builds it from the spec). Throws
  /// CameraError or earshot::InputError (a bad file, calibration or option).
  WebcamSource(WebcamSpec spec, std::unique_ptr<DotDetector> detector, const WebcamOptions& options = {});
  ~WebcamSource() override;

  tracker::SourceEvent next(std::chrono::milliseconds timeout) override;
  /// "webcam:/dev/video0 (640x480 @ 30 fps, apriltag tag36h11 id 0)".
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] std::optional<tracker::Camera> camera() const override { return camera_; }
  [[nodiscard]] std::optional<tracker::LedModel> model() const override;
  bool thumbnail(tracker::Thumbnail& out) const override;

  /// Seconds between reconnection attempts after the camera went away.
  static constexpr double kRetrySeconds = 1.0;

 private:
  bool open(std::string& why);
  void set_camera_model(int width, int height);
  tracker::SourceEvent frame_event(const GrayView& view, double t);
  tracker::SourceEvent next_from_file(std::chrono::milliseconds timeout);
  tracker::SourceEvent next_from_camera(std::chrono::milliseconds timeout);
  void update_thumbnail(const GrayView& view, const Detection& d, double t);

  WebcamSpec spec_;
  std::unique_ptr<DotDetector> detector_;
  tracker::Pacing pacing_;
  bool wait_for_device_;
  std::optional<CameraCalibration> calib_;
  std::optional<tracker::Camera> camera_;
  std::optional<CameraCalibration> lens_;  ///< the calibration at the capture size, when distorted
  tracker::Vec2 offset_ = tracker::Vec2::Zero();  ///< undistorted pixel -> the ideal image's (UndistortedImage)
  std::string camera_note_;                ///< how the focal length was found
  std::string mode_;                       ///< "640x480 @ 30 fps"

  std::unique_ptr<Y4mReader> file_;
  std::chrono::steady_clock::time_point file_start_;
  std::unique_ptr<V4l2Camera> device_;
  bool ever_connected_ = false;
  bool announce_ = false;  ///< a `connected` note is due
  double next_attempt_ = 0.0;
  std::uint64_t frames_ = 0;

  tracker::Thumbnail scratch_;  // built on the tracker thread
  mutable std::mutex thumb_mutex_;  // guards thumb_ (UIs read it; never the audio side)
  tracker::Thumbnail thumb_;
};

/// The source `spec` names, with the detector for its beacon.
[[nodiscard]] std::unique_ptr<tracker::FrameSource> make_webcam_source(const WebcamSpec& spec, const WebcamOptions& options = {});

}  // namespace earshot::webcam
