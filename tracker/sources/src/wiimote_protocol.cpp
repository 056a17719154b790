#include "earshot/tracker/sources/wiimote_protocol.hpp"

#include <stdexcept>

namespace earshot::tracker::wiimote {
namespace {

OutputReport report(std::uint8_t id, std::initializer_list<std::uint8_t> payload, bool rumble) {
  OutputReport r;
  r.bytes[0] = id;
  std::size_t i = 1;
  for (auto b : payload) r.bytes[i++] = b;
  r.size = i;
  if (rumble) r.bytes[1] |= 0x01;
  return r;
}

Buttons buttons_of(std::span<const std::uint8_t> b) {
  // Core buttons in bytes 1-2; the accelerometer's low bits ride in the
  // unused bits 5-6 of each, so mask them out.
  return {static_cast<std::uint16_t>((b[1] & 0x1F) | ((b[2] & 0x9F) << 8))};
}

AccelRaw accel_of(std::span<const std::uint8_t> b) {
  // X has 10 bits (low two in byte 1 bits 5-6); Y and Z have 9 (their low
  // bit 1 in byte 2 bits 5 and 6), bit 0 reads as zero.
  AccelRaw a;
  a.x = static_cast<std::uint16_t>((b[3] << 2) | ((b[1] >> 5) & 0x03));
  a.y = static_cast<std::uint16_t>((b[4] << 2) | ((b[2] >> 4) & 0x02));
  a.z = static_cast<std::uint16_t>((b[5] << 2) | ((b[2] >> 5) & 0x02));
  return a;
}

std::string hex(std::uint8_t v) {
  static constexpr char digits[] = "0123456789ABCDEF";
  return std::string("0x") + digits[v >> 4] + digits[v & 0x0F];
}

enum class IrFormat { none, extended, basic, full };

/// Where a data report keeps what we decode. Sizes include the ID byte.
struct DataLayout {
  std::size_t size;
  bool buttons, accel;
  IrFormat ir;
  std::size_t ir_at;
};

std::optional<DataLayout> data_layout(std::uint8_t id) {
  switch (id) {
    case 0x30: return DataLayout{3, true, false, IrFormat::none, 0};
    case 0x31: return DataLayout{6, true, true, IrFormat::none, 0};
    case 0x32: return DataLayout{11, true, false, IrFormat::none, 0};  // + 8 extension bytes
    case 0x33: return DataLayout{18, true, true, IrFormat::extended, 6};
    case 0x34: return DataLayout{22, true, false, IrFormat::none, 0};  // + 19 extension bytes
    case 0x35: return DataLayout{22, true, true, IrFormat::none, 0};   // + 16 extension bytes
    case 0x36: return DataLayout{22, true, false, IrFormat::basic, 3};
    case 0x37: return DataLayout{22, true, true, IrFormat::basic, 6};
    case 0x3D: return DataLayout{22, false, false, IrFormat::none, 0};  // 21 extension bytes, no buttons
    case 0x3E: case 0x3F: return DataLayout{22, true, false, IrFormat::full, 4};
    default: return std::nullopt;
  }
}

bool fail(std::string* why, const std::string& msg) {
  if (why) *why = msg;
  return false;
}

}  // namespace

OutputReport set_leds(std::uint8_t leds, bool rumble) {
  return report(0x11, {static_cast<std::uint8_t>((leds & 0x0F) << 4)}, rumble);
}

OutputReport set_reporting_mode(std::uint8_t mode, bool continuous, bool rumble) {
  return report(0x12, {static_cast<std::uint8_t>(continuous ? 0x04 : 0x00), mode}, rumble);
}

OutputReport ir_enable(bool on, bool rumble, bool ack) {
  return report(0x13, {static_cast<std::uint8_t>((on ? 0x04 : 0x00) | (ack ? kAckRequest : 0x00))}, rumble);
}
OutputReport ir_enable2(bool on, bool rumble, bool ack) {
  return report(0x1A, {static_cast<std::uint8_t>((on ? 0x04 : 0x00) | (ack ? kAckRequest : 0x00))}, rumble);
}
OutputReport status_request(bool rumble) { return report(0x15, {0x00}, rumble); }

OutputReport write_registers(std::uint32_t address, std::span<const std::uint8_t> data, bool rumble) {
  if (data.empty() || data.size() > 16) throw std::invalid_argument("write_registers: 1 to 16 bytes");
  OutputReport r = report(0x16,
                          {0x04, static_cast<std::uint8_t>(address >> 16), static_cast<std::uint8_t>(address >> 8),
                           static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(data.size())},
                          rumble);
  for (std::size_t i = 0; i < 16; ++i) r.bytes[6 + i] = i < data.size() ? data[i] : 0x00;
  r.size = 22;
  return r;
}

OutputReport read_memory(std::uint32_t address, std::uint16_t size, bool register_space, bool rumble) {
  return report(0x17,
                {static_cast<std::uint8_t>(register_space ? 0x04 : 0x00), static_cast<std::uint8_t>(address >> 16),
                 static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address),
                 static_cast<std::uint8_t>(size >> 8), static_cast<std::uint8_t>(size)},
                rumble);
}

