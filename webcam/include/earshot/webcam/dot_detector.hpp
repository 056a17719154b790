// Webcam frames in, the four beacon points out: what the Wii Remote's camera
// does in its own chip, done in software for an ordinary camera.
//
// Two detectors share one interface:
//   - LEDs: the four brightest compact blobs of the frame (the same headphone
//     LEDs the Wii Remote sees; most webcams see near-infrared, visible LEDs
//     work too), as sub-pixel centroids with sizes, unlabelled; the tracker's
//     labeller assigns them to the model's LEDs as it does for the Wii.
//   - AprilTag: the four corners of a printed tag (libapriltag), labelled by
//     the tag itself (corner k of the tag is model point k).
//
// Conventions: pixel (0, 0) is the centre of the top-left pixel, x grows to
// the right and y downwards (the layout of the frame in memory). The caller
// maps these to the tracker's camera model (and undistorts them) itself.
//
// detect() is called on the tracker thread, one frame at a time; a detector
// keeps its scratch buffers between calls and is not shared between threads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace earshot::webcam {

/// An 8-bit grey frame in memory that the caller owns (the Y plane of a
/// YUYV/NV12/I420 frame, or a converted MJPEG frame).
struct GrayView {
  std::span<const std::uint8_t> pixels;  ///< at least stride * (height - 1) + width bytes
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  ///< bytes from one row to the next (>= width)
};

/// One found point.
struct Point {
  double x = 0.0;      ///< pixels, see the conventions above
  double y = 0.0;
  double size = 0.0;   ///< LEDs: blob area in pixels; tag corners: the tag's side in pixels
};

/// What a detector found in one frame.
struct Detection {
  int count = 0;                    ///< points found, 0..4
  std::array<Point, 4> points{};    ///< [0, count)
  bool labelled = false;            ///< true: points[k] is model point k (tags)
  int tag_id = -1;                  ///< the tag's id (AprilTag), -1 otherwise
};

class DotDetector {
 public:
  virtual ~DotDetector() = default;
  /// Finds the beacon in `frame`. Never throws for any pixel content; a
  /// frame whose view is inconsistent (sizes, stride, span too short) throws
  /// std::invalid_argument.
  virtual Detection detect(const GrayView& frame) = 0;
  /// "leds", "apriltag tag36h11 id 0", ... for status lines.
  [[nodiscard]] virtual std::string describe() const = 0;
};

}  // namespace earshot::webcam
