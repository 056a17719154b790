// Where the tracker sends its poses, from a one-word spec (the same words
// for `earshot track live --send`, `earshot demo --send`, the C API's tracker
// options and the LV2 plugins' send parameter):
//
//   osc[:HOST][:PORT][,format=earshot|sparta|iem|iem-ypr][,rate=HZ]
//   opentrack[:HOST][:PORT][,rate=HZ]
//
// HOST is an IPv4 address or a host name (resolved when the sender opens);
// 127.0.0.1 when none is named: poses go to another program on this machine
// unless a host is named on purpose. PORT defaults to 9000 for OSC (SPARTA's
// default, and Earshot's own OSC input) and 4242 for opentrack. A lone
// number after the kind is the port (osc:9001), anything else the host
// (opentrack:192.168.1.5). rate caps the poses sent per second (1-1000,
// default 100) on the steady clock, whatever rate the source runs at.
//
// OSC formats (float32 messages, one datagram each, never bundles: SPARTA's
// receiver takes neither bundles nor doubles; docs/OSC.md, "Sending poses"):
//   earshot  /earshot/pose/quat x y z qw qx qy qz (Earshot's own input reads it)
//   sparta   /xyz x y z (metres, SAF axes) then /ypr yaw pitch roll (the head,
//            SAF's right-hand rule: pitch + nods down): SPARTA's rotator,
//            binauraliser, ambiBIN and 6DoFconv
//   iem      /SceneRotator/quaternions w x y z: the scene's rotation that
//            compensates the head (IEM SceneRotator; any of its rotation
//            sequences reads it alike)
//   iem-ypr  /SceneRotator/ypr yaw pitch roll of that rotation (for its
//            default sequence, yaw -> pitch -> roll)
// opentrack: its "UDP over network" packet, six little-endian doubles x, y,
// z (cm), yaw, pitch, roll (degrees), opentrack's own signs
// (sources/opentrack_packet.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace earshot::tracker {

/// The spellings accepted, for help texts and error messages.
inline constexpr std::string_view kSendSpecs =
    "osc[:HOST][:PORT][,format=earshot|sparta|iem|iem-ypr][,rate=HZ], opentrack[:HOST][:PORT][,rate=HZ]";

/// Where poses go unless the spec names a host.
inline constexpr std::string_view kDefaultSendHost = "127.0.0.1";
inline constexpr double kDefaultSendRateHz = 100.0;

struct SendSpec {
  enum class Kind { osc, opentrack };
  enum class Format { earshot, sparta, iem, iem_ypr };
  Kind kind = Kind::osc;
  Format format = Format::earshot;  ///< osc only
  std::string host{kDefaultSendHost};
  std::uint16_t port = 0;
  double rate_hz = kDefaultSendRateHz;
  std::string text;  ///< the spec as given, for messages

  friend bool operator==(const SendSpec&, const SendSpec&) = default;
};

/// "earshot", "sparta", "iem", "iem-ypr".
[[nodiscard]] std::string_view send_format_name(SendSpec::Format f);

/// Parses one spec. Throws earshot::InputError naming `field` and the spec
/// for an unknown kind, a bad host, a port that is not 1..65535, an option
/// that is unknown, repeated, empty or out of range, or format= for opentrack.
[[nodiscard]] SendSpec parse_send_spec(std::string_view spec, std::string_view field = "--send");

/// Several specs in one text, separated by ';' (the C API's and the LV2
/// plugins' form; spaces around each are ignored, empty ones skipped).
[[nodiscard]] std::vector<SendSpec> parse_send_list(std::string_view text, std::string_view field = "send");

/// The specs of a list again, joined with ';' (what parse_send_list reads).
[[nodiscard]] std::string send_list_text(const std::vector<SendSpec>& specs);

}  // namespace earshot::tracker
