// Direct pose inputs: opentrack's UDP packet and our OSC addresses, byte by
// byte and over the loopback (127.0.0.1 only, bounded waits); the Pose track
// CSV the recorder writes.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <utility>
#include <vector>

#include "earshot/tracker/live/live_pipeline.hpp"
#include "earshot/tracker/sources/opentrack_packet.hpp"
#include "earshot/tracker/sources/osc_pose.hpp"
#include "earshot/errors.hpp"
#include "earshot/pose_track_csv.hpp"

using namespace earshot::tracker;
using earshot::HeadPose;
using earshot::PoseTrackCsvWriter;
using earshot::read_pose_track_csv;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
using Bytes = std::vector<std::uint8_t>;
}  // namespace

TEST(Opentrack, PacketIsSixLittleEndianDoubles) {
  // 1.0 = 0x3FF0000000000000, -2.5 = 0xC004000000000000, 90.0 = 0x4056800000000000.
  Bytes b{0, 0, 0, 0, 0, 0, 0xF0, 0x3F,  0, 0, 0, 0, 0, 0, 0x04, 0xC0,  0, 0, 0, 0, 0, 0, 0, 0,
          0, 0, 0, 0, 0, 0x80, 0x56, 0x40,  0, 0, 0, 0, 0, 0, 0, 0,  0, 0, 0, 0, 0, 0, 0xF0, 0x3F};
  std::string why;
  const auto p = parse_opentrack(b, &why);
  ASSERT_TRUE(p) << why;
  EXPECT_EQ(p->x_cm, 1.0);
  EXPECT_EQ(p->y_cm, -2.5);
  EXPECT_EQ(p->z_cm, 0.0);
  EXPECT_EQ(p->yaw_deg, 90.0);
  EXPECT_EQ(p->pitch_deg, 0.0);
  EXPECT_EQ(p->roll_deg, 1.0);
  const auto again = encode_opentrack(*p);
  EXPECT_EQ(Bytes(again.begin(), again.end()), b);
}

// opentrack's own signs, one axis at a time, as its trackers fill the pose
// (tracker-rift-140, tracker-steamvr, tracker-tobii: docs/OSC.md, "opentrack"):
// +x left, +y up, +z backward (away from the screen), +yaw right, +pitch up,
// +roll toward the left shoulder. Each hand-built packet must move the head
// that way in the audio world (+x right, +y up, -z ahead), and each head
// pose must come out as that packet: the sign of every axis, both ways.
TEST(Opentrack, EveryAxisHasOpentracksSignBothWays) {
  struct Axis {
    const char* name;
    OpentrackPacket packet;     // what opentrack sends for this head
    Vec3 position_m;            // where the head is, audio world
    Vec3 ahead;                 // where it looks
    Vec3 up;                    // where its top points
  };
  const double s = std::sin(30 * kDeg), c = std::cos(30 * kDeg);
  const std::vector<Axis> axes{
      {"x +10 cm: left", {10, 0, 0, 0, 0, 0}, Vec3(-0.10, 0, 0), Vec3(0, 0, -1), Vec3(0, 1, 0)},
      {"y +10 cm: up", {0, 10, 0, 0, 0, 0}, Vec3(0, 0.10, 0), Vec3(0, 0, -1), Vec3(0, 1, 0)},
      {"z +10 cm: backward", {0, 0, 10, 0, 0, 0}, Vec3(0, 0, 0.10), Vec3(0, 0, -1), Vec3(0, 1, 0)},
      {"yaw +30: right", {0, 0, 0, 30, 0, 0}, Vec3::Zero(), Vec3(s, 0, -c), Vec3(0, 1, 0)},
      {"pitch +30: up", {0, 0, 0, 0, 30, 0}, Vec3::Zero(), Vec3(0, s, -c), Vec3(0, c, s)},
      {"roll +30: left shoulder", {0, 0, 0, 0, 0, 30}, Vec3::Zero(), Vec3(0, 0, -1), Vec3(-s, c, 0)},
  };
  for (const Axis& a : axes) {
    // opentrack -> us: the 48 bytes a sender with opentrack's signs puts on the wire.
    const auto bytes = encode_opentrack(a.packet);
    std::string why;
    const auto m = decode_opentrack(bytes, &why);
    ASSERT_TRUE(m && m->pose) << a.name << ": " << why;
    const Quat q = to_eigen(m->pose->orientation);
    EXPECT_TRUE(to_eigen(m->pose->position).isApprox(a.position_m, 1e-12) ||
                (a.position_m.isZero() && to_eigen(m->pose->position).isZero()))
        << a.name << ": position " << to_eigen(m->pose->position).transpose();
    EXPECT_TRUE((q * Vec3(0, 0, -1)).isApprox(a.ahead, 1e-12)) << a.name << ": ahead " << (q * Vec3(0, 0, -1)).transpose();
    EXPECT_TRUE((q * Vec3(0, 1, 0)).isApprox(a.up, 1e-12)) << a.name << ": up " << (q * Vec3(0, 1, 0)).transpose();

    // us -> opentrack: the head above must come out as the same packet.
    HeadPose h;
    h.position = to_common(a.position_m);
    h.orientation = m->pose->orientation;
    const OpentrackPacket out = pose_to_opentrack(h);
    const std::array<double, 6> got{out.x_cm, out.y_cm, out.z_cm, out.yaw_deg, out.pitch_deg, out.roll_deg};
    const std::array<double, 6> want{a.packet.x_cm,    a.packet.y_cm,      a.packet.z_cm,
                                     a.packet.yaw_deg, a.packet.pitch_deg, a.packet.roll_deg};
    for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(got[i], want[i], 1e-9) << a.name << ": field " << i;
  }
}

