// Pose track CSV (contract): the listener in the audio world frame over
// time, written by `earshot track live --record`, read by `earshot render
// --pose-track` (scenes::PoseTrack interpolates it):
//   t_s,x_m,y_m,z_m,qw,qx,qy,qz[,state]
// metres and a unit quaternion (w, x, y, z) in the frame of
// earshot/geometry.hpp; times strictly increase; `state` (a recording's
// tracker state: searching, tracking, predicted, lost) is optional. Each row
// is a HeadPose. Not to be confused with the Poses CSV
// (tracker/core/poses_csv.hpp): the beacon in the camera frame.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "earshot/geometry.hpp"
#include "earshot/head_pose.hpp"

namespace earshot {

/// Reads a whole Pose track: at least one row; orientations normalised
/// (within 1e-3 of unit length on file); `state` from its column, else
/// tracking. Throws earshot::InputError naming origin, line and field.
[[nodiscard]] std::vector<HeadPose> read_pose_track_csv(std::istream& in, const std::string& origin);
[[nodiscard]] std::vector<HeadPose> load_pose_track_csv(const std::filesystem::path& path);

/// Writes published head poses as a Pose track. The reader wants strictly
/// increasing times, so a pose whose time does not advance is skipped; a
/// non-finite one is never written. `with_state` adds the optional `state`
/// column (each pose's state), as a recording writes it.
class PoseTrackCsvWriter {
 public:
  explicit PoseTrackCsvWriter(std::ostream& out, bool with_state = false);
  /// False when the row was skipped (time not after the last row, or not finite).
  bool write(const HeadPose& p);

 private:
  std::ostream& out_;
  bool with_state_ = false;
  double last_t_ = 0.0;
  bool any_ = false;
};

}  // namespace earshot
