// Byte-exact tests of the Wii Remote protocol against the documented reports
// (shared/reference/wiimote-ir-protocol.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "earshot/tracker/sources/wiimote_protocol.hpp"

using namespace earshot::tracker::wiimote;

namespace {
std::vector<std::uint8_t> bytes(const OutputReport& r) { return {r.view().begin(), r.view().end()}; }
using B = std::vector<std::uint8_t>;
}  // namespace

TEST(WiimoteOutput, SimpleReports) {
  EXPECT_EQ(bytes(set_leds(0b0001)), (B{0x11, 0x10}));
  EXPECT_EQ(bytes(set_leds(0b1001, true)), (B{0x11, 0x91}));
  EXPECT_EQ(bytes(set_reporting_mode(0x33, true)), (B{0x12, 0x04, 0x33}));
  EXPECT_EQ(bytes(set_reporting_mode(0x30, false, true)), (B{0x12, 0x01, 0x30}));
  EXPECT_EQ(bytes(ir_enable(true)), (B{0x13, 0x04}));
  EXPECT_EQ(bytes(ir_enable(false)), (B{0x13, 0x00}));
  EXPECT_EQ(bytes(ir_enable2(true)), (B{0x1A, 0x04}));
  EXPECT_EQ(bytes(ir_enable(true, false, true)), (B{0x13, 0x06}));  // asking for an acknowledgement
  EXPECT_EQ(bytes(ir_enable2(true, true, true)), (B{0x1A, 0x07}));
  EXPECT_EQ(bytes(status_request()), (B{0x15, 0x00}));
  EXPECT_EQ(bytes(read_memory(0x0016, 7)), (B{0x17, 0x00, 0x00, 0x00, 0x16, 0x00, 0x07}));
  EXPECT_EQ(bytes(read_memory(0xA400FA, 6, true)), (B{0x17, 0x04, 0xA4, 0x00, 0xFA, 0x00, 0x06}));
}

TEST(WiimoteOutput, WriteRegistersPadsTo16) {
  const std::uint8_t eight = 0x08;
  B expect{0x16, 0x04, 0xB0, 0x00, 0x30, 0x01, 0x08};
  expect.resize(22, 0x00);
  EXPECT_EQ(bytes(write_registers(0xB00030, std::span(&eight, 1))), expect);
  EXPECT_THROW((void)write_registers(0xB00000, std::span<const std::uint8_t>()), std::invalid_argument);
  const std::array<std::uint8_t, 17> big{};
  EXPECT_THROW((void)write_registers(0xB00000, big), std::invalid_argument);
}

TEST(WiimoteOutput, IrInitSequenceLevel3Extended) {
  const auto seq = ir_init_sequence(IrMode::extended, IrSensitivity::level3);
  ASSERT_EQ(seq.size(), 8u);
  EXPECT_EQ(bytes(seq[0]), (B{0x13, 0x06}));  // enable, acknowledgement requested
  EXPECT_EQ(bytes(seq[1]), (B{0x1A, 0x06}));
  auto w = [](std::uint32_t a, B data) {
    B r(22, 0x00);
    const B head{0x16, 0x04, static_cast<std::uint8_t>(a >> 16), static_cast<std::uint8_t>(a >> 8),
                 static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(data.size())};
    std::copy(head.begin(), head.end(), r.begin());
    std::copy(data.begin(), data.end(), r.begin() + 6);
    return r;
  };
  EXPECT_EQ(bytes(seq[2]), w(0xB00030, {0x08}));
  EXPECT_EQ(bytes(seq[3]), w(0xB00000, {0x02, 0x00, 0x00, 0x71, 0x01, 0x00, 0xaa, 0x00, 0x64}));
  EXPECT_EQ(bytes(seq[4]), w(0xB0001A, {0x63, 0x03}));
  EXPECT_EQ(bytes(seq[5]), w(0xB00033, {0x03}));
  EXPECT_EQ(bytes(seq[6]), w(0xB00030, {0x08}));
  EXPECT_EQ(bytes(seq[7]), (B{0x12, 0x04, 0x33}));
}

TEST(WiimoteOutput, SensitivityTable) {
  EXPECT_EQ(sensitivity_blocks(IrSensitivity::level1).block2, (std::array<std::uint8_t, 2>{0xfd, 0x05}));
  EXPECT_EQ(sensitivity_blocks(IrSensitivity::level5).block1[0], 0x07);
  EXPECT_EQ(sensitivity_blocks(IrSensitivity::custom_high).block1,
            (std::array<std::uint8_t, 9>{0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x90, 0x00, 0x41}));
  EXPECT_EQ(sensitivity_blocks(IrSensitivity::custom_high).block2, (std::array<std::uint8_t, 2>{0x40, 0x00}));
  EXPECT_EQ(sensitivity_blocks(IrSensitivity::wiiyourself).block1[8], 0xc0);
  EXPECT_EQ(reporting_mode_for(IrMode::basic), 0x37);
  EXPECT_EQ(reporting_mode_for(IrMode::full), 0x3E);
}

