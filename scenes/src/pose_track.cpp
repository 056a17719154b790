#include "earshot/scenes/pose_track.hpp"

#include <algorithm>

#include "earshot/geometry.hpp"

namespace earshot::scenes {

PoseTrack PoseTrack::read(std::istream& in, const std::string& origin) {
  return PoseTrack(read_pose_track_csv(in, origin));
}

PoseTrack PoseTrack::load(const std::filesystem::path& path) { return PoseTrack(load_pose_track_csv(path)); }

HeadPose PoseTrack::at(double t) const {
  HeadPose s;
  s.t = t;
  const auto it = std::upper_bound(rows_.begin(), rows_.end(), t,
                                   [](double x, const HeadPose& r) { return x < r.t; });
  if (it == rows_.begin() || it == rows_.end()) {
    const auto& r = it == rows_.begin() ? rows_.front() : rows_.back();
    s.position = r.position;
    s.orientation = r.orientation;
    s.state = r.state;
    return s;
  }
  const auto& a = *(it - 1);
  const auto& b = *it;
  const double u = (t - a.t) / (b.t - a.t);
  s.state = a.state;
  for (std::size_t i = 0; i < 3; ++i) s.position[i] = a.position[i] + u * (b.position[i] - a.position[i]);
  s.orientation = slerp(a.orientation, b.orientation, u);
  return s;
}

}  // namespace earshot::scenes
