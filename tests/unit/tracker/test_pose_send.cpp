// Pose output (tracker/send): the send spec, each format as its receiver
// reads it (our own OSC and opentrack inputs over 127.0.0.1, and liblo's
// oscdump as an outside receiver), with the sign of every axis checked both
// ways, and the rate cap on a clock the test drives (no timing asserted).
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "earshot/errors.hpp"
#include "earshot/tracker/send/pose_sender.hpp"
#include "earshot/tracker/send/send_spec.hpp"
#include "earshot/tracker/sources/opentrack_packet.hpp"
#include "earshot/tracker/sources/osc_pose.hpp"
#include "earshot/tracker/sources/udp_pose_source.hpp"

extern char** environ;

using namespace earshot::tracker;
using earshot::HeadPose;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
using Clock = PoseSender::Clock;

std::string error_of(std::string_view spec) {
  try {
    (void)parse_send_spec(spec, "--send");
  } catch (const earshot::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "'" << spec << "' parsed";
  return {};
}

HeadPose head(double x, double y, double z, double yaw, double pitch, double roll) {
  HeadPose h;
  h.position = {x, y, z};
  h.orientation = earshot::quat_from_ypr(yaw * kDeg, pitch * kDeg, roll * kDeg);
  h.state = earshot::PoseState::tracking;
  return h;
}

/// The poses one offer gets through to `receiver` (our own decoder): the last one.
std::optional<HeadPose> through(UdpPoseSource& receiver, const SendSpec& spec, const HeadPose& h) {
  PoseSender s(spec);
  s.offer(h, Clock::now());
  EXPECT_EQ(s.counters().sent, 1u) << spec.text;
  std::optional<HeadPose> last;
  // Every datagram of the format (SPARTA's two), each within a bounded wait.
  for (int i = 0; i < 20; ++i) {
    const SourceEvent e = receiver.next(std::chrono::milliseconds(i == 0 ? 2000 : 20));
    if (const auto* p = std::get_if<HeadPose>(&e)) last = *p;
    else if (last) break;
  }
  EXPECT_EQ(receiver.dropped(), 0u) << receiver.last_error();
  return last;
}

struct AxisCase {
  const char* name;
  HeadPose pose;
};

/// One head per axis and sign, and one with everything at once.
std::vector<AxisCase> axis_cases() {
  return {{"x +0.1 m (right)", head(0.1, 0, 0, 0, 0, 0)},    {"y +0.1 m (up)", head(0, 0.1, 0, 0, 0, 0)},
          {"z +0.1 m (back)", head(0, 0, 0.1, 0, 0, 0)},     {"yaw +30 (left)", head(0, 0, 0, 30, 0, 0)},
          {"yaw -30 (right)", head(0, 0, 0, -30, 0, 0)},     {"pitch +20 (up)", head(0, 0, 0, 0, 20, 0)},
          {"pitch -20 (down)", head(0, 0, 0, 0, -20, 0)},    {"roll +15 (right shoulder)", head(0, 0, 0, 0, 0, 15)},
          {"roll -15 (left shoulder)", head(0, 0, 0, 0, 0, -15)},
          {"all", head(-0.05, 0.03, 0.12, 50, -25, 10)}};
}

}  // namespace

// ---- The spec ----------------------------------------------------------------

