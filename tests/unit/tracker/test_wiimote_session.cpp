// A whole Wii Remote session replayed byte for byte through a scripted HID
// transport: connect, calibration read, the IR init sequence (every report
// checked), an IR stream with a malformed report, a disconnect, a failed
// attempt, the reconnect with the same init, and the stream again. Then the
// acknowledgements of the IR enables (lost, lost twice, refused), the full
// IR format's halves (lost 0x3E, lost 0x3F, a torn report between), and the
// modes without IR the kernel driver may choose (buttons still arrive).
#include <gtest/gtest.h>

#include <algorithm>

#include "earshot/tracker/sources/wiimote_source.hpp"
#include "scripted_hid.hpp"

using namespace earshot::tracker;
using namespace earshot::tracker::testing;

namespace {

using K = Step::Kind;

Bytes write16(std::uint32_t addr, Bytes data) {
  Bytes r(22, 0x00);
  const Bytes head{0x16, 0x04, static_cast<std::uint8_t>(addr >> 16), static_cast<std::uint8_t>(addr >> 8),
                   static_cast<std::uint8_t>(addr), static_cast<std::uint8_t>(data.size())};
  std::copy(head.begin(), head.end(), r.begin());
  std::copy(data.begin(), data.end(), r.begin() + 6);
  return r;
}

Bytes ack(std::uint8_t report, std::uint8_t error = 0x00) { return {0x22, 0x00, 0x00, report, error}; }
const Bytes kAck16 = ack(0x16);

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

/// The connect + init exchange, spelled out report by report: extended IR
/// (mode 3, report 0x33) unless told otherwise.
void add_init(std::deque<Step>& s, std::uint8_t ir_mode = 0x03, std::uint8_t report = 0x33) {
  s.push_back({K::expect_write, {0x11, 0x10}});                                  // player LED 1
  s.push_back({K::expect_write, {0x17, 0x00, 0x00, 0x00, 0x16, 0x00, 0x0A}});    // read calibration
  s.push_back({K::reply, {0x30, 0x00, 0x00}});                                   // a stray core report first
  s.push_back({K::reply, calibration_reply()});
  s.push_back({K::expect_write, {0x13, 0x06}});  // IR pixel clock, acknowledgement requested
  s.push_back({K::reply, ack(0x13)});
  s.push_back({K::expect_write, {0x1A, 0x06}});  // IR logic, acknowledgement requested
  s.push_back({K::reply, ack(0x1A)});
  for (const auto& w : {write16(0xB00030, {0x08}),
                        write16(0xB00000, {0x02, 0x00, 0x00, 0x71, 0x01, 0x00, 0xaa, 0x00, 0x64}),
                        write16(0xB0001A, {0x63, 0x03}), write16(0xB00033, {ir_mode}), write16(0xB00030, {0x08})}) {
    s.push_back({K::expect_write, w});
    s.push_back({K::reply, kAck16});
  }
  s.push_back({K::expect_write, {0x12, 0x04, report}});  // continuous (0x33: buttons + accel + extended IR)
}

/// The first step of `s` of this kind with these bytes (end() when none).
std::deque<Step>::iterator find_step(std::deque<Step>& s, K kind, const Bytes& bytes) {
  return std::find_if(s.begin(), s.end(), [&](const Step& x) { return x.kind == kind && x.bytes == bytes; });
}

/// The init script up to the acknowledgement `reply`, which never comes: the
/// write goes out once more (`resent`) and the script ends there.
std::deque<Step> init_left_unanswered(const Bytes& reply, const Bytes& resent) {
  std::deque<Step> s;
  add_init(s);
  const auto at = s.insert(s.erase(find_step(s, K::reply, reply)), {K::expect_write, resent});
  s.erase(std::next(at), s.end());
  return s;
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

WiimoteOptions options(FakeClock& clock, earshot::tracker::wiimote::IrMode mode = earshot::tracker::wiimote::IrMode::extended) {
  WiimoteOptions o;
  o.mode = mode;
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

/// The WiimoteError of the first connect attempt ("" when none was thrown).
std::string first_connect_error(WiimoteSource& src) {
  try {
    (void)src.next(std::chrono::milliseconds(10));
  } catch (const WiimoteError& e) {
    return e.what();
  }
  return "";
}

// A register write whose acknowledgement never comes is sent once more,
// then the connect fails naming it.
TEST(WiimoteSession, ARegisterWriteNeverAcknowledgedFailsNamingIt) {
  // After B00030 = 08 no acknowledgement; the second attempt is not answered either.
  std::deque<Step> s = init_left_unanswered(kAck16, write16(0xB00030, {0x08}));
  auto hid = std::make_unique<ScriptedHid>(s);
  ScriptedHid& fake = *hid;
  FakeClock clock;
  WiimoteSource src(std::move(hid), options(clock));
  const std::string error = first_connect_error(src);
  EXPECT_NE(error.find("no acknowledgement of output report 0x16 (write of 1 byte to register 0xB00030) after 2 attempts"),
            std::string::npos) << error;
  EXPECT_EQ(fake.remaining(), 0u);
  for (const auto& err : fake.errors) ADD_FAILURE() << err;
}

// The IR enables ask for an acknowledgement and wait for it: one that never
// comes is sent again, then the connect fails naming the report.
TEST(WiimoteSession, AnIrEnableNeverAcknowledgedIsSentTwiceThenFails) {
  std::deque<Step> s = init_left_unanswered(ack(0x13), {0x13, 0x06});  // the remote stays silent twice
  auto hid = std::make_unique<ScriptedHid>(s);
  ScriptedHid& fake = *hid;
  FakeClock clock;
  WiimoteSource src(std::move(hid), options(clock));
  const std::string error = first_connect_error(src);
  EXPECT_NE(error.find("no acknowledgement of output report 0x13 (IR pixel clock enable) after 2 attempts"),
            std::string::npos) << error;
  ASSERT_EQ(fake.written.size(), 4u);  // LED, calibration read, 13 06, 13 06: nothing after
  EXPECT_EQ(fake.written[2], (Bytes{0x13, 0x06}));
  EXPECT_EQ(fake.written[3], (Bytes{0x13, 0x06}));
  EXPECT_EQ(fake.remaining(), 0u);
  for (const auto& err : fake.errors) ADD_FAILURE() << err;
}

// One lost acknowledgement of an IR enable costs one more write, no more.
TEST(WiimoteSession, ALostIrEnableAcknowledgementIsRecoveredBySendingAgain) {
  std::deque<Step> s;
  add_init(s);
  s.insert(find_step(s, K::reply, ack(0x1A)), {K::expect_write, {0x1A, 0x06}});  // first 1A 06 unanswered
  s.push_back({K::reply, ir_report()});
  auto hid = std::make_unique<ScriptedHid>(s);
  ScriptedHid& fake = *hid;
  FakeClock clock;
  WiimoteSource src(std::move(hid), options(clock));
  auto e = src.next(std::chrono::milliseconds(10));
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::connected) << std::get<SourceNote>(e).message;
  e = src.next(std::chrono::milliseconds(10));
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e));
  EXPECT_EQ(std::get<CameraFrame>(e).dots.visible(), 4);
  EXPECT_EQ(fake.written.size(), 11u);
  EXPECT_EQ(fake.remaining(), 0u);
  for (const auto& err : fake.errors) ADD_FAILURE() << err;
}

