// Poses CSV: the tracker's output (contract), written by `earshot track
// solve`:
//   t_s,state,tx_mm,ty_mm,tz_mm,qw,qx,qy,qz
// the beacon pose in the camera frame (tracker/core/geometry.hpp); state is
// tracking, predicted or lost (earshot::pose_state_name). Not to be confused
// with the Pose track CSV (pose_track_csv.hpp): the listener in the world.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

#include "earshot/head_pose.hpp"
#include "earshot/tracker/core/geometry.hpp"

namespace earshot::tracker {

struct PoseRecord {
  double t = 0.0;
  PoseState state = PoseState::lost;
  Pose pose;
};

class PosesCsvWriter {
 public:
  explicit PosesCsvWriter(std::ostream& out);
  /// Writes one row. A non-finite pose is never written: throws std::logic_error.
  void write(const PoseRecord& r);

 private:
  std::ostream& out_;
};

class PosesCsvReader {
 public:
  PosesCsvReader(std::istream& in, std::string origin);
  std::optional<PoseRecord> next();  ///< throws InputError on a bad line

 private:
  std::istream& in_;
  std::string origin_;
  long line_ = 0;
};

}  // namespace earshot::tracker