TEST(SendSpec, KindHostPortFormatAndRate) {
  SendSpec s = parse_send_spec("osc");
  EXPECT_EQ(s.kind, SendSpec::Kind::osc);
  EXPECT_EQ(s.host, "127.0.0.1") << "loopback unless a host is named";
  EXPECT_EQ(s.port, 9000);
  EXPECT_EQ(s.format, SendSpec::Format::earshot);
  EXPECT_EQ(s.rate_hz, 100.0);
  s = parse_send_spec("osc:9001,format=sparta");
  EXPECT_EQ(s.port, 9001);
  EXPECT_EQ(s.host, "127.0.0.1");
  EXPECT_EQ(s.format, SendSpec::Format::sparta);
  s = parse_send_spec("osc:192.168.1.5:8000,format=iem,rate=50");
  EXPECT_EQ(s.host, "192.168.1.5");
  EXPECT_EQ(s.port, 8000);
  EXPECT_EQ(s.format, SendSpec::Format::iem);
  EXPECT_EQ(s.rate_hz, 50.0);
  s = parse_send_spec("osc:studio-mac.local,format=iem-ypr");
  EXPECT_EQ(s.host, "studio-mac.local");
  EXPECT_EQ(s.port, 9000);
  EXPECT_EQ(s.format, SendSpec::Format::iem_ypr);
  s = parse_send_spec("opentrack");
  EXPECT_EQ(s.kind, SendSpec::Kind::opentrack);
  EXPECT_EQ(s.port, 4242);
  s = parse_send_spec("opentrack:127.0.0.1:4243,rate=250");
  EXPECT_EQ(s.port, 4243);
  EXPECT_EQ(s.rate_hz, 250.0);
  EXPECT_EQ(s.text, "opentrack:127.0.0.1:4243,rate=250");
}

TEST(SendSpec, BadSpecsNameTheFieldAndTheSpec) {
  EXPECT_EQ(error_of("osc:70000"), "--send: send 'osc:70000': bad UDP port '70000' (1-65535)");
  EXPECT_EQ(error_of("osc,format=spatial"),
            "--send: send 'osc,format=spatial': unknown format 'spatial' (earshot, sparta, iem, iem-ypr)");
  EXPECT_EQ(error_of("opentrack,format=iem"),
            "--send: send 'opentrack,format=iem': format= is for osc (opentrack has one packet format)");
  EXPECT_NE(error_of("midi:1").find("unknown send 'midi:1' (osc[:HOST][:PORT]"), std::string::npos);
  EXPECT_NE(error_of("osc:host name:9000").find("bad host 'host name'"), std::string::npos);
  EXPECT_NE(error_of("osc:::1:9000").find("too many ':'"), std::string::npos);
  EXPECT_NE(error_of("osc:1.2.3.4:"), "");
  EXPECT_NE(error_of("osc,rate=0").find("bad rate '0' (poses per second, 1-1000)"), std::string::npos);
  EXPECT_NE(error_of("osc,rate=fast").find("bad rate"), std::string::npos);
  EXPECT_NE(error_of("osc,rate=100,rate=50").find("rate given twice"), std::string::npos);
  EXPECT_NE(error_of("osc,").find("empty option"), std::string::npos);
  EXPECT_NE(error_of("osc,format").find("needs a value"), std::string::npos);
  EXPECT_NE(error_of("osc,colour=red").find("unknown option 'colour' (format, rate)"), std::string::npos);
  EXPECT_NE(error_of("").find("unknown send ''"), std::string::npos);
}

TEST(SendSpec, ListsAreSeparatedBySemicolons) {
  const auto list = parse_send_list(" osc:9001,format=sparta ; opentrack;;", "send");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].format, SendSpec::Format::sparta);
  EXPECT_EQ(list[1].kind, SendSpec::Kind::opentrack);
  EXPECT_EQ(send_list_text(list), "osc:9001,format=sparta;opentrack");
  EXPECT_TRUE(parse_send_list("", "send").empty());
  try {
    (void)parse_send_list("osc;bogus", "send");
    ADD_FAILURE() << "parsed";
  } catch (const earshot::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("send: unknown send 'bogus'"), std::string::npos) << e.what();
  }
}

TEST(PoseSender, AHostThatDoesNotResolveIsAnErrorNamingTheSpec) {
  try {
    PoseSender s(parse_send_spec("osc:no-such-host.invalid:9000"));
    ADD_FAILURE() << "opened";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("send 'osc:no-such-host.invalid:9000': cannot resolve host 'no-such-host.invalid'"),
              std::string::npos)
        << e.what();
  }
}