// An acknowledgement with an error code fails the connect at once (no retry).
TEST(WiimoteSession, AnIrEnableRefusedWithAnErrorCodeFailsAtOnce) {
  std::deque<Step> s;
  add_init(s);
  auto at = find_step(s, K::reply, ack(0x13));
  *at = {K::reply, ack(0x13, 0x03)};
  s.erase(std::next(at), s.end());
  auto hid = std::make_unique<ScriptedHid>(s);
  ScriptedHid& fake = *hid;
  FakeClock clock;
  WiimoteSource src(std::move(hid), options(clock));
  const std::string error = first_connect_error(src);
  EXPECT_NE(error.find("output report 0x13 (IR pixel clock enable) refused with error code 3"), std::string::npos)
      << error;
  EXPECT_EQ(fake.written.size(), 3u);
  EXPECT_EQ(fake.remaining(), 0u);
  for (const auto& err : fake.errors) ADD_FAILURE() << err;
}

TEST(WiimoteSession, WiiUProControllerIsNotTakenForARemote) {
  FakeClock clock;
  auto hid = std::make_unique<ScriptedHid>(std::deque<Step>{},
                                           HidDeviceInfo{"/dev/hidraw7", 0x057E, 0x0330, "Nintendo RVL-CNT-01-UC", ""});
  WiimoteSource src(std::move(hid), options(clock));
  EXPECT_THROW((void)src.next(std::chrono::milliseconds(10)), WiimoteError);
}

