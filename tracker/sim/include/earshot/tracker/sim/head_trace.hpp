// A recorded head in front of the camera: an orientation trace (and, when
// recorded, a position) turned into the beacon's pose in the camera frame,
// as ../shared/data/real_motion/README.md describes.
//
// File: CSV with the header `t_s,qw,qx,qy,qz` or `t_s,qw,qx,qy,qz,x_m,y_m,z_m`;
// the quaternion is an active rotation from head to world axes.
//
//  - Axes: an orientation-only trace has x forward, y left, z up (the
//    360-degree viewer traces); one with position has x right, y up, z
//    backward (the standing VR user's). Both are mapped to the camera frame
//    (x right in the image, y down, z away from the camera) with a listener
//    who faces the camera at rest: R_cam = M R M^T, p_cam = M p.
//  - Front: the whole trace is turned once about the vertical so that the
//    centre of the +-40 deg heading sector the head holds most often faces
//    the camera; elevation and roll stay as recorded.
//  - Head centre: an orientation-only head turns about a neck pivot fixed in
//    the room (`pivot_mm` in head axes at rest, default 100 mm below and
//    50 mm behind the centre): centre = rest + p - R p. A trace with
//    position puts its mean at the rest point and follows the recorded
//    displacement (turned with the front).
//  - Time: slerp along the shorter arc between neighbouring samples,
//    position linearly; t = 0 is the trace's first sample.
// The beacon's model frame is the head's (its origin at the head centre).
#pragma once

#include <filesystem>
#include <istream>
#include <string_view>
#include <vector>

#include "earshot/tracker/core/geometry.hpp"

namespace earshot::tracker {

struct HeadTraceOptions {
  Vec3 rest_mm{0.0, 0.0, 1000.0};    ///< head centre at rest, camera frame
  Vec3 pivot_mm{0.0, 100.0, 50.0};   ///< neck pivot from the head centre, head axes at rest (y down, z away from the camera)
};

class HeadTrace {
 public:
  /// Reads the CSV (throws InputError naming `origin` and the line).
  static HeadTrace parse(std::istream& in, std::string_view origin, const HeadTraceOptions& o = {});
  static HeadTrace load(const std::filesystem::path& path, const HeadTraceOptions& o = {});
  /// Samples as given: times (s, from the first sample), head-to-world
  /// rotations in the source's own axes, positions (m; empty without).
  static HeadTrace from_samples(std::vector<double> t, std::vector<Quat> q, std::vector<Vec3> pos_m,
                                const HeadTraceOptions& o = {});

  /// The beacon's pose in the camera frame at time t (clamped to the trace).
  [[nodiscard]] Pose at(double t) const;
  [[nodiscard]] double duration() const { return t_.empty() ? 0.0 : t_.back(); }
  [[nodiscard]] bool has_position() const { return !p_mm_.empty(); }
  /// The heading (rad, about the source's vertical) turned to face the camera.
  [[nodiscard]] double front_rad() const { return front_rad_; }

 private:
  std::vector<double> t_;
  std::vector<Quat> q_;     ///< camera-frame rotations, front turned, signs made continuous
  std::vector<Vec3> p_mm_;  ///< camera-frame head centres (with position only)
  HeadTraceOptions o_;
  double front_rad_ = 0.0;
};

}  // namespace earshot::tracker
