// A listener pose track: a Pose track CSV (common/pose_track_csv.hpp, the
// file format and its reader) interpolated in time: position linearly,
// orientation by slerp; held before the first row and after the last.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "earshot/audio/renderer.hpp"
#include "earshot/pose_track_csv.hpp"

namespace earshot::scenes {

class PoseTrack {
 public:
  /// Throws earshot::InputError naming origin, line and field.
  static PoseTrack read(std::istream& in, const std::string& origin);
  static PoseTrack load(const std::filesystem::path& path);

  [[nodiscard]] audio::ListenerState at(double t) const;
  [[nodiscard]] std::size_t size() const { return rows_.size(); }

 private:
  explicit PoseTrack(std::vector<PoseTrackRow> rows) : rows_(std::move(rows)) {}
  std::vector<PoseTrackRow> rows_;  // at least one, times increasing
};

}  // namespace earshot::scenes
