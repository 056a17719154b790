// A live Wii Remote as a FrameSource, over any HidTransport.
//
// Connect: find 057e:0306 or 057e:0330 (not a Wii U Pro controller), open it,
// light player LED 1, read the accelerometer calibration (EEPROM 0x16), run
// the IR init sequence (wiimote_protocol.hpp) waiting for the acknowledgement
// of each report that asks for one (the IR enables and the register writes):
// a missing one is sent once more, then the connection fails naming the
// report; an acknowledgement with an error code fails it at once.
//
// Then every data report becomes a CameraFrame (dots, calibrated
// accelerometer in the camera frame, buttons). Reports without IR (0x30-0x32,
// 0x34, 0x35: the kernel's hid-wiimote may switch the remote to them) give a
// frame with no dots, so the buttons (A/Home recenter) still arrive; 0x3D has
// no buttons and gives nothing. Full IR comes in halves: a 0x3E and the
// report right after it, if that is a 0x3F, make one frame; a 0x3E followed
// by anything else, or a 0x3F without its 0x3E, is a lost half and dropped.
// A read that fails means the remote went away: the source says so and
// reconnects on its own, every `retry_s`. Malformed reports are counted and
// dropped.
//
// With no remote at the first attempt it throws WiimoteError (with how to
// pair one) instead of waiting forever; after a first connection it keeps
// trying. With `wait_for_remote` (the plugin's choice: its host plays on and
// shows the message) it never throws for a missing remote: it says so in a
// `searching` note, with how to pair one, and keeps looking every `retry_s`.
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>

#include "earshot/tracker/core/frame_source.hpp"
#include "earshot/tracker/sources/hid_transport.hpp"
#include "earshot/tracker/sources/wiimote_protocol.hpp"

namespace earshot::tracker {

/// The Wii Remote accelerometer's axes (+x its left side, +y its back, +z out
/// of the button face; at rest it reads +1 g upward) in the camera frame.
[[nodiscard]] Vec3 remote_accel_to_camera(const Vec3& accel_remote_g);

class WiimoteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct WiimoteOptions {
  wiimote::IrMode mode = wiimote::IrMode::extended;
  wiimote::IrSensitivity sensitivity = wiimote::IrSensitivity::level3;
  double retry_s = 1.0;                                      ///< between reconnection attempts
  std::chrono::milliseconds reply_timeout{500};              ///< for each ack / read reply (per attempt)
  std::function<double()> clock;                             ///< seconds; default steady clock
  bool wait_for_remote = false;  ///< no remote yet: a `searching` note instead of WiimoteError
};

/// The message for "no remote": how to pair one with BlueZ.
[[nodiscard]] std::string no_wiimote_message();

class WiimoteSource final : public FrameSource {
 public:
  explicit WiimoteSource(std::unique_ptr<HidTransport> transport, WiimoteOptions opt = {});
  ~WiimoteSource() override;
  SourceEvent next(std::chrono::milliseconds timeout) override;
  [[nodiscard]] std::string describe() const override { return "wiimote"; }
  [[nodiscard]] std::uint64_t dropped() const override { return dropped_; }
  [[nodiscard]] bool connected() const { return connected_; }
  [[nodiscard]] const wiimote::AccelCalibration& calibration() const { return cal_; }

 private:
  SourceEvent connect();
  /// Sends the init sequence; false (with `why`) when the remote stops answering.
  bool initialise(std::string& why);
  /// Sends `report` and, when it is acknowledged, waits for its 0x22 (twice
  /// at most); false with `why` naming the report and what went wrong.
  bool send(const wiimote::OutputReport& report, std::string& why);
  /// Reads until `want` says yes or the reply timeout passes.
  bool await(const std::function<bool(const wiimote::InputReport&)>& want);
  SourceEvent lose(const std::string& why);
  std::optional<SourceEvent> on_report(std::span<const std::uint8_t> bytes);

  std::unique_ptr<HidTransport> hid_;
  WiimoteOptions opt_;
  bool connected_ = false, ever_connected_ = false;
  double next_attempt_ = 0.0;
  wiimote::AccelCalibration cal_;
  /// The dots of a 0x3E waiting for its 0x3F (the very next report).
  std::optional<std::array<std::optional<wiimote::IrDot>, 2>> first_half_;
  std::uint64_t dropped_ = 0;
};

}  // namespace earshot::tracker