// A general pose survives our output and our input: x, y, z and the three
// angles together (yaw first, as both sides compose them).
TEST(Opentrack, OurOutputIsOurInput) {
  for (const auto& [ypr, pos] : std::vector<std::pair<std::array<double, 3>, Vec3>>{
           {{40, -20, 15}, Vec3(0.05, -0.02, 0.12)}, {{-130, 60, -75}, Vec3(-0.3, 0.1, -0.2)}, {{0, 0, 0}, Vec3::Zero()}}) {
    HeadPose h;
    h.position = to_common(pos);
    h.orientation = earshot::quat_from_ypr(ypr[0] * kDeg, ypr[1] * kDeg, ypr[2] * kDeg);
    std::string why;
    const auto m = decode_opentrack(encode_opentrack(pose_to_opentrack(h)), &why);
    ASSERT_TRUE(m && m->pose) << why;
    EXPECT_TRUE(to_eigen(m->pose->position).isApprox(pos, 1e-12) || pos.isZero());
    EXPECT_NEAR(to_eigen(m->pose->orientation).angularDistance(to_eigen(h.orientation)), 0.0, 1e-12);
  }
}

TEST(Opentrack, MalformedPacketsAreDroppedWithAReason) {
  std::string why;
  EXPECT_FALSE(parse_opentrack(Bytes(47, 0), &why));
  EXPECT_NE(why.find("47 bytes"), std::string::npos);
  auto b = encode_opentrack({0, 0, 0, std::nan(""), 0, 0});
  EXPECT_FALSE(parse_opentrack(b, &why));
  EXPECT_NE(why.find("yaw"), std::string::npos);
  b = encode_opentrack({5000.0, 0, 0, 0, 0, 0});  // 50 m
  EXPECT_FALSE(parse_opentrack(b, &why));
  b = encode_opentrack({0, 0, 0, 0, 0, 1e6});
  EXPECT_FALSE(parse_opentrack(b, &why));
  EXPECT_NE(why.find("roll"), std::string::npos);
}

