#include "earshot/host/listener.hpp"

#include <numbers>

namespace earshot::host {

HeadPose fixed_listener(const scenes::SceneListener& l) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  HeadPose s;
  s.position = l.position;
  s.orientation = quat_from_ypr(l.yaw_deg * kDeg, l.pitch_deg * kDeg, l.roll_deg * kDeg);
  return s;
}

void set_listener(const WorldHandle& world, const HeadPose& l, std::string_view origin, double t) {
  const float pos[3] = {float(l.position[0]), float(l.position[1]), float(l.position[2])};
  const float quat[4] = {float(l.orientation[0]), float(l.orientation[1]), float(l.orientation[2]),
                         float(l.orientation[3])};
  ESenum e = esListenerfv(world.id(), ES_POSITION, pos);
  if (e == ES_OK) e = esListenerfv(world.id(), ES_ORIENTATION_QUAT, quat);
  if (e != ES_OK) world.fail(e, origin, "listener at t = " + std::to_string(t) + " s");
}

ListenerTrack::ListenerTrack(const scenes::Scene& scene, const std::optional<std::filesystem::path>& pose_track)
    : fixed_(fixed_listener(scene.listener)) {
  const auto path = pose_track ? pose_track : scene.pose_track;
  origin_ = path ? path->string() : scene.origin.empty() ? "scene" : scene.origin;
  if (path) track_ = scenes::PoseTrack::load(*path);
}

void ListenerTrack::start(const WorldHandle& world) const {
  if (!track_) set_listener(world, fixed_, origin_, 0.0);
}

void ListenerTrack::at(const WorldHandle& world, double t) const {
  if (track_) set_listener(world, track_->at(t), origin_, t);
}

}  // namespace earshot::host