namespace {

/// One dot in the full format: extended bytes, bounding box, 0, intensity.
Bytes full_dot(int x, int y, int size) {
  return {static_cast<std::uint8_t>(x & 0xFF), static_cast<std::uint8_t>(y & 0xFF),
          static_cast<std::uint8_t>(((y >> 8) << 6) | ((x >> 8) << 4) | size), 1, 2, 3, 4, 0x00, 99};
}

/// 0x3E (slots 0-1) or 0x3F (slots 2-3): buttons, an accelerometer byte, two full dots.
Bytes full_half(std::uint8_t id, Bytes dot_a, Bytes dot_b, std::uint8_t buttons_hi = 0x00) {
  Bytes r(22, 0x00);
  r[0] = id;
  r[2] = buttons_hi;
  r[3] = 0x80;
  std::copy(dot_a.begin(), dot_a.end(), r.begin() + 4);
  std::copy(dot_b.begin(), dot_b.end(), r.begin() + 13);
  return r;
}

/// Frame k of a full-format stream: its four dots sit 10k pixels right of
/// (100,200) (300,200) (100,400) (300,400), so a stale half shows.
Bytes first_half(int k) {
  const int dx = 10 * k;
  return full_half(0x3E, full_dot(100 + dx, 200, 3), full_dot(300 + dx, 200, 4));
}
Bytes second_half(int k) {
  const int dx = 10 * k;
  return full_half(0x3F, full_dot(100 + dx, 400, 5), full_dot(300 + dx, 400, 6));
}

void expect_frame(const SourceEvent& e, int k) {
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e)) << "frame " << k;
  const auto& f = std::get<CameraFrame>(e);
  const double dx = 10.0 * k;
  ASSERT_EQ(f.dots.visible(), 4) << "frame " << k;
  EXPECT_EQ(*f.dots.slots[0], Vec2(100 + dx, 200)) << "frame " << k;
  EXPECT_EQ(*f.dots.slots[1], Vec2(300 + dx, 200)) << "frame " << k;
  EXPECT_EQ(*f.dots.slots[2], Vec2(100 + dx, 400)) << "frame " << k;
  EXPECT_EQ(*f.dots.slots[3], Vec2(300 + dx, 400)) << "frame " << k;
  EXPECT_EQ(f.dot_size, (std::array<int, kSlots>{3, 4, 5, 6})) << "frame " << k;
}

void expect_nothing(const SourceEvent& e, const char* what) {
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e)) << what << ": expected no frame";
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::timeout) << what;
}

}  // namespace

