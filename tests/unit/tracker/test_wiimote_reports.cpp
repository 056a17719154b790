// Byte-exact coverage of the Wii Remote reports the live tracker sends and
// decodes, beyond test_wiimote.cpp: rumble kept in every output report, the
// IR init sequence for every mode and sensitivity, and every data mode
// (buttons, buttons + accelerometer, basic IR with accelerometer, the second
// half of full IR), status flags, read errors and refused writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "earshot/tracker/sources/wiimote_protocol.hpp"

using namespace earshot::tracker::wiimote;

namespace {
using B = std::vector<std::uint8_t>;
B bytes(const OutputReport& r) { return {r.view().begin(), r.view().end()}; }
B write16(std::uint32_t a, B data) {
  B r(22, 0x00);
  const B head{0x16, 0x04, static_cast<std::uint8_t>(a >> 16), static_cast<std::uint8_t>(a >> 8),
               static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(data.size())};
  std::copy(head.begin(), head.end(), r.begin());
  std::copy(data.begin(), data.end(), r.begin() + 6);
  return r;
}
}  // namespace

TEST(WiimoteReports, RumbleBitIsKeptInEveryOutputReport) {
  EXPECT_EQ(bytes(ir_enable(true, true)), (B{0x13, 0x05}));
  EXPECT_EQ(bytes(ir_enable2(false, true)), (B{0x1A, 0x01}));
  EXPECT_EQ(bytes(status_request(true)), (B{0x15, 0x01}));
  EXPECT_EQ(bytes(read_memory(0x0016, 10, false, true)), (B{0x17, 0x01, 0x00, 0x00, 0x16, 0x00, 0x0A}));
  EXPECT_EQ(bytes(set_reporting_mode(0x33, true, true)), (B{0x12, 0x05, 0x33}));
  const std::uint8_t one = 0x01;
  B w = write16(0xB00030, {0x01});
  w[1] |= 0x01;
  EXPECT_EQ(bytes(write_registers(0xB00030, std::span(&one, 1), true)), w);
  EXPECT_EQ(bytes(set_leds(0b1111)), (B{0x11, 0xF0}));
}

TEST(WiimoteReports, InitSequenceForEveryModeAndSensitivity) {
  struct Case {
    IrMode mode;
    IrSensitivity s;
    B block1, block2;
    std::uint8_t mode_byte, report;
  };
  const std::vector<Case> cases{
      {IrMode::basic, IrSensitivity::level1, {0x02, 0x00, 0x00, 0x71, 0x01, 0x00, 0x64, 0x00, 0xfe}, {0xfd, 0x05}, 0x01, 0x37},
      {IrMode::extended, IrSensitivity::level5, {0x07, 0x00, 0x00, 0x71, 0x01, 0x00, 0x72, 0x00, 0x20}, {0x1f, 0x03}, 0x03, 0x33},
      {IrMode::full, IrSensitivity::custom_high, {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x90, 0x00, 0x41}, {0x40, 0x00}, 0x05, 0x3E},
      {IrMode::extended, IrSensitivity::wiiyourself, {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x90, 0x00, 0xc0}, {0x40, 0x00}, 0x03, 0x33},
  };
  for (const auto& c : cases) {
    const auto seq = ir_init_sequence(c.mode, c.s);
    ASSERT_EQ(seq.size(), 8u);
    const std::vector<B> want{{0x13, 0x06}, {0x1A, 0x06}, write16(0xB00030, {0x08}), write16(0xB00000, c.block1),
                              write16(0xB0001A, c.block2), write16(0xB00033, {c.mode_byte}), write16(0xB00030, {0x08}),
                              {0x12, 0x04, c.report}};
    for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(bytes(seq[i]), want[i]) << "report " << i;
  }
}

