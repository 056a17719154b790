// A whole Wii Remote session replayed byte for byte through a scripted HID
// transport: connect, calibration read, the IR init sequence (every report
// checked), an IR stream with a malformed report, a disconnect, a failed
// attempt, the reconnect with the same init, and the stream again.
#include <gtest/gtest.h>

#include "earshot/tracker/wiimote_source.hpp"
#include "scripted_hid.hpp"

using namespace earshot::tracker;
using namespace earshot::tracker::testing;

namespace {

using K = Step::Kind;

Bytes write16(std::uint32_t addr, Bytes data) {
  Bytes r{0x16, 0x04, static_cast<std::uint8_t>(addr >> 16), static_cast<std::uint8_t>(addr >> 8),
          static_cast<std::uint8_t>(addr), static_cast<std::uint8_t>(data.size())};
  r.insert(r.end(), data.begin(), data.end());
  r.resize(22, 0x00);
  return r;
}

const Bytes kAck16{0x22, 0x00, 0x00, 0x16, 0x00};

/// Calibration at EEPROM 0x16: zero g 0x200 on every axis, +1 g 0x268.
Bytes calibration_reply() {
  Bytes data{0x80, 0x80, 0x80, 0x00, 0x9A, 0x9A, 0x9A, 0x00, 0x00};
  unsigned sum = 0x55;
  for (auto v : data) sum += v;
  data.push_back(static_cast<std::uint8_t>(sum));
  Bytes r{0x21, 0x00, 0x00, 0x90, 0x00, 0x16};  // size 10, no error, address 0x0016
  r.insert(r.end(), data.begin(), data.end());
  r.resize(22, 0x00);
  return r;
}

/// The connect + init exchange, spelled out report by report.
void add_init(std::deque<Step>& s) {
  s.push_back({K::expect_write, {0x11, 0x10}});                                  // player LED 1
  s.push_back({K::expect_write, {0x17, 0x00, 0x00, 0x00, 0x16, 0x00, 0x0A}});    // read calibration
  s.push_back({K::reply, {0x30, 0x00, 0x00}});                                   // a stray core report first
  s.push_back({K::reply, calibration_reply()});
  s.push_back({K::expect_write, {0x13, 0x04}});  // IR pixel clock
  s.push_back({K::expect_write, {0x1A, 0x04}});  // IR logic
  for (const auto& w : {write16(0xB00030, {0x08}),
                        write16(0xB00000, {0x02, 0x00, 0x00, 0x71, 0x01, 0x00, 0xaa, 0x00, 0x64}),
                        write16(0xB0001A, {0x63, 0x03}), write16(0xB00033, {0x03}), write16(0xB00030, {0x08})}) {
    s.push_back({K::expect_write, w});
    s.push_back({K::reply, kAck16});
  }
  s.push_back({K::expect_write, {0x12, 0x04, 0x33}});  // continuous, buttons + accel + extended IR
}

/// 0x33: buttons, accel (remote face up: +1 g on z), four dots at
/// (100,200) (300,200) (100,400) (300,400).
Bytes ir_report(std::uint8_t buttons_hi = 0x00) {
  return {0x33, 0x00, buttons_hi, 0x80, 0x80, 0x9A,
          0x64, 0xC8, 0x02, 0x2C, 0xC8, 0x12, 0x64, 0x90, 0x42, 0x2C, 0x90, 0x52};
}

struct FakeClock {
  double t = 0.0;
  double operator()() { return t += 0.001; }
};

WiimoteOptions options(FakeClock& clock) {
  WiimoteOptions o;
  o.retry_s = 0.0;
  o.clock = [&clock] { return clock(); };
  return o;
}

}  // namespace

TEST(WiimoteSession, ReplaysAWholeSessionByteForByte) {
  std::deque<Step> s;
  add_init(s);
  s.push_back({K::reply, ir_report()});
  s.push_back({K::reply, {0x33, 0x00}});  // malformed: too short
  s.push_back({K::reply, ir_report(0x08)});  // button A held
  s.push_back({K::gone, {}});
  s.push_back({K::absent_once, {}});
  s.push_back({K::plug, {}});
  add_init(s);
  s.push_back({K::reply, ir_report()});
  auto hid = std::make_unique<ScriptedHid>(s);
  ScriptedHid& fake = *hid;
  FakeClock clock;
  WiimoteSource src(std::move(hid), options(clock));
  const auto wait = std::chrono::milliseconds(10);

  auto e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::connected) << std::get<SourceNote>(e).message;
  EXPECT_TRUE(src.connected());
  EXPECT_DOUBLE_EQ(src.calibration().zero[2], 512.0);
  EXPECT_DOUBLE_EQ(src.calibration().one_g[2], 616.0);

  e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e));
  const auto& f = std::get<CameraFrame>(e);
  ASSERT_EQ(f.dots.visible(), 4);
  EXPECT_EQ(*f.dots.slots[0], Vec2(100, 200));
  EXPECT_EQ(*f.dots.slots[1], Vec2(300, 200));
  EXPECT_EQ(*f.dots.slots[2], Vec2(100, 400));
  EXPECT_EQ(*f.dots.slots[3], Vec2(300, 400));
  ASSERT_TRUE(f.accel_g.has_value());
  // Face up, the remote reads +1 g out of its face: camera "up" is -y.
  EXPECT_NEAR(f.accel_g->x(), 0.0, 1e-12);
  EXPECT_NEAR(f.accel_g->y(), -1.0, 1e-12);
  EXPECT_NEAR(f.accel_g->z(), 0.0, 1e-12);
  EXPECT_EQ(f.buttons, 0);

  e = src.next(wait);  // the malformed report: dropped, counted
  EXPECT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_EQ(src.dropped(), 1u);

  e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e));
  EXPECT_EQ(std::get<CameraFrame>(e).buttons, 0x0800);  // A

  e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::disconnected);
  EXPECT_FALSE(src.connected());

  e = src.next(wait);  // nobody on the bus yet: keep waiting, no exception
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::timeout);

  e = src.next(wait);  // back: the same init again
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::connected);

  e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e));
  EXPECT_EQ(std::get<CameraFrame>(e).dots.visible(), 4);

  EXPECT_EQ(fake.remaining(), 0u);
  EXPECT_EQ(fake.opens, 2);
  EXPECT_EQ(fake.written.size(), 2u * 10u);
  for (const auto& err : fake.errors) ADD_FAILURE() << err;
}

