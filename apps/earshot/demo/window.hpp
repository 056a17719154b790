#pragma once
// The demo's window (Dear ImGui over GLFW + OpenGL 3): top, front and side
// views of the listener's head and the sources with their names and paths;
// tracker state and rate; audio load and xruns; per-source gain and rolloff,
// the room preset; a recenter button. Keys: R recenter, Q or Esc quit.
// Built only when Debian's libimgui-dev and libglfw3-dev are present.
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace earshot::demo {

struct ViewSource {
  std::string name;
  std::array<float, 3> position{};
  std::vector<std::array<float, 3>> path;  ///< sampled path (empty: fixed)
  float gain_db = 0, rolloff = 1;
};

/// What the window shows, refreshed by the control loop each frame.
struct WindowModel {
  std::string scene, room, tracker, device, message;
  std::array<float, 3> head_position{};
  std::array<float, 4> head_orientation{1, 0, 0, 0};  ///< w, x, y, z
  double time_s = 0, load = 0, load_max = 0, latency_ms = 0;
  unsigned long long xruns = 0, blocks = 0;
  std::vector<ViewSource> sources;
  std::vector<std::string> rooms;
  int room_index = 0;
};

/// What the person did this frame.
struct WindowActions {
  bool quit = false, recenter = false, room_changed = false;
  std::vector<int> changed_sources;  ///< indices whose gain or rolloff moved
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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  long frames_ = 0;
};

/// True when this build has the window.
[[nodiscard]] bool window_available();

}  // namespace earshot::demo