// Full IR comes as 0x3E (slots 0-1) then 0x3F (slots 2-3). A frame is a
// 0x3E and the report right after it; a 0x3F whose 0x3E was lost must not
// take slots 0-1 from an older frame, and a 0x3E whose 0x3F was lost is
// replaced by the next one.
TEST(WiimoteSession, FullIrHalvesPairOnlyWithTheReportRightAfter) {
  std::deque<Step> s;
  add_init(s, 0x05, 0x3E);
  s.push_back({K::reply, first_half(0)});
  s.push_back({K::reply, second_half(0)});  // frame 0
  s.push_back({K::reply, second_half(1)});  // frame 1's 0x3E was lost: nothing
  s.push_back({K::reply, first_half(2)});
  s.push_back({K::reply, second_half(2)});  // frame 2
  s.push_back({K::reply, first_half(3)});   // frame 3's 0x3F was lost ...
  s.push_back({K::reply, first_half(4)});   // ... so this 0x3E replaces it
  s.push_back({K::reply, second_half(4)});  // frame 4
  s.push_back({K::reply, first_half(5)});
  s.push_back({K::reply, {0x3F, 0x00, 0x00}});  // torn (malformed): the half goes with it
  s.push_back({K::reply, second_half(5)});  // nothing
  s.push_back({K::reply, first_half(6)});
  s.push_back({K::reply, second_half(6)});  // frame 6
  auto hid = std::make_unique<ScriptedHid>(s);
  ScriptedHid& fake = *hid;
  FakeClock clock;
  WiimoteSource src(std::move(hid), options(clock, earshot::tracker::wiimote::IrMode::full));
  const auto wait = std::chrono::milliseconds(10);
  auto e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  ASSERT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::connected) << std::get<SourceNote>(e).message;

  expect_nothing(src.next(wait), "0x3E of frame 0");
  expect_frame(src.next(wait), 0);
  expect_nothing(src.next(wait), "0x3F of frame 1 without its 0x3E");
  expect_nothing(src.next(wait), "0x3E of frame 2");
  expect_frame(src.next(wait), 2);
  expect_nothing(src.next(wait), "0x3E of frame 3");
  expect_nothing(src.next(wait), "0x3E of frame 4");
  expect_frame(src.next(wait), 4);
  expect_nothing(src.next(wait), "0x3E of frame 5");
  expect_nothing(src.next(wait), "a torn report");
  expect_nothing(src.next(wait), "0x3F of frame 5 after a torn report");
  expect_nothing(src.next(wait), "0x3E of frame 6");
  expect_frame(src.next(wait), 6);
  EXPECT_EQ(src.dropped(), 1u);  // the torn report; lost halves are not malformed
  EXPECT_EQ(fake.remaining(), 0u);
  for (const auto& err : fake.errors) ADD_FAILURE() << err;
}

// The kernel's hid-wiimote may switch the remote to a mode without IR
// (0x32, 0x34, 0x35 with an extension; 0x30, 0x31 without): the buttons still
// arrive, in frames with no dots, so A/Home recenter keeps working. 0x3D has
// no buttons and gives nothing.
TEST(WiimoteSession, ModesWithoutIrStillDeliverTheButtons) {
  std::deque<Step> s;
  add_init(s);
  Bytes r35{0x35, 0x00, 0x08, 0x80, 0x80, 0x9A};  // A, face up
  r35.resize(22, 0xFF);
  Bytes r34{0x34, 0x00, 0x80};  // Home
  r34.resize(22, 0xFF);
  Bytes r3d{0x3D};
  r3d.resize(22, 0x08);  // extension bytes that would read as A if taken for buttons
  s.push_back({K::reply, r35});
  s.push_back({K::reply, {0x32, 0x00, 0x00, 0, 0, 0, 0, 0, 0, 0, 0}});  // nothing pressed
  s.push_back({K::reply, r34});
  s.push_back({K::reply, r3d});
  s.push_back({K::reply, {0x30, 0x10, 0x00}});  // Plus
  auto hid = std::make_unique<ScriptedHid>(s);
  ScriptedHid& fake = *hid;
  FakeClock clock;
  WiimoteSource src(std::move(hid), options(clock));
  const auto wait = std::chrono::milliseconds(10);
  ASSERT_TRUE(std::holds_alternative<SourceNote>(src.next(wait)));

  auto e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e)) << "0x35";
  EXPECT_EQ(std::get<CameraFrame>(e).buttons, 0x0800);
  EXPECT_EQ(std::get<CameraFrame>(e).dots.visible(), 0);
  ASSERT_TRUE(std::get<CameraFrame>(e).accel_g.has_value());
  EXPECT_NEAR(std::get<CameraFrame>(e).accel_g->y(), -1.0, 1e-12);
  e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e)) << "0x32";
  EXPECT_EQ(std::get<CameraFrame>(e).buttons, 0);
  EXPECT_FALSE(std::get<CameraFrame>(e).accel_g.has_value());
  e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e)) << "0x34";
  EXPECT_EQ(std::get<CameraFrame>(e).buttons, 0x8000);
  EXPECT_EQ(std::get<CameraFrame>(e).dots.visible(), 0);
  expect_nothing(src.next(wait), "0x3D");
  e = src.next(wait);
  ASSERT_TRUE(std::holds_alternative<CameraFrame>(e)) << "0x30";
  EXPECT_EQ(std::get<CameraFrame>(e).buttons, 0x0010);
  EXPECT_EQ(src.dropped(), 0u);  // none of these is malformed
  EXPECT_EQ(fake.remaining(), 0u);
  for (const auto& err : fake.errors) ADD_FAILURE() << err;
}
