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

#include "earshot/head_pose.hpp"
#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/led_model.hpp"

namespace earshot::tracker {

/// One camera frame: the dots plus what the remote knows about itself.
struct CameraFrame {
  DotFrame dots;                  ///< dots.t: seconds on the source's clock
  std::optional<Vec3> accel_g;    ///< gravity + motion in the camera frame, g
  std::uint16_t buttons = 0;      ///< wiimote::Buttons bits
  /// Blob size per slot as the camera reports it (Wii: 0..15); -1 unknown.
  std::array<int, kSlots> dot_size{-1, -1, -1, -1};
  /// Slot k holds model point k (a tag's corners come labelled): the
  /// tracker solves from them directly, without its labeller.
  bool labelled = false;
};

/// A small grey copy of a camera's newest frame with the dots found in it,
/// for UIs (a fixed-size buffer: copying it never allocates).
struct Thumbnail {
  static constexpr int kMaxWidth = 160, kMaxHeight = 120;
  int width = 0, height = 0;  ///< of the thumbnail; 0: no frame yet
  std::array<std::uint8_t, static_cast<std::size_t>(kMaxWidth) * kMaxHeight> pixels{};  ///< row after row, `width` apart
  std::array<std::optional<Vec2>, kSlots> dots;  ///< in thumbnail pixels (as detected, before undistortion)
  bool labelled = false;     ///< dots[k] is model point k
  std::uint64_t frame = 0;   ///< frames delivered by the source so far
  double t = 0.0;            ///< the frame's time on the source clock
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

/// What a source hands the pipeline: a camera frame of dots, a head pose
/// from a source that solves its own (opentrack, OSC: the head in the audio
/// world frame, +x right, +y up, -z ahead, metres, on the source's clock in
/// `t`), or a note about the link.
using SourceEvent = std::variant<CameraFrame, HeadPose, SourceNote>;

[[nodiscard]] inline SourceNote make_note(SourceNote::Kind kind, std::string message = {},
                                          std::optional<double> t = std::nullopt) {
  SourceNote n;
  n.kind = kind;
  n.message = std::move(message);
  n.t = t;
  return n;
}

/// A source of frames or poses. Called from the tracker thread only.
/// How a source that could run faster than a camera (the simulator, a
/// replayed file, a video) hands out its frames: at their own times, or as
/// fast as they are asked for (offline work, tests).
enum class Pacing { real_time, as_fast_as_possible };

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
  /// The camera behind the dots when the source knows it (a webcam: its
  /// resolution and focal length); nullopt: the tracker's configured one.
  /// May change when the source (re)connects (a `connected` note).
  [[nodiscard]] virtual std::optional<Camera> camera() const { return std::nullopt; }
  /// The beacon the source watches when it defines it (a tag's corners);
  /// nullopt: the tracker's configured LED model.
  [[nodiscard]] virtual std::optional<LedModel> model() const { return std::nullopt; }
  /// Copies the newest frame's thumbnail into `out`; false when the source
  /// has none. Safe from any thread while next() runs (not real-time safe:
  /// it may wait for the copy the tracker thread is making).
  virtual bool thumbnail(Thumbnail& out) const {
    (void)out;
    return false;
  }
};

}  // namespace earshot::tracker