// Which reports the remote answers with a 0x22, and how they are named in errors.
TEST(WiimoteOutput, WhichReportsAreAcknowledged) {
  const std::uint8_t eight = 0x08;
  EXPECT_TRUE(expects_acknowledgement(write_registers(0xB00030, std::span(&eight, 1))));
  EXPECT_TRUE(expects_acknowledgement(ir_enable(true, false, true)));
  EXPECT_TRUE(expects_acknowledgement(ir_enable2(false, true, true)));
  EXPECT_FALSE(expects_acknowledgement(ir_enable(true)));
  EXPECT_FALSE(expects_acknowledgement(ir_enable2(true, true)));  // rumble is bit 0, not the request
  EXPECT_FALSE(expects_acknowledgement(set_reporting_mode(0x33, true)));
  EXPECT_FALSE(expects_acknowledgement(set_leds(0x0F)));
  EXPECT_FALSE(expects_acknowledgement(read_memory(0x0016, 10)));  // answered by 0x21 instead
  EXPECT_FALSE(expects_acknowledgement(status_request()));         // answered by 0x20
  const auto seq = ir_init_sequence(IrMode::extended, IrSensitivity::level3);
  std::vector<bool> acked;
  for (const auto& r : seq) acked.push_back(expects_acknowledgement(r));
  EXPECT_EQ(acked, (std::vector<bool>{true, true, true, true, true, true, true, false}));
  EXPECT_EQ(describe(ir_enable(true, false, true)), "0x13 (IR pixel clock enable)");
  EXPECT_EQ(describe(ir_enable2(true, false, true)), "0x1A (IR logic enable)");
  EXPECT_EQ(describe(seq[3]), "0x16 (write of 9 bytes to register 0xB00000)");
  EXPECT_EQ(describe(read_memory(0x0016, 10)), "0x17 (memory read)");
}

TEST(WiimoteInput, ExtendedIrWithButtonsAndAccel) {
  // Buttons A + Home, accel X = 0x200 + 3, Y = 0x1F0 + 2, Z = 0x260 + 0;
  // dots (803, 420, size 3), (822, 302, 2), empty, (191, 767, 15).
  B r{0x33,
      static_cast<std::uint8_t>(0x00 | (3 << 5)), static_cast<std::uint8_t>(0x08 | 0x80 | (1 << 5) | (0 << 6)),
      0x80, 0x7C, 0x98,
      0x23, 0xA4, static_cast<std::uint8_t>((1 << 6) | (3 << 4) | 3),   // 803 = 0x323, 420 = 0x1A4
      0x36, 0x2E, static_cast<std::uint8_t>((1 << 6) | (3 << 4) | 2),   // 822 = 0x336, 302 = 0x12E
      0xFF, 0xFF, 0xFF,
      0xBF, 0xFF, static_cast<std::uint8_t>((2 << 6) | (0 << 4) | 15)};  // 191, 767 = 0x2FF
  std::string why;
  const auto in = decode(r, &why);
  ASSERT_TRUE(in.has_value()) << why;
  const auto& d = std::get<DataReport>(*in);
  EXPECT_TRUE(d.buttons->pressed(Buttons::a));
  EXPECT_TRUE(d.buttons->pressed(Buttons::home));
  EXPECT_FALSE(d.buttons->pressed(Buttons::b));
  EXPECT_EQ(d.buttons->bits, Buttons::a | Buttons::home);
  ASSERT_TRUE(d.accel.has_value());
  EXPECT_EQ(d.accel->x, 0x200 + 3);
  EXPECT_EQ(d.accel->y, 0x1F0 + 2);
  EXPECT_EQ(d.accel->z, 0x260);
  ASSERT_TRUE(d.ir[0] && d.ir[1] && !d.ir[2] && d.ir[3]);
  EXPECT_EQ(d.ir[0]->x, 803);
  EXPECT_EQ(d.ir[0]->y, 420);
  EXPECT_EQ(d.ir[0]->size, 3);
  EXPECT_EQ(d.ir[1]->x, 822);
  EXPECT_EQ(d.ir[1]->y, 302);
  EXPECT_EQ(d.ir[3]->x, 191);
  EXPECT_EQ(d.ir[3]->y, 767);
  EXPECT_EQ(d.ir[3]->size, 15);
}

