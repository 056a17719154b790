#pragma once
// The live demo's window wiring: fills the window's model (window.hpp) from
// the session and the audio's counters, draws a frame when it is due, and
// applies what the person did there to the session. Without a display, or
// in a build without the window, open() gives nothing and the terminal's
// status line is all there is.
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "audio_output.hpp"
#include "earshot/head_pose.hpp"
#include "live_demo.hpp"
#include "live_session.hpp"

namespace earshot::demo {

class WindowView {
 public:
  /// The window, when `o.window` and there is a display; else null (said on
  /// stderr when the window cannot open). `device`, `latency_s`: shown.
  [[nodiscard]] static std::unique_ptr<WindowView> open(const LiveOptions& o, const LiveSession& session,
                                                        const std::string& device, double latency_s);
  ~WindowView();
  WindowView(const WindowView&) = delete;
  WindowView& operator=(const WindowView&) = delete;

  /// Draws a frame when one is due (at most 30 a second, fewer in software
  /// OpenGL; 4 a second when nothing moved) and applies the person's
  /// actions to `session`. False: the person closed the window or quit.
  /// `head`: the head as the last block heard it (esGetHeadPose).
  bool tick(LiveSession& session, const OutputStats& stats, const HeadPose& head, double t);
  /// At the end: frames drawn, the screenshot asked for.
  void finish(const LiveOptions& o);

 private:
  struct Impl;
  explicit WindowView(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace earshot::demo