// ---- Each format into our own inputs: the head comes back ------------------------

// Every format, every axis and sign: what we send, our own input (OSC's
// SPARTA, SceneRotator and Earshot addresses; opentrack's packet) reads back
// as the same head. The inputs' signs are checked against each sender's
// convention in test_osc_conventions.cpp and test_pose_inputs.cpp, so a sign
// wrong here is wrong on the wire.
TEST(PoseSend, EveryFormatReachesOurOwnInputWithEverySign) {
  UdpPoseSource osc("osc", 0, std::string("127.0.0.1"), OscPoseDecoder::packet_decoder());
  UdpPoseSource ot("opentrack", 0, std::string("127.0.0.1"), decode_opentrack);
  const std::string o = std::to_string(osc.port());
  struct Format {
    std::string spec;
    bool position;  // the format carries the position
  };
  for (const Format& f : std::vector<Format>{{"osc:" + o + ",format=earshot", true},
                                             {"osc:" + o + ",format=sparta", true},
                                             {"osc:" + o + ",format=iem", false},
                                             {"osc:" + o + ",format=iem-ypr", false},
                                             {"opentrack:127.0.0.1:" + std::to_string(ot.port()), true}}) {
    const SendSpec spec = parse_send_spec(f.spec);
    UdpPoseSource& rx = spec.kind == SendSpec::Kind::osc ? osc : ot;
    for (const AxisCase& c : axis_cases()) {
      const auto got = through(rx, spec, c.pose);
      ASSERT_TRUE(got) << f.spec << ", " << c.name << ": nothing received; " << rx.last_error();
      EXPECT_NEAR(to_eigen(got->orientation).angularDistance(to_eigen(c.pose.orientation)), 0.0, 2e-6)
          << f.spec << ", " << c.name;
      const Vec3 want = f.position ? to_eigen(c.pose.position) : Vec3::Zero();
      EXPECT_LT((to_eigen(got->position) - want).norm(), 1e-6) << f.spec << ", " << c.name << ": position "
                                                               << to_eigen(got->position).transpose();
    }
  }
}