TEST(WiimoteInput, BasicIr) {
  // 0x36: buttons, 10 IR bytes (two pairs), 9 extension bytes.
  // Pair 1: (1023, 767) and empty (x2 = y2 = 1023); pair 2: (0, 0) and (512, 384).
  B r{0x36, 0x00, 0x00,
      0xFF, 0xFF, static_cast<std::uint8_t>((2 << 6) | (3 << 4) | (3 << 2) | 3), 0xFF, 0xFF,
      0x00, 0x00, static_cast<std::uint8_t>((0 << 6) | (0 << 4) | (1 << 2) | 2), 0x00, 0x80};
  r.resize(22, 0x00);
  const auto in = decode(r);
  ASSERT_TRUE(in.has_value());
  const auto& d = std::get<DataReport>(*in);
  EXPECT_FALSE(d.accel.has_value());
  ASSERT_TRUE(d.ir[0].has_value());
  EXPECT_EQ(d.ir[0]->x, 1023);
  EXPECT_EQ(d.ir[0]->y, 767);
  EXPECT_FALSE(d.ir[1].has_value());
  ASSERT_TRUE(d.ir[2] && d.ir[3]);
  EXPECT_EQ(d.ir[2]->x, 0);
  EXPECT_EQ(d.ir[3]->x, 512);
  EXPECT_EQ(d.ir[3]->y, 384);
}

TEST(WiimoteInput, FullIrInterleaved) {
  B r{0x3E, 0x00, 0x00, 0x00};
  const B dot{0x00, 0x80, static_cast<std::uint8_t>((1 << 6) | (2 << 4) | 7), 10, 20, 30, 40, 0x00, 200};  // (512, 384)
  r.insert(r.end(), dot.begin(), dot.end());
  r.insert(r.end(), 9, 0xFF);
  const auto in = decode(r);
  ASSERT_TRUE(in.has_value());
  const auto& d = std::get<DataReport>(*in);
  EXPECT_EQ(d.ir_first_slot, 0);
  EXPECT_EQ(d.ir_slot_count, 2);
  ASSERT_TRUE(d.ir[0].has_value());
  EXPECT_EQ(d.ir[0]->x, 512);
  EXPECT_EQ(d.ir[0]->y, 384);
  EXPECT_EQ(d.ir[0]->size, 7);
  EXPECT_EQ(d.ir[0]->x_max, 30);
  EXPECT_EQ(d.ir[0]->intensity, 200);
  EXPECT_FALSE(d.ir[1].has_value());
}

// The empty-slot marker, as wiimote_protocol.hpp documents it: all bits set
// (x = y = 1023), and any y above 767 reads as no dot.
TEST(WiimoteInput, EmptySlotMarker) {
  const auto ext = [](std::uint8_t a, std::uint8_t b, std::uint8_t c) {
    const std::array<std::uint8_t, 3> bytes{a, b, c};
    return decode_ir_extended(bytes);
  };
  EXPECT_FALSE(ext(0xFF, 0xFF, 0xFF));                           // the marker
  EXPECT_FALSE(ext(0x10, 0xFF, 0xC5));                           // x 16, y 1023: no dot either
  EXPECT_FALSE(ext(0x10, 0x00, 0xC5));                           // y 768: outside the image
  const auto last_row = ext(0xFF, 0xFF, 0xB5);                   // x 1023, y 767, size 5: a dot
  ASSERT_TRUE(last_row);
  EXPECT_EQ(last_row->x, 1023);
  EXPECT_EQ(last_row->y, 767);
  EXPECT_EQ(last_row->size, 5);
  // Basic: dot 2 of the pair is the marker (X2 = Y2 = FF, its high bits 11 11).
  const std::array<std::uint8_t, 5> pair{0x64, 0xC8, 0x0F, 0xFF, 0xFF};
  const auto basic = decode_ir_basic(pair);
  ASSERT_TRUE(basic[0]);
  EXPECT_EQ(basic[0]->x, 100);
  EXPECT_EQ(basic[0]->y, 200);
  EXPECT_FALSE(basic[1]);
  // Full: nine FF bytes.
  std::array<std::uint8_t, 9> full{};
  full.fill(0xFF);
  EXPECT_FALSE(decode_ir_full(full));
}

