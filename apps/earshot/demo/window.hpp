#pragma once
// The demo's window (Dear ImGui over GLFW + OpenGL 3): top, front and side
// views of the listener's head and the sources with their names and paths;
// the tracker's camera (its own size: the Wii Remote's 1024 x 768, a
// webcam's resolution) with its dots and their LED labels, under them the
// camera's picture when the source has one (a webcam's thumbnail), its
// state, rate and message ("no remote" and "disconnected" in a banner); audio
// load and xruns; pickers for the scene, the room and, per source, the sound,
// the path or a fixed position, gain and distance attenuation; a recenter
// button; the keys (keys.hpp). It only draws and reports what the person
// did: window_view.cpp applies it to the session (live_session.hpp).
// Built only when Debian's libimgui-dev and libglfw3-dev are present.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace earshot::demo {

struct ViewSource {
  std::string name;
  std::array<float, 3> position{};
  std::vector<std::array<float, 3>> path;  ///< sampled path (empty: fixed)
  float gain_db = 0, rolloff = 1, reference_distance = 1;
  int distance_model = 2;  ///< index into WindowModel::distance_models
  int sound = -1, path_choice = 0;  ///< indices into WindowModel::sounds / paths (0: fixed)
};

struct ViewDot {
  float x = 0, y = 0;  ///< camera pixels
  int size = -1, label = -1;
};

/// What the window shows, refreshed by the control loop each frame.
struct WindowModel {
  std::string scene, room, device, message, hrtf;
  std::array<float, 3> head_position{};
  std::array<float, 4> head_orientation{1, 0, 0, 0};  ///< w, x, y, z
  double time_s = 0, load = 0, load_max = 0, latency_ms = 0;
  unsigned long long xruns = 0, blocks = 0;
  // the tracker (esGetTrackerState)
  std::string tracker, tracker_state, tracker_message;
  bool tracker_alarm = false;  ///< no remote / disconnected / failed: the banner
  float tracker_rate = 0;
  unsigned long long tracker_frames = 0;
  std::vector<ViewDot> dots;
  int camera_width = 1024, camera_height = 768;  ///< the image the dots are in
  /// The camera's picture (esGetTrackerImage): grey, picture_width apart;
  /// empty when the source has none. A new picture_frame: a new picture.
  std::vector<std::uint8_t> picture;
  int picture_width = 0, picture_height = 0;
  std::uint32_t picture_frame = 0;
  // controls
  std::vector<ViewSource> sources;
  std::vector<std::string> scenes, rooms, sounds, paths, distance_models;
  int scene_index = 0, room_index = 0;
  std::string scene_file_input;  ///< the "load a scene file" field
};

/// What the person did this frame.
struct WindowActions {
  bool quit = false, recenter = false, room_changed = false, scene_changed = false, next_scene = false,
       next_room = false, next_hrtf = false, load_file = false;
  std::vector<int> changed_sources;  ///< gain or distance attenuation moved
  std::vector<int> changed_sounds, changed_paths, changed_positions;
};

class DemoWindow {
 public:
  /// Throws std::runtime_error when no window can be opened.
  explicit DemoWindow(const std::string& title);
  ~DemoWindow();
  DemoWindow(const DemoWindow&) = delete;
  DemoWindow& operator=(const DemoWindow&) = delete;

  /// Draws one frame of `m` (controls edit `m`) and reports the actions.
  WindowActions frame(WindowModel& m);
  /// Writes the last frame as a PNG.
  void screenshot(const std::filesystem::path& png) const;
  [[nodiscard]] long frames() const { return frames_; }
  /// Camera pictures uploaded and shown so far (new frames of the picture).
  [[nodiscard]] long pictures() const;
  /// True when OpenGL is rendered in software (Mesa llvmpipe/softpipe, as
  /// under Xvfb): the window then draws without anti-aliasing.
  [[nodiscard]] bool software() const { return software_; }
  [[nodiscard]] const std::string& renderer() const { return renderer_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  long frames_ = 0;
  bool software_ = false;
  std::string renderer_;
};

/// True when this build has the window.
[[nodiscard]] bool window_available();

}  // namespace earshot::demo