TEST(Osc, AddressesAndTypes) {
  OscPoseDecoder d;
  const std::array<double, 6> ypr{0.1, 0.2, -0.3, 90.0, 0.0, 0.0};
  std::string why;
  auto m = d.decode(encode_osc("/earshot/pose/ypr", ypr), &why);
  ASSERT_TRUE(m && m->pose) << why;
  EXPECT_TRUE(to_eigen(m->pose->position).isApprox(Vec3(0.1, 0.2, -0.3)));
  EXPECT_TRUE((to_eigen(m->pose->orientation) * Vec3(0, 0, -1)).isApprox(Vec3(-1, 0, 0), 1e-12));  // yaw 90 = left

  const Quat q = to_eigen(earshot::quat_from_ypr(0, 0, 30 * kDeg));
  const std::array<double, 7> quat{0, 0, 0, q.w(), q.x(), q.y(), q.z()};
  m = d.decode(encode_osc("/earshot/pose/quat", quat), &why);
  ASSERT_TRUE(m && m->pose) << why;
  EXPECT_NEAR(to_eigen(m->pose->orientation).angularDistance(q), 0.0, 1e-12);

  const std::array<double, 3> ypr_only{0, 45, 0};
  m = d.decode(encode_osc("/earshot/ypr", ypr_only), &why);
  ASSERT_TRUE(m && m->pose) << why;
  EXPECT_TRUE(to_eigen(m->pose->position).isZero());

  const std::array<double, 4> q_only{1, 0, 0, 0};
  EXPECT_TRUE(d.decode(encode_osc("/earshot/quat", q_only), &why));

  m = d.decode(encode_osc("/earshot/recenter", {}), &why);
  ASSERT_TRUE(m) << why;
  EXPECT_TRUE(m->recenter);
  EXPECT_FALSE(m->pose);

  // Float32 arguments, byte for byte: "/earshot/ypr\0\0\0\0" ",fff\0\0\0\0" then three floats.
  Bytes raw{'/', 'e', 'a', 'r', 's', 'h', 'o', 't', '/', 'y', 'p', 'r', 0, 0, 0, 0, ',', 'f', 'f', 'f', 0, 0, 0, 0,
            0x42, 0xB4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};  // 90.0f, 0, 0 (big-endian)
  m = d.decode(raw, &why);
  ASSERT_TRUE(m && m->pose) << why;
  EXPECT_TRUE((to_eigen(m->pose->orientation) * Vec3(0, 0, -1)).isApprox(Vec3(-1, 0, 0), 1e-6));
}

TEST(Osc, MalformedMessagesAreDroppedWithAReason) {
  OscPoseDecoder d;
  std::string why;
  const std::array<double, 2> two{1, 2};
  EXPECT_FALSE(d.decode(encode_osc("/earshot/ypr", two), &why));
  EXPECT_NE(why.find("expected 3 numbers"), std::string::npos) << why;
  const std::array<double, 3> three{1, 2, 3};
  EXPECT_FALSE(d.decode(encode_osc("/other/thing", three), &why));
  EXPECT_NE(why.find("not one of ours"), std::string::npos) << why;
  const std::array<double, 4> zero{0, 0, 0, 0};  // a quaternion is normalised; one with no direction is refused
  EXPECT_FALSE(d.decode(encode_osc("/earshot/quat", zero), &why));
  EXPECT_NE(why.find("no direction"), std::string::npos) << why;
  const std::array<double, 6> far{100, 0, 0, 0, 0, 0};
  EXPECT_FALSE(d.decode(encode_osc("/earshot/pose/ypr", far), &why));
  const std::array<double, 3> nan{std::nan(""), 0, 0};
  EXPECT_FALSE(d.decode(encode_osc("/earshot/ypr", nan), &why));
  EXPECT_FALSE(d.decode(Bytes{'/', 'x', 0}, &why));  // truncated
  EXPECT_FALSE(d.decode(Bytes{}, &why));
  Bytes bundle{'#', 'b', 'u', 'n', 'd', 'l', 'e', 0, 0, 0, 0, 0, 0, 0, 0, 1};  // an empty bundle
  EXPECT_FALSE(d.decode(bundle, &why));
  EXPECT_NE(why.find("bundle holds no messages"), std::string::npos) << why;
}

TEST(UdpPoseSources, LoopbackPacketsBecomePosesAndBadOnesAreCounted) {
  UdpPoseSource ot("opentrack", 0, false, decode_opentrack);  // any free port, 127.0.0.1
  const auto good = encode_opentrack({0, 0, 10.0, 0, 0, 0});
  send_udp_loopback(ot.port(), good);
  send_udp_loopback(ot.port(), Bytes(12, 0xAB));
  send_udp_loopback(ot.port(), good);
  int poses = 0;
  for (int i = 0; i < 50 && poses < 2; ++i) {  // bounded: at most 50 waits of 100 ms
    const auto e = ot.next(std::chrono::milliseconds(100));
    if (const auto* p = std::get_if<HeadPose>(&e)) {
      ++poses;
      EXPECT_TRUE(to_eigen(p->position).isApprox(Vec3(0, 0, 0.1)));  // opentrack's +z: backward
    }
  }
  EXPECT_EQ(poses, 2);
  EXPECT_EQ(ot.dropped(), 1u);
  EXPECT_NE(ot.last_error().find("12 bytes"), std::string::npos) << ot.last_error();

  UdpPoseSource osc("osc", 0, false, OscPoseDecoder::packet_decoder());
  send_udp_loopback(osc.port(), encode_osc("/earshot/recenter", {}));
  bool recenter = false;
  for (int i = 0; i < 50 && !recenter; ++i) {
    const auto e = osc.next(std::chrono::milliseconds(100));
    if (const auto* n = std::get_if<SourceNote>(&e)) recenter = n->kind == SourceNote::Kind::recenter;
  }
  EXPECT_TRUE(recenter);
}