TEST(WiimoteInput, StatusReadReplyAndAck) {
  const auto st = decode(B{0x20, 0x00, 0x00, 0x1A, 0x00, 0x00, 0xC8});
  ASSERT_TRUE(st.has_value());
  const auto& s = std::get<StatusReport>(*st);
  EXPECT_TRUE(s.extension);
  EXPECT_TRUE(s.ir);
  EXPECT_FALSE(s.battery_low);
  EXPECT_EQ(s.leds, 0x1);
  EXPECT_EQ(s.battery, 0xC8);

  B rr{0x21, 0x00, 0x00, 0x60, 0x00, 0x16, 1, 2, 3, 4, 5, 6, 7};
  rr.resize(22, 0);
  const auto rep = std::get<ReadReply>(*decode(rr));
  EXPECT_EQ(rep.size, 7);
  EXPECT_EQ(rep.error, 0);
  EXPECT_EQ(rep.address_low, 0x0016);
  EXPECT_EQ(rep.data[6], 7);

  const auto ack = std::get<Acknowledge>(*decode(B{0x22, 0x00, 0x00, 0x16, 0x00}));
  EXPECT_EQ(ack.report, 0x16);
  EXPECT_EQ(ack.error, 0);
}

TEST(WiimoteInput, MalformedReportsAreDroppedWithAReason) {
  std::string why;
  EXPECT_FALSE(decode(B{}, &why).has_value());
  EXPECT_EQ(why, "empty report");
  EXPECT_FALSE(decode(B{0x33, 0x00, 0x00, 0x80}, &why).has_value());
  EXPECT_NE(why.find("too short"), std::string::npos);
  EXPECT_FALSE(decode(B{0x99, 0x00}, &why).has_value());
  EXPECT_NE(why.find("unknown input report"), std::string::npos);
}

TEST(WiimoteAccel, CalibrationFromEeprom) {
  // zero g: X=0x80<<2|1, Y=0x80<<2|2, Z=0x80<<2|3; one g: +0x19 on each high byte, low bits 0.
  B cal{0x80, 0x80, 0x80, static_cast<std::uint8_t>((1 << 4) | (2 << 2) | 3), 0x99, 0x99, 0x99, 0x00, 0x40};
  unsigned sum = 0x55;
  for (auto v : cal) sum += v;
  cal.push_back(static_cast<std::uint8_t>(sum));
  const auto c = parse_accel_calibration(cal);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->zero[0], 0x201);
  EXPECT_EQ(c->zero[1], 0x202);
  EXPECT_EQ(c->zero[2], 0x203);
  EXPECT_EQ(c->one_g[0], 0x264);
  const auto g = c->apply({0x264, 0x202, static_cast<std::uint16_t>(0x203 - (0x264 - 0x203))});
  EXPECT_DOUBLE_EQ(g[0], 1.0);
  EXPECT_DOUBLE_EQ(g[1], 0.0);
  EXPECT_DOUBLE_EQ(g[2], -1.0);
  cal[9] ^= 0x01;  // bad checksum
  EXPECT_FALSE(parse_accel_calibration(cal).has_value());
}

// The checksum, as wiimote_protocol.hpp documents it: required, at the tenth
// byte, the low byte of 0x55 plus all nine bytes before it (0x1E included).
TEST(WiimoteAccel, ChecksumIsRequiredAndCoversTheNineBytes) {
  B cal{0x82, 0x82, 0x82, 0x15, 0x9C, 0x9C, 0x9E, 0x38, 0x40};  // sums past 0xFF
  unsigned sum = 0x55;
  for (auto v : cal) sum += v;
  ASSERT_GT(sum, 0xFFu);
  EXPECT_EQ(sum & 0xFF, 0x3Eu);  // the block wiibrew shows from a real remote ends in 3E
  EXPECT_FALSE(parse_accel_calibration(cal).has_value()) << "nine bytes: no checksum, no calibration";
  cal.push_back(static_cast<std::uint8_t>(sum));
  const auto c = parse_accel_calibration(cal);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->zero[0], (0x82 << 2) | 0x1);    // --XXYYZZ = 00 01 01 01
  EXPECT_EQ(c->one_g[2], (0x9E << 2) | 0x0);   // --XXYYZZ = 00 11 10 00
  EXPECT_EQ(c->one_g[0], (0x9C << 2) | 0x3);
  B no_seed = cal;
  no_seed[9] = static_cast<std::uint8_t>(sum - 0x55);  // the sum without 0x55
  EXPECT_FALSE(parse_accel_calibration(no_seed).has_value());
  B unused_byte = cal;
  unused_byte[8] ^= 0x01;  // 0x1E is not calibration data but is summed
  EXPECT_FALSE(parse_accel_calibration(unused_byte).has_value());
}
