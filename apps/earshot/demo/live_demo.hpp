#pragma once
// `earshot demo` in real time: a scene played through PortAudio by the
// plugin's esRender on the audio thread, sources fed by callback sources
// (the scenes' generators), moved along their paths on the control thread,
// the head turned by a tracker attached to the world (its own thread). The
// scene-to-plugin work is the host layer's (host/, via live_session.hpp);
// the demo adds the device, the window, the keys and the status line.
#include <filesystem>
#include <string>
#include <vector>

namespace earshot::demo {

struct LiveOptions {
  std::string scene = "circles", room, tracker = "sim", device;
  std::string ambix;        ///< an Ambisonic file played as a bed, looping ("": none)
  bool ambix_alone = true;  ///< the file alone (no --scene given), else a bed in `scene`
  /// SOFA sets to switch among with 'h' (esWorldHrtf); the first plays at
  /// the start; "" or none: MIT KEMAR.
  std::vector<std::string> hrtfs;
  std::vector<std::string> send;  ///< where the tracker also sends its poses (--send)
  unsigned long buffer = 128;
  double duration = -1;                 ///< seconds; <= 0: until 'q' / Ctrl-C
  std::filesystem::path capture;        ///< WAV of what the callback wrote
  std::filesystem::path capture_poses;  ///< CSV: t, yaw (deg), per control tick, written as it goes
  bool list_devices = false;
  bool window = true;                   ///< open the window when there is a display
  std::filesystem::path screenshot;     ///< window: PNG of the last frame
};

/// Prints the PortAudio output devices.
void list_devices();
/// Plays until the duration ends or 'q'; a status line on the terminal.
/// Returns the number of xruns.
long run_live(const LiveOptions& o);

}  // namespace earshot::demo