TEST(PoseTrackCsv, WritesTheRendererContractAndSkipsStaleRows) {
  std::ostringstream out;
  PoseTrackCsvWriter w(out);
  earshot::HeadPose p;
  p.t = 0.5;
  p.position = {0.1, 0.0, -0.2};
  EXPECT_TRUE(w.write(p));
  EXPECT_FALSE(w.write(p));  // same time: the renderer wants increasing times
  p.t = 0.51;
  p.position[0] = std::nan("");
  EXPECT_FALSE(w.write(p));
  EXPECT_EQ(out.str(), "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0.5,0.1,0,-0.2,1,0,0,0\n");
}

TEST(PoseTrackCsv, ReadsWhatItWrites) {
  std::stringstream io;
  PoseTrackCsvWriter w(io);
  earshot::HeadPose p;
  p.t = 0.25;
  p.position = {0.1, -0.2, 0.3};
  p.orientation = earshot::quat_from_ypr(0.4, -0.1, 0.2);
  ASSERT_TRUE(w.write(p));
  p.t = 0.5;
  ASSERT_TRUE(w.write(p));
  const auto rows = read_pose_track_csv(io, "mem");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].t, 0.5);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(rows[0].position[i], p.position[i], 1e-8);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(rows[0].orientation[i], p.orientation[i], 1e-8);
}

TEST(PoseTrackCsv, BadInputNamesFileLineAndField) {
  auto error_of = [](const std::string& text) -> std::string {
    std::istringstream in(text);
    try {
      (void)read_pose_track_csv(in, "track.csv");
    } catch (const earshot::InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  const std::string h = "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  EXPECT_EQ(error_of("time,x\n"), "track.csv:1: field 't_s': expected the header t_s,x_m,y_m,z_m,qw,qx,qy,qz");
  EXPECT_EQ(error_of(h), "track.csv: no poses in the track");
  EXPECT_EQ(error_of(h + "0,0,0,0,1,0,0\n"), "track.csv:2: expected 8 fields, found 7");
  EXPECT_EQ(error_of(h + "0,0,abc,0,1,0,0,0\n"), "track.csv:2: field 'y_m': not a number: 'abc'");
  EXPECT_EQ(error_of(h + "0,0,0,0,0.5,0,0,0\n"), "track.csv:2: field 'qw': quaternion is not unit length");
  EXPECT_EQ(error_of(h + "1,0,0,0,1,0,0,0\n1,0,0,0,1,0,0,0\n"), "track.csv:3: field 't_s': times must increase");
}

TEST(PoseTrackCsv, ARecordingCarriesEachRowsStateAndReadsBack) {
  std::stringstream io;
  PoseTrackCsvWriter w(io, true);
  earshot::HeadPose p;
  p.t = 0.0;  // the first frame: time zero is a row too
  p.state = earshot::PoseState::searching;
  ASSERT_TRUE(w.write(p));
  p.t = 0.01;
  p.state = earshot::PoseState::tracking;
  ASSERT_TRUE(w.write(p));
  p.t = 0.02;
  p.state = earshot::PoseState::lost;
  ASSERT_TRUE(w.write(p));
  EXPECT_EQ(io.str().substr(0, io.str().find('\n')), "t_s,x_m,y_m,z_m,qw,qx,qy,qz,state");
  const auto rows = read_pose_track_csv(io, "mem");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].t, 0.0);
  EXPECT_EQ(rows[0].state, earshot::PoseState::searching);
  EXPECT_EQ(rows[1].state, earshot::PoseState::tracking);
  EXPECT_EQ(rows[2].state, earshot::PoseState::lost);
}
