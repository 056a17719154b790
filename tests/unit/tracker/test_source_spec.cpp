// Source specs: every spelling the tools accept, and for each way a spec can
// be wrong, an error that names where it came from and the spec itself.
#include "earshot/tracker/source_spec.hpp"

#include <gtest/gtest.h>

#include <string>

#include "earshot/errors.hpp"

namespace earshot::tracker {
namespace {

using Kind = SourceSpec::Kind;

/// The message parse_source_spec throws for `spec` (fails if it parses).
std::string error_of(std::string_view spec, std::string_view field = "--source") {
  try {
    (void)parse_source_spec(spec, field);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "'" << spec << "' parsed";
  return {};
}

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
  EXPECT_EQ(error_of("webcam", "tracker"),
            "tracker: unknown source 'webcam' (wiimote, sim, replay:FILE, opentrack[:PORT], osc[:PORT])");
  EXPECT_NE(error_of("").find("unknown source ''"), std::string::npos);
  EXPECT_NE(error_of("Sim").find("unknown source 'Sim'"), std::string::npos);
  EXPECT_EQ(error_of("sim:3"), "--source: source 'sim:3': 'sim' takes no argument");
  EXPECT_EQ(error_of("wiimote:0"), "--source: source 'wiimote:0': 'wiimote' takes no argument");
  EXPECT_EQ(error_of("replay"), "--source: source 'replay': replay needs a file (replay:FILE)");
  EXPECT_EQ(error_of("replay:"), "--source: source 'replay:': replay needs a file (replay:FILE)");
}

TEST(SourceSpec, MakesTheSourceItNames) {
  EXPECT_EQ(make_frame_source(parse_source_spec("sim"))->describe(), "sim");
  EXPECT_THROW((void)make_frame_source(parse_source_spec("replay:/nonexistent/dots.csv")), InputError);
}

}  // namespace
}  // namespace earshot::tracker
