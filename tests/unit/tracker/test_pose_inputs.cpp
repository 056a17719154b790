// Direct pose inputs: opentrack's UDP packet and our OSC addresses, byte by
// byte and over the loopback (127.0.0.1 only, bounded waits); the Pose track
// CSV the recorder writes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

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

TEST(Opentrack, AxesMapIntoTheAudioFrame) {
  // opentrack: yaw right positive, z forward (towards the screen).
  const HeadPose d = opentrack_to_pose({10.0, 5.0, 20.0, 90.0, 0.0, 0.0});
  EXPECT_TRUE(to_eigen(d.position).isApprox(Vec3(0.10, 0.05, -0.20)));
  EXPECT_TRUE((to_eigen(d.orientation) * Vec3(0, 0, -1)).isApprox(Vec3(1, 0, 0), 1e-12));  // looks right
  const HeadPose up = opentrack_to_pose({0, 0, 0, 0, 30.0, 0});
  EXPECT_GT((to_eigen(up.orientation) * Vec3(0, 0, -1)).y(), 0.4);  // pitch up looks up
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
  const std::array<double, 4> notunit{2, 0, 0, 0};
  EXPECT_FALSE(d.decode(encode_osc("/earshot/quat", notunit), &why));
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
      EXPECT_TRUE(to_eigen(p->position).isApprox(Vec3(0, 0, -0.1)));
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
