// Source specs: every spelling the tools accept, and for each way a spec can
// be wrong, an error that names where it came from and the spec itself.
#include "earshot/tracker/live/source_spec.hpp"

#include <gtest/gtest.h>

#include <string>

#include "earshot/errors.hpp"
#include "source_spec_error.hpp"
#include "earshot/tracker/sources/udp_pose_source.hpp"

namespace earshot::tracker {
namespace {

using Kind = SourceSpec::Kind;

using spec_tests::error_of;

TEST(SourceSpec, ParsesEveryKind) {
  EXPECT_EQ(parse_source_spec("wiimote").kind, Kind::wiimote);
  EXPECT_EQ(parse_source_spec("sim").kind, Kind::sim);
  const SourceSpec r = parse_source_spec("replay:walk.csv");
  EXPECT_EQ(r.kind, Kind::replay);
  EXPECT_EQ(r.file, "walk.csv");
  EXPECT_EQ(parse_source_spec("replay:dir/a:b.csv").file, "dir/a:b.csv");  // only the first colon splits
  EXPECT_FALSE(r.sends_poses());
}

TEST(SourceSpec, PortsDefaultAndParse) {
  EXPECT_EQ(parse_source_spec("opentrack").port, 4242);
  EXPECT_EQ(parse_source_spec("osc").port, 9000);
  const SourceSpec o = parse_source_spec("opentrack:5000");
  EXPECT_EQ(o.kind, Kind::opentrack);
  EXPECT_EQ(o.port, 5000);
  EXPECT_TRUE(o.sends_poses());
  EXPECT_EQ(parse_source_spec("osc:1").port, 1);
  EXPECT_EQ(parse_source_spec("osc:65535").port, 65535);
}

TEST(SourceSpec, BadPortsNameThePortAndTheSpec) {
  EXPECT_EQ(error_of("osc:0"), "--source: source 'osc:0': bad UDP port '0' (1-65535)");
  for (const char* spec : {"osc:65536", "opentrack:", "opentrack:12ab", "osc:-5", "osc: 80", "osc:+80", "osc:99999999999"}) {
    const std::string e = error_of(spec);
    EXPECT_NE(e.find("bad UDP port"), std::string::npos) << e;
    EXPECT_NE(e.find(std::string("'") + spec + "'"), std::string::npos) << e;
  }
}

TEST(SourceSpec, UnknownKindsAndArgumentsAreErrors) {
  EXPECT_EQ(error_of("kinect", "tracker"), "tracker: unknown source 'kinect' (" + std::string(kSourceSpecs) + ")");
  EXPECT_EQ(std::string(kSourceSpecs).rfind("wiimote, sim, replay:FILE, opentrack[:PORT][@ADDR], osc[:PORT][@ADDR], webcam", 0), 0u);
  EXPECT_NE(error_of("").find("unknown source ''"), std::string::npos);
  EXPECT_NE(error_of("Sim").find("unknown source 'Sim'"), std::string::npos);
  EXPECT_EQ(error_of("sim:3"), "--source: source 'sim:3': 'sim' takes no argument");
  EXPECT_EQ(error_of("wiimote:0"), "--source: source 'wiimote:0': 'wiimote' takes no argument");
  EXPECT_EQ(error_of("replay"), "--source: source 'replay': replay needs a file (replay:FILE)");
  EXPECT_EQ(error_of("replay:"), "--source: source 'replay:': replay needs a file (replay:FILE)");
}

TEST(SourceSpec, ListenAddressDefaultsToLoopbackAndParses) {
  EXPECT_EQ(parse_source_spec("osc").listen, "127.0.0.1");
  EXPECT_EQ(parse_source_spec("opentrack:5000").listen, "127.0.0.1");
  SourceSpec s = parse_source_spec("osc:9001@0.0.0.0");
  EXPECT_EQ(s.kind, Kind::osc);
  EXPECT_EQ(s.port, 9001);
  EXPECT_EQ(s.listen, "0.0.0.0");
  s = parse_source_spec("opentrack@192.168.1.5");
  EXPECT_EQ(s.kind, Kind::opentrack);
  EXPECT_EQ(s.port, 4242);
  EXPECT_EQ(s.listen, "192.168.1.5");
  s = parse_source_spec("osc@0.0.0.0");
  EXPECT_EQ(s.port, 9000);
  EXPECT_EQ(s.listen, "0.0.0.0");
  EXPECT_EQ(parse_source_spec("replay:take@home.csv").file, "take@home.csv");  // a file name may hold '@'
}

TEST(SourceSpec, BadListenAddressesNameTheFieldAndTheSpec) {
  EXPECT_EQ(error_of("osc:9000@localhost"),
            "--source: source 'osc:9000@localhost': bad listen address 'localhost' (an IPv4 address: 127.0.0.1, "
            "0.0.0.0 for every interface, or one interface's address)");
  for (const char* spec : {"osc@", "osc@1.2.3", "opentrack@256.0.0.1", "osc:9000@::1", "osc@ 127.0.0.1", "osc@1.2.3.4@5"}) {
    const std::string e = error_of(spec, "tracker");
    EXPECT_EQ(e.rfind("tracker: ", 0), 0u) << e;
    EXPECT_NE(e.find("bad listen address"), std::string::npos) << e;
    EXPECT_NE(e.find(std::string("'") + spec + "'"), std::string::npos) << e;
  }
  EXPECT_NE(error_of("osc:@0.0.0.0").find("bad UDP port ''"), std::string::npos);
  EXPECT_EQ(error_of("sim@0.0.0.0"), "--source: source 'sim@0.0.0.0': 'sim' takes no listen address (only opentrack and osc listen)");
  EXPECT_NE(error_of("wiimote@127.0.0.1").find("takes no listen address"), std::string::npos);
}

TEST(SourceSpec, ListenOptionAppendsTheAddressToPoseSourcesOnly) {
  EXPECT_EQ(with_listen_address("osc:9000", "0.0.0.0"), "osc:9000@0.0.0.0");
  EXPECT_EQ(with_listen_address("opentrack", "192.168.1.5"), "opentrack@192.168.1.5");
  auto err = [](std::string_view spec, std::string_view addr) {
    try {
      (void)with_listen_address(spec, addr, "--tracker", "--listen");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << spec << " with " << addr << " was accepted";
    return std::string();
  };
  EXPECT_EQ(err("sim", "0.0.0.0"),
            "--listen: needs a pose source (opentrack[:PORT] or osc[:PORT]); 'sim' does not listen on the network");
  EXPECT_NE(err("none", "0.0.0.0").find("needs a pose source"), std::string::npos);
  EXPECT_EQ(err("osc:0", "0.0.0.0"), "--tracker: source 'osc:0': bad UDP port '0' (1-65535)");  // the spec's own error
  EXPECT_NE(err("osc", "everywhere").find("--listen: bad listen address 'everywhere'"), std::string::npos);
  EXPECT_NE(err("osc@127.0.0.1", "0.0.0.0").find("already names a listen address"), std::string::npos);
}

// The socket itself: bound to 127.0.0.1 unless the spec says otherwise, as the
// kernel reports it (getsockname).
TEST(SourceSpec, PoseSourcesBindTheLoopbackByDefault) {
  for (const char* text : {"osc", "opentrack"}) {
    SourceSpec s = parse_source_spec(text);
    s.port = 0;  // any free port: the test must not collide with a running tracker
    const auto src = make_frame_source(s);
    const auto* udp = dynamic_cast<const UdpPoseSource*>(src.get());
    ASSERT_NE(udp, nullptr) << text;
    EXPECT_EQ(udp->listen_address(), "127.0.0.1") << text;
    EXPECT_NE(udp->port(), 0) << text;
  }
  SourceSpec all = parse_source_spec("osc@0.0.0.0");
  all.port = 0;
  const auto src = make_frame_source(all);
  EXPECT_EQ(dynamic_cast<const UdpPoseSource&>(*src).listen_address(), "0.0.0.0");
}

TEST(SourceSpec, MakesTheSourceItNames) {
  EXPECT_EQ(make_frame_source(parse_source_spec("sim"))->describe(), "sim");
  EXPECT_THROW((void)make_frame_source(parse_source_spec("replay:/nonexistent/dots.csv")), InputError);
}

}  // namespace
}  // namespace earshot::tracker
