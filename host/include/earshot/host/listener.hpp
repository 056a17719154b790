// The listener of a world: where the scene puts it, or where a Pose track
// has it at each block (a tracker attached to the world turns the head on
// top of either: tracker_status.hpp).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "earshot/head_pose.hpp"
#include "earshot/host/world_handle.hpp"
#include "earshot/scenes/pose_track.hpp"
#include "earshot/scenes/scene.hpp"

namespace earshot::host {

/// The scene's listener: its position, turned by its yaw, pitch and roll.
[[nodiscard]] HeadPose fixed_listener(const scenes::SceneListener& l);

/// Sets the world's listener position and orientation; an error names
/// `origin` and the time `t` (seconds).
void set_listener(const WorldHandle& world, const HeadPose& l, std::string_view origin, double t);

/// The listener of an offline render: a Pose track when there is one (the
/// override, else the scene's), else the scene's fixed listener.
class ListenerTrack {
 public:
  /// Reads the track; throws earshot::InputError naming its file.
  ListenerTrack(const scenes::Scene& scene, const std::optional<std::filesystem::path>& pose_track);
  /// Before the first block: the fixed listener (nothing with a track).
  void start(const WorldHandle& world) const;
  /// Before the block at `t` seconds: the track's pose (nothing without one).
  void at(const WorldHandle& world, double t) const;

 private:
  std::optional<scenes::PoseTrack> track_;
  std::string origin_;
  HeadPose fixed_;
};

}  // namespace earshot::host
