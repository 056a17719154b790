// What the live tracker reads: one interface for every input.
//
// Camera sources (Wii Remote, simulator, Dots CSV replay) deliver dot frames
// that still need labelling and solving; pose sources (opentrack UDP, OSC)
// deliver a head pose directly. Notes tell the tracker thread what happened
// to the source (nothing arrived in time, it ended, it lost or regained its
// device) so its state machine can report it instead of guessing.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "earshot/tracker/dots_csv.hpp"

namespace earshot::tracker {

/// One camera frame: the dots plus what the remote knows about itself.
struct CameraFrame {
  DotFrame dots;                  ///< dots.t: seconds on the source's clock
  std::optional<Vec3> accel_g;    ///< gravity + motion in the camera frame, g
  std::uint16_t buttons = 0;      ///< wiimote::Buttons bits
  /// Blob size per slot as the camera reports it (Wii: 0..15); -1 unknown.
  std::array<int, kSlots> dot_size{-1, -1, -1, -1};
};

/// A head pose from a source that solves its own (opentrack, OSC): the head
/// in the audio world frame (+x right, +y up, -z ahead), metres.
struct DirectPose {
  double t = 0.0;  ///< seconds on the source's clock
  Vec3 position_m = Vec3::Zero();
  Quat orientation = Quat::Identity();
};

struct SourceNote {
  enum class Kind {
    timeout,       ///< nothing arrived within the wait
    ended,         ///< the source has no more input (replay done, simulator stopped)
    disconnected,  ///< the device went away; the source tries to reconnect
    connected,     ///< (re)connected and initialised
    recenter,      ///< the user asked to recenter (a button, an OSC message)
    searching,     ///< no device yet (never connected); the source keeps looking
  };
  Kind kind = Kind::timeout;
  std::string message;      ///< for people: what happened and what to do
  std::optional<double> t;  ///< source-clock time, when the source knows it
};

using SourceEvent = std::variant<CameraFrame, DirectPose, SourceNote>;

[[nodiscard]] inline SourceNote make_note(SourceNote::Kind kind, std::string message = {},
                                          std::optional<double> t = std::nullopt) {
  SourceNote n;
  n.kind = kind;
  n.message = std::move(message);
  n.t = t;
  return n;
}

/// A source of frames or poses. Called from the tracker thread only.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  /// The next event, waiting at most `timeout` (a timeout note when nothing came).
  /// Errors the source cannot recover from throw (with a message for people).
  virtual SourceEvent next(std::chrono::milliseconds timeout) = 0;
  /// "wiimote", "sim", "replay:walk.csv", "opentrack:4242", ...
  [[nodiscard]] virtual std::string describe() const = 0;
  /// Malformed input dropped so far (packets, reports, lines).
  [[nodiscard]] virtual std::uint64_t dropped() const { return 0; }
};

}  // namespace earshot::tracker
