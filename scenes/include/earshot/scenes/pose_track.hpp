// A listener pose track: a Pose track CSV (common/pose_track_csv.hpp, the
// file format and its reader) interpolated in time: position linearly,
// orientation by slerp; held before the first row and after the last.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "earshot/head_pose.hpp"
#include "earshot/pose_track_csv.hpp"

namespace earshot::scenes {

class PoseTrack {
 public:
  /// Throws earshot::InputError naming origin, line and field.
  static PoseTrack read(std::istream& in, const std::string& origin);
  static PoseTrack load(const std::filesystem::path& path);

  /// The listener at `t` (position, orientation; the state of the row before).
  [[nodiscard]] HeadPose at(double t) const;
  [[nodiscard]] std::size_t size() const { return rows_.size(); }

 private:
  explicit PoseTrack(std::vector<HeadPose> rows) : rows_(std::move(rows)) {}
  std::vector<HeadPose> rows_;  // at least one, times increasing
};

}  // namespace earshot::scenes
