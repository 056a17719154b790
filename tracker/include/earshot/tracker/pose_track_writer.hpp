// Writes published listener poses as a Pose track CSV (contract, read by
// `earshot render --pose-track`): t_s,x_m,y_m,z_m,qw,qx,qy,qz, the listener
// in the audio world frame. The reader wants strictly increasing times, so a
// pose whose time does not advance is skipped; a non-finite one never written.
#pragma once

#include <iosfwd>

#include "earshot/head_pose.hpp"

namespace earshot::tracker {

class PoseTrackWriter {
 public:
  explicit PoseTrackWriter(std::ostream& out);
  /// False when the row was skipped (time not after the last row, or not finite).
  bool write(const HeadPose& p);

 private:
  std::ostream& out_;
  double last_t_ = 0.0;
  bool any_ = false;
};

}  // namespace earshot::tracker
