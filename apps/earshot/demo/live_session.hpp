#pragma once
// The scene side of the live demo, on the control thread: the plugin world,
// the scene's sources in it (host/), the tracker, what can be picked (scene
// presets, sounds, paths, rooms) and the changes the keys and the window ask
// for. The device, the window and the terminal are elsewhere.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "earshot/host/scene_sources.hpp"
#include "earshot/host/tracker_status.hpp"
#include "earshot/host/world_handle.hpp"
#include "earshot/scenes/motion_path.hpp"
#include "earshot/scenes/scene.hpp"
#include "live_demo.hpp"

namespace earshot::demo {

/// A scene read from a preset name or a file, and the name it is shown by.
struct NamedScene {
  scenes::Scene scene;
  std::string name;   ///< the file's name, e.g. "circles.json"
  std::string error;  ///< the asked-for scene's error when Circles stands in
};

/// The scene `arg` (a preset or a file). One with errors is said and
/// Circles plays instead (the audio goes on); `room` ("": the scene's)
/// overrides its room.
[[nodiscard]] NamedScene load_demo_scene(const std::string& arg, const std::string& room);

/// Sounds and paths to pick from: the current scene's, then every preset's.
struct Library {
  std::vector<std::string> sound_names, path_names{"fixed position"};
  std::vector<scenes::Signal> sounds;
  std::vector<scenes::MotionPath> paths;  ///< paths[i] is path_names[i + 1]

  void add(const std::string& scene_name, const scenes::Scene& s);
};

class LiveSession {
 public:
  /// Makes the world (at the scene's rate, `o.buffer` frames a block),
  /// loads the scene into it and attaches the tracker.
  LiveSession(NamedScene first, const LiveOptions& o);

  [[nodiscard]] ESworld world() const { return world_.id(); }
  [[nodiscard]] double rate() const { return rate_; }
  [[nodiscard]] const scenes::Scene& scene() const { return sources_.scene(); }
  [[nodiscard]] const std::string& scene_name() const { return scene_name_; }
  [[nodiscard]] host::SceneSources& sources() { return sources_; }
  [[nodiscard]] const Library& library() const { return lib_; }
  [[nodiscard]] const std::vector<std::string>& scene_args() const { return scene_args_; }
  [[nodiscard]] const std::vector<std::string>& rooms() const { return rooms_; }
  [[nodiscard]] std::size_t scene_pick() const { return scene_pick_; }
  [[nodiscard]] std::size_t room_pick() const { return room_pick_; }
  /// Counts scene loads: a view redraws the scene when it changed.
  [[nodiscard]] std::uint64_t scene_generation() const { return generation_; }

  [[nodiscard]] const host::TrackerStatus& tracker() const { return tracker_; }
  void refresh_tracker() { tracker_.refresh(world_.id()); }
  /// The tracker's picture and camera size, asked for now (esGetTrackerImage;
  /// a ~19 kB copy: at a window's frame rate, not the status line's).
  [[nodiscard]] const EStrackerimage& tracker_image();
  void recenter() { (void)esRecenter(world_.id()); }
  /// Tells the person (stderr, and the window's message line).
  void say(const std::string& m);

  /// The last thing said to the person (scene or room changed, an error).
  [[nodiscard]] const std::string& message() const { return message_; }

  // Changes asked for at `t` seconds of audio; each says what happened.
  void pick_scene(std::size_t i, double t);
  void next_scene(double t);
  void load_scene_file(const std::string& arg, double t);
  void pick_room(std::size_t i);
  void next_room() { pick_room(room_pick_ + 1); }
  /// The next SOFA set of --hrtf (esWorldHrtf: no gap while it switches).
  void next_hrtf();
  /// The set playing, as shown: its file name, or "MIT KEMAR".
  [[nodiscard]] std::string hrtf_name() const;

 private:
  host::WorldHandle world_;
  double rate_;
  host::SceneSources sources_;
  std::string scene_name_, message_;
  std::vector<std::string> scene_args_, rooms_, hrtfs_;
  Library lib_;
  std::size_t scene_pick_ = 0, room_pick_ = 0, hrtf_pick_ = 0;
  std::uint64_t generation_ = 0;
  host::TrackerStatus tracker_;
  std::unique_ptr<EStrackerimage> image_;  // on the heap: ~19 kB
};

}  // namespace earshot::demo
