// What a `webcam[:DEVICE][,OPTION=VALUE...]` source spec says (the part of
// the tracker source spec, earshot/tracker/live/source_spec.hpp, that names a
// camera or a .y4m file and the beacon it watches), and its parser.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace earshot::webcam {

/// What a webcam spec says beyond its kind.
struct WebcamSpec {
  enum class Beacon { leds, apriltag };
  /// /dev/videoN, or a .y4m file played as if a camera delivered it.
  std::string device = "/dev/video0";
  Beacon beacon = Beacon::leds;
  /// apriltag: side of the square whose corners the detector finds: the
  /// outside of the black border for tag36h11, tag36h10, tag25h9, tag16h5;
  /// the inside edge of the black ring for the reversed-border families
  /// (tagStandard41h12, tagStandard52h13, tagCircle*, tagCustom48h12).
  double size_mm = 50.0;
  std::string family = "tag36h11";  ///< apriltag: the tag family
  int id = -1;                      ///< apriltag: only this id; -1 any
  /// apriltag: libapriltag's quad decimation. 2 finds the quads on a
  /// half-size image (the corners are still refined at full size): as
  /// accurate as 1 on rendered walks and a quarter of the cost (5 against
  /// 18 ms a 640x480 frame; docs/BENCHMARKS.md), so it is the default.
  double decimate = 2.0;
  std::optional<double> focal_px;   ///< focal length in pixels (overrides the calibration's)
  std::string calib;                ///< OpenCV calibration YAML; empty: none
  int max_width = 0, max_height = 0;  ///< capture at most this size; 0: the default (1280x720)
  int max_fps = 0;                  ///< capture at most this rate; 0: the highest offered

  /// The device is a Y4M file, not a camera.
  [[nodiscard]] bool is_file() const;
};

/// Parses what follows "webcam" in `spec` (`rest`: empty, ":DEVICE...", or
/// ",OPTION=VALUE..."). Throws earshot::InputError naming `field` and the
/// spec for a bad device, an unknown, repeated, empty or out-of-range option,
/// or a tag option without beacon=apriltag.
[[nodiscard]] WebcamSpec parse_webcam_spec(std::string_view spec, std::string_view field, std::string_view rest);

}  // namespace earshot::webcam