bool expects_acknowledgement(const OutputReport& r) {
  if (r.size < 2) return false;
  switch (r.id()) {
    case 0x16: return true;
    case 0x11: case 0x12: case 0x13: case 0x1A: return (r.bytes[1] & kAckRequest) != 0;
    default: return false;
  }
}

std::string describe(const OutputReport& r) {
  const std::string id = hex(r.id());
  switch (r.id()) {
    case 0x11: return id + " (player LEDs)";
    case 0x12: return id + " (data reporting mode)";
    case 0x13: return id + " (IR pixel clock enable)";
    case 0x15: return id + " (status request)";
    case 0x16: {
      if (r.size < 6) return id + " (memory write)";
      static constexpr char digits[] = "0123456789ABCDEF";
      std::string address = "0x";
      for (std::size_t i = 2; i < 5; ++i) address += {digits[r.bytes[i] >> 4], digits[r.bytes[i] & 0x0F]};
      return id + " (write of " + std::to_string(r.bytes[5]) + (r.bytes[5] == 1 ? " byte to " : " bytes to ") +
             ((r.bytes[1] & 0x04) ? "register " : "EEPROM ") + address + ")";
    }
    case 0x17: return id + " (memory read)";
    case 0x1A: return id + " (IR logic enable)";
    default: return id;
  }
}

SensitivityBlocks sensitivity_blocks(IrSensitivity s) {
  switch (s) {
    case IrSensitivity::level1: return {{0x02, 0x00, 0x00, 0x71, 0x01, 0x00, 0x64, 0x00, 0xfe}, {0xfd, 0x05}};
    case IrSensitivity::level3: return {{0x02, 0x00, 0x00, 0x71, 0x01, 0x00, 0xaa, 0x00, 0x64}, {0x63, 0x03}};
    case IrSensitivity::level5: return {{0x07, 0x00, 0x00, 0x71, 0x01, 0x00, 0x72, 0x00, 0x20}, {0x1f, 0x03}};
    case IrSensitivity::custom_high: return {{0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x90, 0x00, 0x41}, {0x40, 0x00}};
    case IrSensitivity::wiiyourself: return {{0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x90, 0x00, 0xc0}, {0x40, 0x00}};
  }
  return sensitivity_blocks(IrSensitivity::level3);
}

std::uint8_t reporting_mode_for(IrMode mode) {
  switch (mode) {
    case IrMode::basic: return 0x37;
    case IrMode::extended: return 0x33;
    case IrMode::full: return 0x3E;
  }
  return 0x33;
}

std::vector<OutputReport> ir_init_sequence(IrMode mode, IrSensitivity s, bool rumble) {
  const SensitivityBlocks blocks = sensitivity_blocks(s);
  const std::uint8_t eight = 0x08;
  const auto m = static_cast<std::uint8_t>(mode);
  return {ir_enable(true, rumble, true),
          ir_enable2(true, rumble, true),
          write_registers(0xB00030, std::span(&eight, 1), rumble),
          write_registers(0xB00000, blocks.block1, rumble),
          write_registers(0xB0001A, blocks.block2, rumble),
          write_registers(0xB00033, std::span(&m, 1), rumble),
          write_registers(0xB00030, std::span(&eight, 1), rumble),
          set_reporting_mode(reporting_mode_for(mode), true, rumble)};
}

std::optional<IrDot> decode_ir_extended(std::span<const std::uint8_t, 3> b) {
  IrDot d;
  d.x = static_cast<std::uint16_t>(b[0] | ((b[2] & 0x30) << 4));
  d.y = static_cast<std::uint16_t>(b[1] | ((b[2] & 0xC0) << 2));
  d.size = b[2] & 0x0F;
  if (d.y > 767) return std::nullopt;  // the empty slot (FF FF FF: y = 1023), or no dot the sensor can see
  return d;
}

std::array<std::optional<IrDot>, 2> decode_ir_basic(std::span<const std::uint8_t, 5> b) {
  std::array<std::optional<IrDot>, 2> out;
  IrDot d1, d2;
  d1.x = static_cast<std::uint16_t>(b[0] | ((b[2] & 0x30) << 4));
  d1.y = static_cast<std::uint16_t>(b[1] | ((b[2] & 0xC0) << 2));
  d2.x = static_cast<std::uint16_t>(b[3] | ((b[2] & 0x03) << 8));
  d2.y = static_cast<std::uint16_t>(b[4] | ((b[2] & 0x0C) << 6));
  if (d1.y <= 767) out[0] = d1;  // x has 10 bits: always <= 1023
  if (d2.y <= 767) out[1] = d2;
  return out;
}

