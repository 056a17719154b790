// The Wii Remote's HID protocol as pure functions: bytes in, values out, and
// values in, bytes out. No I/O here; the transport (hidapi) lives elsewhere.
//
// Output reports start with the report ID; bit 0 of the first payload byte
// is rumble in every output report. Input reports start with their ID too.
// Facts: shared/reference/wiimote-ir-protocol.md (wiibrew and peers).
//
// IR coordinates are reported as the sensor sees them: x 0..1023, y 0..767,
// origin top-left (our camera convention); we do not mirror x.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace earshot::tracker::wiimote {

inline constexpr std::uint16_t kVendorNintendo = 0x057E;
inline constexpr std::uint16_t kProductWiimote = 0x0306;      ///< RVL-CNT-01
inline constexpr std::uint16_t kProductWiimotePlus = 0x0330;  ///< RVL-CNT-01-TR (also Wii U Pro)

/// One output report: ID byte then payload (at most 22 bytes in all).
struct OutputReport {
  std::array<std::uint8_t, 22> bytes{};
  std::size_t size = 0;
  [[nodiscard]] std::span<const std::uint8_t> view() const { return {bytes.data(), size}; }
  [[nodiscard]] std::uint8_t id() const { return bytes[0]; }
};

// ---- Output reports (host -> remote) -------------------------------------

/// 0x11: player LEDs, bit i of `leds` (0..3) lights LED i+1.
[[nodiscard]] OutputReport set_leds(std::uint8_t leds, bool rumble = false);
/// 0x12: data reporting mode (e.g. 0x33), continuous or on change only.
[[nodiscard]] OutputReport set_reporting_mode(std::uint8_t mode, bool continuous, bool rumble = false);
/// 0x13: IR camera pixel clock enable (`13 04` on). With `ack` the report
/// also asks for an acknowledgement (`13 06`), as the Wii and the kernel's
/// hid-wiimote send it.
[[nodiscard]] OutputReport ir_enable(bool on, bool rumble = false, bool ack = false);
/// 0x1A: IR camera logic enable (`1A 04` on; `1A 06` with `ack`).
[[nodiscard]] OutputReport ir_enable2(bool on, bool rumble = false, bool ack = false);
/// 0x15: status request.
[[nodiscard]] OutputReport status_request(bool rumble = false);
/// 0x16: write up to 16 bytes to the register space (address byte 0x04) at `address`
/// (24-bit register address, e.g. 0xB00030). Throws std::invalid_argument
/// for 0 or more than 16 bytes.
[[nodiscard]] OutputReport write_registers(std::uint32_t address, std::span<const std::uint8_t> data,
                                           bool rumble = false);
/// 0x17: read `size` bytes from EEPROM memory (register_space = false) or
/// registers at a 24-bit address.
[[nodiscard]] OutputReport read_memory(std::uint32_t address, std::uint16_t size, bool register_space = false,
                                       bool rumble = false);

/// Bit 1 of the first payload byte of 0x11, 0x12, 0x13 and 0x1A asks the
/// remote to answer with an acknowledgement (input report 0x22).
inline constexpr std::uint8_t kAckRequest = 0x02;

/// Whether the remote answers `r` with an acknowledgement (0x22 naming r's
/// ID, with an error code): always for a memory write (0x16), and for 0x11,
/// 0x12, 0x13 and 0x1A when they carry kAckRequest.
[[nodiscard]] bool expects_acknowledgement(const OutputReport& r);

/// `r` for people, e.g. "0x13 (IR pixel clock enable)" or
/// "0x16 (write of 9 bytes to register 0xB00000)".
[[nodiscard]] std::string describe(const OutputReport& r);

// ---- IR camera set-up ----------------------------------------------------

enum class IrMode : std::uint8_t { basic = 1, extended = 3, full = 5 };

/// Sensitivity blocks in use by peers (block 1: 9 bytes at 0xB00000,
/// block 2: 2 bytes at 0xB0001A). What is known of them (the Wiimote
/// project wiki's IR sensor register map): block 1 byte 6 is the largest
/// blob, byte 8 the gain (smaller is more gain); block 2 is the gain limit
/// (below the gain) and the smallest blob.
///  - level1, level3, level5: the Wii's own levels 1, 3 and 5 (wiibrew;
///    wiiuse and the kernel's hid-wiimote use level 3).
///  - custom_high: `00 00 00 00 00 00 90 00 41` / `40 00`, not a Wii level:
///    wiibrew's table lists it as "suggested by inio (high sensitivity)" and
///    peers offer it as a custom high setting. Some call it "max", but the
///    table's "max sensitivity" is another block (`... ff 00 0c` / `00 00`).
///  - wiiyourself: `00 00 00 00 00 00 90 00 c0` / `40 00`, as WiiYourself
///    uses (wiibrew's table: "suggested by Marcan").
/// No user input names these (WiimoteOptions sets one in code).
enum class IrSensitivity { level1, level3, level5, custom_high, wiiyourself };

struct SensitivityBlocks {
  std::array<std::uint8_t, 9> block1;
  std::array<std::uint8_t, 2> block2;
};
[[nodiscard]] SensitivityBlocks sensitivity_blocks(IrSensitivity s);

/// The data reporting mode that carries `mode`'s IR format with buttons and
/// accelerometer: 0x33 (extended), 0x37 (basic, with extension bytes), 0x3E (full).
[[nodiscard]] std::uint8_t reporting_mode_for(IrMode mode);

