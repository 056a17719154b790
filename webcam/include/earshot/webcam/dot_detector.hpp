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
// the right and y downwards (the layout of the frame in memory): the
// tracker's camera frame (+x right, +y down, +z forward), so points pass to
// it unchanged once undistorted (the caller undistorts them).
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

struct LedOptions {
  double min_area_px = 1.0;     ///< smaller blobs are noise
  double max_area_px = 2500.0;  ///< larger ones are lamps and windows, not LEDs
};

struct AprilTagOptions {
  std::string family = "tag36h11";  ///< tag36h11, tag25h9, tag16h5, tagStandard41h12, ...
  int id = -1;                      ///< only this id; -1: the best-decoded tag of any id
  float decimate = 1.0f;            ///< libapriltag's quad_decimate (2 halves the cost at 1280x720)
};

/// The LED detector: the four brightest compact blobs, threshold from the
/// frame's own statistics (median + max(6 sigma, 16) grey levels, sigma from
/// the MAD of a subsample), brightest first. Its scratch buffers are sized
/// by the first frame of each size; later frames of that size allocate
/// nothing.
[[nodiscard]] std::unique_ptr<DotDetector> make_led_detector(const LedOptions& options = {});

/// The AprilTag detector. Throws std::invalid_argument naming the family when
/// libapriltag does not know it (or the id when the family has no such
/// code, or a decimate below 1). libapriltag allocates inside each detection.
[[nodiscard]] std::unique_ptr<DotDetector> make_apriltag_detector(const AprilTagOptions& options = {});

/// A tag's corners in label order (Detection::points of a tag): 0 top-left,
/// 1 top-right, 2 bottom-right, 3 bottom-left of the printed tag held
/// upright. `side_mm` is the side of the square whose corners libapriltag
/// finds: the outside of the black border of tag36h11 and the other classic
/// families, the inside edge of the black ring of the reversed-border ones
/// (tagStandard41h12 ...). In the tag's frame, mm: the tag upright and
/// facing the camera at the identity pose of the tracker's camera frame
/// (+x right, +y down), in the plane z = 0; its face looks along -z.
[[nodiscard]] constexpr std::array<std::array<double, 3>, 4> tag_corners_mm(double side_mm) {
  const double h = side_mm / 2.0;
  return {{{-h, -h, 0.0}, {h, -h, 0.0}, {h, h, 0.0}, {-h, h, 0.0}}};
}

}  // namespace earshot::webcam