TEST(WiimoteReports, CoreButtonsAndAccelerometerModes) {
  // 0x30: buttons only (Left + Minus + Two).
  auto r = decode(B{0x30, 0x01, 0x11});
  ASSERT_TRUE(r);
  auto d = std::get<DataReport>(*r);
  EXPECT_EQ(d.buttons, Buttons{Buttons::left | Buttons::minus | Buttons::two});
  EXPECT_FALSE(d.accel);
  EXPECT_FALSE(d.has_ir);
  // 0x31: buttons + accelerometer; the low bits ride in the button bytes.
  r = decode(B{0x31, static_cast<std::uint8_t>(0x10 | (2 << 5)), static_cast<std::uint8_t>(0x80 | (1 << 5) | (1 << 6)), 0x81, 0x7F, 0x9A});
  ASSERT_TRUE(r);
  d = std::get<DataReport>(*r);
  EXPECT_EQ(d.buttons, Buttons{Buttons::plus | Buttons::home});
  ASSERT_TRUE(d.accel);
  EXPECT_EQ(d.accel->x, (0x81 << 2) | 2);
  EXPECT_EQ(d.accel->y, (0x7F << 2) | 2);
  EXPECT_EQ(d.accel->z, (0x9A << 2) | 2);
  EXPECT_FALSE(d.has_ir);
}

TEST(WiimoteReports, BasicIrWithAccelerometer) {
  // 0x37: buttons, accel, 10 basic IR bytes, 6 extension bytes.
  // Dots (100, 200), (300, 400), empty, (1023, 0).
  B r{0x37, 0x00, 0x08, 0x80, 0x80, 0x9A,
      0x64, 0xC8, static_cast<std::uint8_t>((0 << 6) | (0 << 4) | (1 << 2) | 1), 0x2C, 0x90,
      0xFF, 0xFF, static_cast<std::uint8_t>((3 << 6) | (3 << 4) | (0 << 2) | 3), 0xFF, 0x00};
  r.resize(22, 0x00);
  const auto in = decode(r);
  ASSERT_TRUE(in);
  const auto& d = std::get<DataReport>(*in);
  EXPECT_TRUE(d.buttons->pressed(Buttons::a));
  ASSERT_TRUE(d.accel);
  EXPECT_EQ(d.accel->z, 0x9A << 2);
  ASSERT_TRUE(d.ir[0] && d.ir[1] && !d.ir[2] && d.ir[3]);
  EXPECT_EQ(d.ir[0]->x, 100);
  EXPECT_EQ(d.ir[0]->y, 200);
  EXPECT_EQ(d.ir[1]->x, 300);
  EXPECT_EQ(d.ir[1]->y, 400);
  EXPECT_EQ(d.ir[3]->x, 1023);
  EXPECT_EQ(d.ir[3]->y, 0);
}

TEST(WiimoteReports, SecondHalfOfFullIr) {
  B r{0x3F, 0x00, 0x00, 0x00};
  r.insert(r.end(), 9, 0xFF);  // slot 2 empty
  const B dot{0x2C, 0x90, static_cast<std::uint8_t>((1 << 6) | (1 << 4) | 9), 1, 2, 3, 4, 0x00, 77};  // (300, 400)
  r.insert(r.end(), dot.begin(), dot.end());
  const auto in = decode(r);
  ASSERT_TRUE(in);
  const auto& d = std::get<DataReport>(*in);
  EXPECT_EQ(d.ir_first_slot, 2);
  EXPECT_EQ(d.ir_slot_count, 2);
  EXPECT_FALSE(d.ir[2]);
  ASSERT_TRUE(d.ir[3]);
  EXPECT_EQ(d.ir[3]->x, 300);
  EXPECT_EQ(d.ir[3]->y, 400);
  EXPECT_EQ(d.ir[3]->size, 9);
  EXPECT_EQ(d.ir[3]->x_min, 1);
  EXPECT_EQ(d.ir[3]->y_max, 4);
  EXPECT_EQ(d.ir[3]->intensity, 77);
}