/// The IR initialisation sequence, in order: enable 1 and 2 (each asking for
/// an acknowledgement: `13 06`, `1A 06`), B00030 = 08, sensitivity blocks,
/// mode at B00033, B00030 = 08 again, reporting mode (not acknowledged).
/// Send each and wait for its acknowledgement (0x22) where
/// expects_acknowledgement() says one is due.
[[nodiscard]] std::vector<OutputReport> ir_init_sequence(IrMode mode, IrSensitivity s, bool rumble = false);

// ---- Input reports (remote -> host) --------------------------------------

/// Buttons, as the two core bytes with the accelerometer bits masked off.
struct Buttons {
  std::uint16_t bits = 0;
  static constexpr std::uint16_t left = 0x0001, right = 0x0002, down = 0x0004, up = 0x0008, plus = 0x0010,
                                 two = 0x0100, one = 0x0200, b = 0x0400, a = 0x0800, minus = 0x1000,
                                 home = 0x8000;
  [[nodiscard]] bool pressed(std::uint16_t mask) const { return (bits & mask) != 0; }
  friend bool operator==(const Buttons&, const Buttons&) = default;
};

/// One IR dot. The camera marks an empty slot with all bits set (x = y =
/// 1023; in the extended format the bytes `FF FF FF`); the decoders return
/// no dot for that and for any y above 767, which the sensor never reports.
struct IrDot {
  std::uint16_t x = 0, y = 0;  ///< 0..1023, 0..767
  std::uint8_t size = 0;       ///< 0..15 (extended and full formats)
  // Full format only:
  std::uint8_t x_min = 0, y_min = 0, x_max = 0, y_max = 0, intensity = 0;
};

/// Accelerometer raw counts (10 bits per axis).
struct AccelRaw {
  std::uint16_t x = 0, y = 0, z = 0;
};

struct StatusReport {
  Buttons buttons;
  bool battery_low = false, extension = false, speaker = false, ir = false;
  std::uint8_t leds = 0;     ///< bit i: LED i+1
  std::uint8_t battery = 0;  ///< raw level, 0..~200
};

struct ReadReply {
  Buttons buttons;
  std::uint8_t error = 0;        ///< 0 ok, 7 write-only, 8 no such address
  std::uint8_t size = 0;         ///< bytes in this reply, 1..16
  std::uint16_t address_low = 0; ///< low 16 bits of the address of data[0]
  std::array<std::uint8_t, 16> data{};
};

struct Acknowledge {
  Buttons buttons;
  std::uint8_t report = 0;  ///< the output report acknowledged
  std::uint8_t error = 0;
};

/// A data report (0x30-0x37, 0x3D-0x3F). What each carries besides
/// extension bytes (which we do not decode):
///   0x30 buttons; 0x31 buttons, accelerometer; 0x32 buttons (+8);
///   0x33 buttons, accelerometer, extended IR; 0x34 buttons (+19);
///   0x35 buttons, accelerometer (+16); 0x36 buttons, basic IR (+9);
///   0x37 buttons, accelerometer, basic IR (+6); 0x3D extension bytes only
///   (21: no buttons); 0x3E/0x3F buttons and half of the full IR (the
///   accelerometer is split across the pair and not decoded).
struct DataReport {
  std::uint8_t id = 0;
  std::optional<Buttons> buttons;  ///< none in 0x3D
  std::optional<AccelRaw> accel;
  std::array<std::optional<IrDot>, 4> ir{};  ///< by camera slot; empty = not seen
  bool has_ir = false;
  /// Full IR (0x3E/0x3F) carries two dots per report: slots 0-1 (0x3E) or
  /// 2-3 (0x3F). The two make one camera frame only as a pair, 0x3E then
  /// 0x3F; the reports carry no frame counter, so pairing is the reader's job.
  int ir_first_slot = 0, ir_slot_count = 4;
};

using InputReport = std::variant<StatusReport, ReadReply, Acknowledge, DataReport>;

/// Decodes one input report (ID byte first). nullopt with `why` set when the
/// bytes are not a report we know or are too short: drop it, never trust it.
[[nodiscard]] std::optional<InputReport> decode(std::span<const std::uint8_t> bytes, std::string* why = nullptr);

/// IR formats on their own (exposed for tests).
[[nodiscard]] std::optional<IrDot> decode_ir_extended(std::span<const std::uint8_t, 3> b);
[[nodiscard]] std::array<std::optional<IrDot>, 2> decode_ir_basic(std::span<const std::uint8_t, 5> b);
[[nodiscard]] std::optional<IrDot> decode_ir_full(std::span<const std::uint8_t, 9> b);

// ---- Accelerometer calibration --------------------------------------------

inline constexpr std::uint32_t kAccelCalibrationAddress = 0x0016;
inline constexpr std::uint16_t kAccelCalibrationSize = 10;

struct AccelCalibration {
  std::array<double, 3> zero{};  ///< counts at 0 g
  std::array<double, 3> one_g{}; ///< counts at +1 g
  /// Acceleration in g from raw counts.
  [[nodiscard]] std::array<double, 3> apply(const AccelRaw& raw) const;
};

/// Parses the 10 bytes read from EEPROM 0x0016: zero-g X,Y,Z (high 8 bits),
/// their low bits as --XXYYZZ, +1 g X,Y,Z, their low bits, then at 0x1F a
/// checksum: the low byte of 0x55 plus the sum of the nine bytes before it.
/// The checksum is required: nullopt for fewer than 10 bytes, a checksum
/// that does not match, or a zero gain (+1 g equal to zero g) on any axis.
[[nodiscard]] std::optional<AccelCalibration> parse_accel_calibration(std::span<const std::uint8_t> bytes);

}  // namespace earshot::tracker::wiimote
