// Which live tracker source to run, from its one-word spec (the same words
// for `earshot track live --source`, `earshot demo --tracker`,
// esAttachTracker and the OpenAL bridge):
//   wiimote                  a Wii Remote over Bluetooth HID
//   sim                      the simulator's seeded random walk
//   replay:FILE              a recorded Dots CSV
//   opentrack[:PORT][@ADDR]  opentrack's UDP output (default port 4242)
//   osc[:PORT][@ADDR]        OSC head poses: Earshot's, SPARTA's and IEM
//                            SceneRotator's addresses (default port 9000;
//                            docs/OSC.md)
//   webcam[:DEVICE][,OPTION=VALUE...]
//                            a V4L2 webcam (DEVICE: /dev/videoN or N, default
//                            /dev/video0) or a .y4m video standing in for one,
//                            watching the LED beacon or a printed AprilTag.
//                            Options: beacon=leds|apriltag, size_mm=S (the
//                            square the tag detector finds: tag36h11's black
//                            square; the inside of tagStandard41h12's black
//                            ring; README's table), family=F and id=N (which
//                            tag), decimate=D (the tag search's image
//                            reduction, default 2; 1 for a tag far away),
//                            focal=F (pixels) or calib=FILE (OpenCV's
//                            calibration YAML), resolution=WxH and fps=N (a
//                            camera's largest size and rate to use; a file
//                            plays as it is). e.g. webcam:1,beacon=apriltag,size_mm=60
// The first three and webcam deliver camera dots, opentrack and osc ready-made
// poses.
// ADDR is the IPv4 address the UDP socket listens on: 127.0.0.1 by default,
// 0.0.0.0 for every interface, or one interface's address (e.g.
// osc:9000@0.0.0.0, opentrack@192.168.1.5). Loopback is the default because
// pose packets are unauthenticated: a socket open to the network lets anyone
// on it turn the listener's head. Listen wider only on a network you trust.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/frame_source.hpp"
#include "earshot/tracker/core/led_model.hpp"
#include "earshot/tracker/sources/sim_source.hpp"
#include "earshot/webcam/webcam_spec.hpp"

namespace earshot::tracker {

/// The spellings accepted, for help texts and error messages.
inline constexpr std::string_view kSourceSpecs =
    "wiimote, sim, replay:FILE, opentrack[:PORT][@ADDR], osc[:PORT][@ADDR], "
    "webcam[:DEVICE][,beacon=leds|apriltag][,size_mm=S][,family=F][,id=N][,decimate=D][,focal=F][,calib=FILE]"
    "[,resolution=WxH][,fps=N]";

/// Where pose inputs listen unless the spec says otherwise.
inline constexpr std::string_view kDefaultListenAddress = "127.0.0.1";

struct SourceSpec {
  enum class Kind { wiimote, sim, replay, opentrack, osc, webcam };
  Kind kind = Kind::wiimote;
  std::string file;        ///< replay: the Dots CSV
  std::uint16_t port = 0;  ///< opentrack, osc: the UDP port (the default when none is given)
  std::string listen{kDefaultListenAddress};  ///< opentrack, osc: the IPv4 address to listen on
  webcam::WebcamSpec webcam;       ///< webcam: device, beacon, camera model, capture limits

  /// opentrack and osc send poses, not camera dots.
  [[nodiscard]] bool sends_poses() const { return kind == Kind::opentrack || kind == Kind::osc; }
};

/// Parses a spec. Throws earshot::InputError naming `field` (where the spec
/// came from, e.g. "--source") and the spec itself for an unknown kind, a
/// missing or unexpected argument, a port that is not 1..65535, a listen
/// address that is not IPv4 (or given to a source that does not listen), or
/// a webcam option that is unknown, repeated, out of range or not for its beacon.
[[nodiscard]] SourceSpec parse_source_spec(std::string_view spec, std::string_view field = "source");

/// `spec` with "@ADDRESS" appended (what `--listen ADDRESS` means). Throws
/// earshot::InputError naming `spec_field` when the spec does not parse, and
/// naming `listen_field` when it is not a pose source (opentrack, osc),
/// already has a listen address, or `address` is not an IPv4 address.
[[nodiscard]] std::string with_listen_address(std::string_view spec, std::string_view address,
                                              std::string_view spec_field = "--source",
                                              std::string_view listen_field = "--listen");

/// How to build a source beyond its spec.
struct SourceOptions {
  Pacing pacing = Pacing::real_time;         ///< sim, replay, webcam from a .y4m file
  Camera camera = Camera::with_focal(1280.0);  ///< sim
  std::optional<LedModel> model;             ///< sim; default: the thesis beacon
  SimSourceConfig sim{};                     ///< sim: walk, length, faults (its pacing is `pacing`)
  /// wiimote, webcam: no device yet is a `searching` note instead of an
  /// error (for hosts that play on and show how to connect one).
  bool wait_for_remote = false;
};

/// The source a spec names. Throws whatever the source's constructor throws
/// (port in use, unreadable file).
[[nodiscard]] std::unique_ptr<FrameSource> make_frame_source(const SourceSpec& spec, const SourceOptions& options = {});

}  // namespace earshot::tracker
