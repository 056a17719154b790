// Pose track CSV (contract): t_s,x_m,y_m,z_m,qw,qx,qy,qz: the listener in
// the audio world frame over time, interpolated between rows (position
// linearly, orientation by slerp); held before the first and after the last.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "earshot/audio/renderer.hpp"

namespace earshot::scenes {

class PoseTrack {
 public:
  /// Throws earshot::InputError naming origin, line and field.
  static PoseTrack read(std::istream& in, const std::string& origin);
  static PoseTrack load(const std::filesystem::path& path);

  [[nodiscard]] audio::ListenerState at(double t) const;
  [[nodiscard]] std::size_t size() const { return rows_.size(); }

 private:
  struct Row {
    double t;
    audio::Vec3 p;
    audio::Quat q;
  };
  std::vector<Row> rows_;
};

}  // namespace earshot::scenes