// The numbers on the wire, one axis at a time, in each receiver's own
// convention (the other direction of the check above).
TEST(PoseSend, TheWireCarriesEachReceiversSigns) {
  auto floats_of = [](const std::vector<std::uint8_t>& bytes, std::size_t n) {
    std::vector<float> v;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t at = bytes.size() - 4 * (n - i);
      const std::uint32_t u = (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
                              (std::uint32_t{bytes[at + 2]} << 8) | std::uint32_t{bytes[at + 3]};
      v.push_back(std::bit_cast<float>(u));
    }
    return v;
  };
  const SendSpec sparta = parse_send_spec("osc,format=sparta"), iem = parse_send_spec("osc,format=iem-ypr"),
                 ot = parse_send_spec("opentrack");
  struct Want {
    HeadPose pose;
    std::array<float, 3> sparta_xyz, sparta_ypr, iem_ypr;
    std::array<double, 6> opentrack;  // x y z yaw pitch roll
  };
  const std::vector<Want> wants{
      // Earshot yaw +30 (left): SPARTA yaw +30; the scene turns right: SceneRotator yaw -30; opentrack yaw -30 (right +).
      {head(0, 0, 0, 30, 0, 0), {0, 0, 0}, {30, 0, 0}, {-30, 0, 0}, {0, 0, 0, -30, 0, 0}},
      // pitch +20 (up): SPARTA's right-hand rule about y (left) nods down: -20; SceneRotator +20; opentrack +20.
      {head(0, 0, 0, 0, 20, 0), {0, 0, 0}, {0, -20, 0}, {0, 20, 0}, {0, 0, 0, 0, 20, 0}},
      // roll +15 (right shoulder): SPARTA +15; SceneRotator -15; opentrack -15 (left +).
      {head(0, 0, 0, 0, 0, 15), {0, 0, 0}, {0, 0, 15}, {0, 0, -15}, {0, 0, 0, 0, 0, -15}},
      // x +0.1 m (right): SAF y (left) -0.1; opentrack x (left +) -10 cm.
      {head(0.1, 0, 0, 0, 0, 0), {0, -0.1f, 0}, {0, 0, 0}, {0, 0, 0}, {-10, 0, 0, 0, 0, 0}},
      // y +0.1 m (up): SAF z +0.1; opentrack y +10 cm.
      {head(0, 0.1, 0, 0, 0, 0), {0, 0, 0.1f}, {0, 0, 0}, {0, 0, 0}, {0, 10, 0, 0, 0, 0}},
      // z +0.1 m (back): SAF x (ahead) -0.1; opentrack z (back +) +10 cm.
      {head(0, 0, 0.1, 0, 0, 0), {-0.1f, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 10, 0, 0, 0}},
  };
  for (const Want& w : wants) {
    const auto s = pose_datagrams(sparta, w.pose);
    ASSERT_EQ(s.size(), 2u);
    const auto xyz = floats_of(s[0], 3), ypr = floats_of(s[1], 3), iypr = floats_of(pose_datagrams(iem, w.pose)[0], 3);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(xyz[i], w.sparta_xyz[i], 1e-6) << "SPARTA /xyz " << i;
      EXPECT_NEAR(ypr[i], w.sparta_ypr[i], 1e-4) << "SPARTA /ypr " << i;
      EXPECT_NEAR(iypr[i], w.iem_ypr[i], 1e-4) << "SceneRotator /ypr " << i;
    }
    const auto bytes = pose_datagrams(ot, w.pose)[0];
    const auto p = parse_opentrack(bytes, nullptr);
    ASSERT_TRUE(p);
    const std::array<double, 6> got{p->x_cm, p->y_cm, p->z_cm, p->yaw_deg, p->pitch_deg, p->roll_deg};
    for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(got[i], w.opentrack[i], 1e-9) << "opentrack field " << i;
  }
  // SPARTA's /xyz comes before its /ypr; the addresses are what each receiver matches.
  const auto s = pose_datagrams(sparta, head(0, 0, 0, 0, 0, 0));
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(s[0].data())), "/xyz");
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(s[1].data())), "/ypr");
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(pose_datagrams(parse_send_spec("osc,format=iem"), head(0, 0, 0, 0, 0, 0))[0].data())),
            "/SceneRotator/quaternions");
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(pose_datagrams(parse_send_spec("osc"), head(0, 0, 0, 0, 0, 0))[0].data())),
            "/earshot/pose/quat");
}

// ---- The rate cap, on a clock the test drives -------------------------------------

TEST(PoseSender, SendsAtMostItsRateWhateverTheSourceRate) {
  UdpReceiver sink(0, std::string("127.0.0.1"));  // receives, never read: the kernel drops what does not fit
  const HeadPose h = head(0, 0, 0, 10, 0, 0);
  const auto t0 = Clock::time_point{} + std::chrono::hours(1);
  struct Case {
    double source_hz, cap_hz, seconds;
    std::uint64_t min_sent, max_sent;
  };
  // A 1 kHz source (or one replayed faster than real time) under a 100/s
  // cap: 100 a second, plus the bucket's half pose. A 60 Hz source under it: all of them.
  for (const Case& c : std::vector<Case>{{1000, 100, 1.0, 100, 102}, {10000, 100, 2.0, 200, 202}, {60, 100, 1.0, 60, 61},
                                         {1000, 250, 1.0, 250, 252}, {100, 100, 1.0, 99, 102}}) {
    PoseSender s(parse_send_spec("osc:" + std::to_string(sink.port()) + ",rate=" + std::to_string(int(c.cap_hz))));
    const long n = std::lround(c.source_hz * c.seconds);
    for (long i = 0; i < n; ++i) {
      // A source with jitter: every other pose 2% early.
      const double t = (static_cast<double>(i) - (i % 2 ? 0.02 : 0.0)) / c.source_hz;
      s.offer(h, t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t)));
    }
    const SendCounters k = s.counters();
    EXPECT_GE(k.sent + k.dropped, c.min_sent) << c.source_hz << " Hz under " << c.cap_hz;
    EXPECT_LE(k.sent + k.dropped, c.max_sent) << c.source_hz << " Hz under " << c.cap_hz;
    EXPECT_EQ(k.failed, 0u) << std::strerror(k.last_error);
  }
}