// The modes with extension bytes (the kernel's hid-wiimote picks them when an
// extension is in use and nobody wants IR): their core buttons and, in 0x35,
// the accelerometer; 0x3D has extension bytes only.
TEST(WiimoteReports, ExtensionModesYieldTheirButtons) {
  B r32{0x32, 0x00, 0x08, 1, 2, 3, 4, 5, 6, 7, 8};  // A; 8 extension bytes
  auto in = decode(r32);
  ASSERT_TRUE(in);
  auto d = std::get<DataReport>(*in);
  EXPECT_EQ(d.id, 0x32);
  EXPECT_EQ(d.buttons, Buttons{Buttons::a});
  EXPECT_FALSE(d.accel);
  EXPECT_FALSE(d.has_ir);

  B r34{0x34, 0x00, 0x80};  // Home; 19 extension bytes
  r34.resize(22, 0xA5);
  in = decode(r34);
  ASSERT_TRUE(in);
  d = std::get<DataReport>(*in);
  EXPECT_EQ(d.buttons, Buttons{Buttons::home});
  EXPECT_FALSE(d.accel);
  EXPECT_FALSE(d.has_ir);

  // 0x35: Up + B, accelerometer X = 0x81 << 2 | 1, Y = 0x7F << 2 | 2, Z = 0x9A << 2; 16 extension bytes.
  B r35{0x35, static_cast<std::uint8_t>(0x08 | (1 << 5)), static_cast<std::uint8_t>(0x04 | (1 << 5)), 0x81, 0x7F, 0x9A};
  r35.resize(22, 0xFF);
  in = decode(r35);
  ASSERT_TRUE(in);
  d = std::get<DataReport>(*in);
  EXPECT_EQ(d.buttons, Buttons{Buttons::up | Buttons::b});
  ASSERT_TRUE(d.accel);
  EXPECT_EQ(d.accel->x, (0x81 << 2) | 1);
  EXPECT_EQ(d.accel->y, (0x7F << 2) | 2);
  EXPECT_EQ(d.accel->z, 0x9A << 2);
  EXPECT_FALSE(d.has_ir);

  B r3d{0x3D};  // 21 extension bytes, no buttons
  r3d.resize(22, 0x08);
  in = decode(r3d);
  ASSERT_TRUE(in);
  d = std::get<DataReport>(*in);
  EXPECT_EQ(d.id, 0x3D);
  EXPECT_FALSE(d.buttons);
  EXPECT_FALSE(d.accel);
  EXPECT_FALSE(d.has_ir);

  std::string why;  // torn: one byte short each
  EXPECT_FALSE(decode(B(r32.begin(), r32.end() - 1), &why));
  EXPECT_EQ(why, "report 0x32 too short: 10 bytes, need 11");
  EXPECT_FALSE(decode(B(r35.begin(), r35.end() - 1), &why));
  EXPECT_EQ(why, "report 0x35 too short: 21 bytes, need 22");
  EXPECT_FALSE(decode(B(r3d.begin(), r3d.end() - 1), &why));
  EXPECT_EQ(why, "report 0x3D too short: 21 bytes, need 22");
}

TEST(WiimoteReports, StatusFlagsReadErrorsAndRefusedWrites) {
  const auto st = std::get<StatusReport>(*decode(B{0x20, 0x00, 0x08, 0xF5, 0x00, 0x00, 0x20}));
  EXPECT_TRUE(st.battery_low);
  EXPECT_FALSE(st.extension);
  EXPECT_TRUE(st.speaker);
  EXPECT_FALSE(st.ir);
  EXPECT_EQ(st.leds, 0xF);
  EXPECT_EQ(st.battery, 0x20);
  EXPECT_TRUE(st.buttons.pressed(Buttons::a));

  B rr{0x21, 0x00, 0x00, 0x08, 0xFF, 0xFF};  // size 1, error 8: no such address
  rr.resize(22, 0);
  const auto rep = std::get<ReadReply>(*decode(rr));
  EXPECT_EQ(rep.size, 1);
  EXPECT_EQ(rep.error, 8);
  EXPECT_EQ(rep.address_low, 0xFFFF);

  const auto ack = std::get<Acknowledge>(*decode(B{0x22, 0x00, 0x00, 0x16, 0x03}));
  EXPECT_EQ(ack.report, 0x16);
  EXPECT_EQ(ack.error, 0x03);
}