TEST(WiimoteSession, NoRemoteFailsAtOnceWithHowToPair) {
  std::deque<Step> s{{K::absent_once, {}}};
  FakeClock clock;
  WiimoteSource src(std::make_unique<ScriptedHid>(s), options(clock));
  try {
    (void)src.next(std::chrono::milliseconds(10));
    FAIL() << "expected WiimoteError";
  } catch (const WiimoteError& e) {
    EXPECT_NE(std::string(e.what()).find("bluetoothctl"), std::string::npos) << e.what();
  }
}

// Waiting for the remote (the plugin's way): no remote is a searching note
// with how to pair one, on every attempt, and the remote is taken when it
// appears.
TEST(WiimoteSession, WaitingForTheRemoteSaysHowToPairAndKeepsLooking) {
  std::deque<Step> s{{K::absent_once, {}}, {K::absent_once, {}}};
  add_init(s);
  s.push_back({K::reply, ir_report()});
  auto hid = std::make_unique<ScriptedHid>(s);
  ScriptedHid& fake = *hid;
  FakeClock clock;
  WiimoteOptions o = options(clock);
  o.wait_for_remote = true;
  WiimoteSource src(std::move(hid), o);
  for (int attempt = 0; attempt < 2; ++attempt) {
    const auto e = src.next(std::chrono::milliseconds(10));
    ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
    const auto& n = std::get<SourceNote>(e);
    EXPECT_EQ(n.kind, SourceNote::Kind::searching);
    EXPECT_NE(n.message.find("no Wii Remote found"), std::string::npos) << n.message;
    EXPECT_NE(n.message.find("bluetoothctl"), std::string::npos) << n.message;
  }
  auto e = src.next(std::chrono::milliseconds(10));
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::connected);
  e = src.next(std::chrono::milliseconds(10));
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e));
  const auto& f = std::get<CameraFrame>(e);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(f.dot_size[i], 2) << "slot " << i;  // extended format sizes
  EXPECT_EQ(fake.enumerations, 3);
  for (const auto& err : fake.errors) ADD_FAILURE() << err;
}

TEST(WiimoteSession, PermissionDeniedNamesTheUdevRule) {
  auto hid = std::make_unique<ScriptedHid>(std::deque<Step>{});
  hid->open_error = HidOpenError(HidOpenError::Reason::permission_denied,
                                 "permission denied opening /dev/hidraw7: install the udev rule ...");
  FakeClock clock;
  WiimoteSource src(std::move(hid), options(clock));
  try {
    (void)src.next(std::chrono::milliseconds(10));
    FAIL() << "expected WiimoteError";
  } catch (const WiimoteError& e) {
    EXPECT_NE(std::string(e.what()).find("udev"), std::string::npos) << e.what();
  }
}

TEST(WiimoteSession, KernelDriverBoundIsWarnedAbout) {
  std::deque<Step> s;
  add_init(s);
  FakeClock clock;
  auto hid = std::make_unique<ScriptedHid>(s, HidDeviceInfo{"/dev/hidraw7", 0x057E, 0x0330, "Nintendo RVL-CNT-01-TR", "wiimote"});
  WiimoteSource src(std::move(hid), options(clock));
  const auto e = src.next(std::chrono::milliseconds(10));
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_NE(std::get<SourceNote>(e).message.find("hid-wiimote"), std::string::npos);
}

TEST(WiimoteSession, AMissingAcknowledgementFailsTheFirstConnectClearly) {
  std::deque<Step> s;
  add_init(s);
  // Drop the first register write's acknowledgement.
  for (auto it = s.begin(); it != s.end(); ++it)
    if (it->kind == K::reply && it->bytes == kAck16) {
      s.erase(it);
      break;
    }
  FakeClock clock;
  WiimoteSource src(std::make_unique<ScriptedHid>(s), options(clock));
  EXPECT_THROW((void)src.next(std::chrono::milliseconds(10)), WiimoteError);
}

TEST(WiimoteSession, WiiUProControllerIsNotTakenForARemote) {
  FakeClock clock;
  auto hid = std::make_unique<ScriptedHid>(std::deque<Step>{},
                                           HidDeviceInfo{"/dev/hidraw7", 0x057E, 0x0330, "Nintendo RVL-CNT-01-UC", ""});
  WiimoteSource src(std::move(hid), options(clock));
  EXPECT_THROW((void)src.next(std::chrono::milliseconds(10)), WiimoteError);
}