std::optional<IrDot> decode_ir_full(std::span<const std::uint8_t, 9> b) {
  auto d = decode_ir_extended(b.first<3>());
  if (!d) return std::nullopt;
  d->x_min = b[3] & 0x7F;
  d->y_min = b[4] & 0x7F;
  d->x_max = b[5] & 0x7F;
  d->y_max = b[6] & 0x7F;
  d->intensity = b[8];
  return d;
}

std::optional<InputReport> decode(std::span<const std::uint8_t> b, std::string* why) {
  auto need = [&](std::size_t n) {
    return b.size() >= n || fail(why, "report " + hex(b[0]) + " too short: " +
                                         std::to_string(b.size()) + " bytes, need " + std::to_string(n));
  };
  if (b.empty()) {
    fail(why, "empty report");
    return std::nullopt;
  }
  switch (b[0]) {
    case 0x20: {
      if (!need(7)) return std::nullopt;
      StatusReport s;
      s.buttons = buttons_of(b);
      s.battery_low = b[3] & 0x01;
      s.extension = b[3] & 0x02;
      s.speaker = b[3] & 0x04;
      s.ir = b[3] & 0x08;
      s.leds = static_cast<std::uint8_t>(b[3] >> 4);
      s.battery = b[6];
      return s;
    }
    case 0x21: {
      if (!need(22)) return std::nullopt;
      ReadReply r;
      r.buttons = buttons_of(b);
      r.size = static_cast<std::uint8_t>((b[3] >> 4) + 1);
      r.error = b[3] & 0x0F;
      r.address_low = static_cast<std::uint16_t>((b[4] << 8) | b[5]);
      for (std::size_t i = 0; i < 16; ++i) r.data[i] = b[6 + i];
      return r;
    }
    case 0x22: {
      if (!need(5)) return std::nullopt;
      return Acknowledge{buttons_of(b), b[3], b[4]};
    }
    default: {
      const auto layout = data_layout(b[0]);
      if (!layout) break;
      if (!need(layout->size)) return std::nullopt;
      DataReport d;
      d.id = b[0];
      if (layout->buttons) d.buttons = buttons_of(b);
      if (layout->accel) d.accel = accel_of(b);
      switch (layout->ir) {
        case IrFormat::none: break;
        case IrFormat::extended:
          d.has_ir = true;
          for (std::size_t k = 0; k < 4; ++k) d.ir[k] = decode_ir_extended(b.subspan(layout->ir_at + 3 * k).first<3>());
          break;
        case IrFormat::basic:
          d.has_ir = true;
          for (std::size_t k = 0; k < 2; ++k) {
            const auto pair = decode_ir_basic(b.subspan(layout->ir_at + 5 * k).first<5>());
            d.ir[2 * k] = pair[0];
            d.ir[2 * k + 1] = pair[1];
          }
          break;
        case IrFormat::full:
          // Interleaved: each report has two 9-byte dots (and a share of the
          // accelerometer, which we leave).
          d.has_ir = true;
          d.ir_first_slot = b[0] == 0x3E ? 0 : 2;
          d.ir_slot_count = 2;
          for (std::size_t k = 0; k < 2; ++k)
            d.ir[static_cast<std::size_t>(d.ir_first_slot) + k] =
                decode_ir_full(b.subspan(layout->ir_at + 9 * k).first<9>());
          break;
      }
      return d;
    }
  }
  fail(why, "unknown input report " + hex(b[0]));
  return std::nullopt;
}

std::array<double, 3> AccelCalibration::apply(const AccelRaw& raw) const {
  const std::array<double, 3> v{static_cast<double>(raw.x), static_cast<double>(raw.y), static_cast<double>(raw.z)};
  std::array<double, 3> g{};
  for (std::size_t i = 0; i < 3; ++i) g[i] = (v[i] - zero[i]) / (one_g[i] - zero[i]);
  return g;
}

std::optional<AccelCalibration> parse_accel_calibration(std::span<const std::uint8_t> b) {
  if (b.size() < kAccelCalibrationSize) return std::nullopt;
  unsigned sum = 0x55;
  for (std::size_t i = 0; i < 9; ++i) sum += b[i];
  if ((sum & 0xFF) != b[9]) return std::nullopt;
  AccelCalibration c;
  for (std::size_t i = 0; i < 3; ++i) {
    const unsigned shift = static_cast<unsigned>(4 - 2 * i);  // low bits: --XXYYZZ
    c.zero[i] = static_cast<double>((b[i] << 2) | ((b[3] >> shift) & 0x03));
    c.one_g[i] = static_cast<double>((b[4 + i] << 2) | ((b[7] >> shift) & 0x03));
    if (c.one_g[i] == c.zero[i]) return std::nullopt;
  }
  return c;
}

}  // namespace earshot::tracker::wiimote