TEST(PoseSender, NothingListeningIsNoErrorAndNothingBlocks) {
  // A port nobody listens on (bound then closed): UDP has no one to refuse it.
  std::uint16_t port = 0;
  {
    UdpReceiver r(0, std::string("127.0.0.1"));
    port = r.port();
  }
  PoseSender s(parse_send_spec("opentrack:127.0.0.1:" + std::to_string(port)));
  const auto t0 = Clock::now();
  for (int i = 0; i < 20; ++i) s.offer(head(0, 0, 0, i, 0, 0), t0 + std::chrono::milliseconds(20 * i));
  const SendCounters k = s.counters();
  EXPECT_EQ(k.sent + k.dropped + k.failed, 20u);
  EXPECT_EQ(k.failed, 0u) << std::strerror(k.last_error);
  EXPECT_EQ(s.describe(), "opentrack 127.0.0.1:" + std::to_string(port) + " (100/s)");
}

// ---- An outside receiver: liblo's oscdump ---------------------------------------------

namespace {

std::string oscdump_path() {
  for (const char* p : {"/usr/bin/oscdump", "/usr/local/bin/oscdump"})
    if (::access(p, X_OK) == 0) return p;
  return {};
}

/// oscdump on a free port, its stdout read line by line. liblo takes a host
/// in a server URL as a multicast group, so oscdump cannot be bound to
/// 127.0.0.1 alone: it listens on the port for the few seconds of this test.
class OscDump {
 public:
  OscDump() {
    {
      UdpReceiver probe(0, std::string("127.0.0.1"));  // a free port, then let go
      port_ = probe.port();
    }
    int fds[2];
    if (::pipe(fds) != 0) return;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fds[1], 1);
    posix_spawn_file_actions_addclose(&fa, fds[0]);
    std::string path = oscdump_path(), flag = "-L", port = std::to_string(port_);
    char* argv[] = {path.data(), flag.data(), port.data(), nullptr};
    if (::posix_spawn(&pid_, argv[0], &fa, nullptr, argv, environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
    ::close(fds[1]);
    out_ = fds[0];
  }
  ~OscDump() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) ::close(out_);
  }
  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] bool started() const { return pid_ > 0; }

  /// The next line oscdump prints (without its timetag), or "" after `wait`.
  std::string line(std::chrono::milliseconds wait) {
    const auto deadline = std::chrono::steady_clock::now() + wait;
    for (;;) {
      if (const auto nl = buf_.find('\n'); nl != std::string::npos) {
        std::string l = buf_.substr(0, nl);
        buf_.erase(0, nl + 1);
        if (const auto sp = l.find(' '); sp != std::string::npos && l.front() != '/') l.erase(0, sp + 1);
        return l;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return {};
      pollfd p{out_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
      char chunk[512];
      const ssize_t n = ::read(out_, chunk, sizeof chunk);
      if (n <= 0) return {};
      buf_.append(chunk, static_cast<std::size_t>(n));
    }
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::uint16_t port_ = 0;
  std::string buf_;
};

/// "/ypr fff 30.000000 -20.000000 5.000000" -> address, type tags, numbers.
struct Dumped {
  std::string address, types;
  std::vector<double> v;
};
Dumped parse_dump(const std::string& l) {
  std::istringstream in(l);
  Dumped d;
  in >> d.address >> d.types;
  for (double x; in >> x;) d.v.push_back(x);
  return d;
}

}  // namespace

// liblo's oscdump as SPARTA's and IEM's stand-in: it prints what arrives as
// it parsed it. Float32 only (SPARTA's receiver takes nothing else), no
// bundles (SPARTA's takes none either), and the signs of each receiver for
// the head turned left, nodded up, tilted right and moved right.
TEST(PoseSend, OscdumpReceivesEachFormatWithItsSigns) {
  ASSERT_FALSE(oscdump_path().empty()) << "oscdump not found: install liblo-tools (scripts/install-deps.sh installs it)";
  OscDump dump;
  ASSERT_TRUE(dump.started());
  // Ready when a probe gets through (bounded: 5 s).
  PoseSender probe(parse_send_spec("osc:" + std::to_string(dump.port())));
  std::string l;
  for (int i = 0; i < 50 && l.empty(); ++i) {
    probe.offer(head(0, 0, 0, 0, 0, 0), PoseSender::Clock::now() + std::chrono::seconds(i));
    l = dump.line(std::chrono::milliseconds(100));
  }
  ASSERT_FALSE(l.empty()) << "oscdump printed nothing within 5 s";
  while (!dump.line(std::chrono::milliseconds(200)).empty()) {
  }

  const HeadPose h = head(0.1, 0, 0, 30, 20, 15);  // right 0.1 m; yaw left 30, pitch up 20, roll right 15
  const auto a = sparta_ypr(to_eigen(h.orientation)), b = scene_rotator_ypr(to_eigen(h.orientation));
  const auto q = scene_rotator_quaternions(to_eigen(h.orientation));
  struct Expect {
    std::string format, address, types;
    std::vector<double> v;
  };
  const std::vector<Expect> expects{
      {"sparta", "/xyz", "fff", {0, -0.1, 0}},
      {"", "/ypr", "fff", {a[0], a[1], a[2]}},
      {"iem-ypr", "/SceneRotator/ypr", "fff", {b[0], b[1], b[2]}},
      {"iem", "/SceneRotator/quaternions", "ffff", {q[0], q[1], q[2], q[3]}},
      {"earshot", "/earshot/pose/quat", "fffffff",
       {0.1, 0, 0, h.orientation[0], h.orientation[1], h.orientation[2], h.orientation[3]}},
  };
  // The signs of the angles those numbers carry, for a head yaw left, pitch up, roll right:
  EXPECT_GT(a[0], 0) << "SPARTA: yaw + is left";
  EXPECT_LT(a[1], 0) << "SPARTA: pitch + nods down";
  EXPECT_GT(a[2], 0) << "SPARTA: roll + is the right shoulder";
  EXPECT_LT(b[0], 0) << "SceneRotator: the scene turns right";
  EXPECT_GT(b[1], 0) << "SceneRotator: the scene pitches up";
  EXPECT_LT(b[2], 0) << "SceneRotator: the scene rolls left";
  int step = 0;
  for (const Expect& e : expects) {
    if (!e.format.empty()) {
      PoseSender s(parse_send_spec("osc:" + std::to_string(dump.port()) + ",format=" + e.format));
      s.offer(h, PoseSender::Clock::now() + std::chrono::seconds(100 + step++));
      ASSERT_EQ(s.counters().sent, 1u);
    }
    const Dumped d = parse_dump(dump.line(std::chrono::seconds(5)));
    EXPECT_EQ(d.address, e.address);
    EXPECT_EQ(d.types, e.types) << e.address << ": float32 arguments only";
    ASSERT_EQ(d.v.size(), e.v.size()) << e.address;
    for (std::size_t i = 0; i < e.v.size(); ++i) EXPECT_NEAR(d.v[i], e.v[i], 2e-6 + 1e-6 * std::abs(e.v[i])) << e.address << " " << i;
  }
}
