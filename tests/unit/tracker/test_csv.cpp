#include <gtest/gtest.h>

#include <sstream>

#include "earshot/errors.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/led_model.hpp"
#include "earshot/tracker/core/poses_csv.hpp"

using namespace earshot::tracker;
using earshot::PoseState;
using earshot::InputError;

namespace {
std::string error_of(const std::string& text) {
  std::istringstream in(text);
  DotsCsvReader r(in, "dots.csv");
  try {
    while (r.next()) {
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(DotsCsv, ReadsSlotsAndEmptyFields) {
  std::istringstream in("t_s,x1,y1,x2,y2,x3,y3,x4,y4\n0.01,10,20,,,30.5,40,1,2\n");
  DotsCsvReader r(in, "dots.csv");
  const auto f = r.next();
  ASSERT_TRUE(f.has_value());
  EXPECT_DOUBLE_EQ(f->t, 0.01);
  EXPECT_EQ(f->visible(), 3);
  EXPECT_FALSE(f->slots[1].has_value());
  EXPECT_DOUBLE_EQ(f->slots[2]->x(), 30.5);
  EXPECT_FALSE(f->truth.has_value());
  EXPECT_FALSE(r.next().has_value());
}

TEST(DotsCsv, ErrorsNameFileLineAndField) {
  const std::string h = "t_s,x1,y1,x2,y2,x3,y3,x4,y4\n";
  EXPECT_EQ(error_of(h + "0,1,2,3,4,5,6,7,8\n0.1,1,2,abc,4,5,6,7,8\n"),
            "dots.csv:3: field 'x2': not a number: 'abc'");
  EXPECT_EQ(error_of(h + "0,1,2,3,,5,6,7,8\n"), "dots.csv:2: field 'y2': a dot needs both x and y (or neither)");
  EXPECT_EQ(error_of(h + "0,1,2,3\n"), "dots.csv:2: expected at least 9 fields, found 4");
  EXPECT_EQ(error_of(h + "nan,1,2,3,4,5,6,7,8\n"), "dots.csv:2: field 't_s': not a finite number: 'nan'");
  EXPECT_EQ(error_of(h + "0,inf,2,3,4,5,6,7,8\n"), "dots.csv:2: field 'x1': not a finite number: 'inf'");
  EXPECT_EQ(error_of("time,x1,y1,x2,y2,x3,y3,x4,y4\n"), "dots.csv:1: field 't_s': header column 1 is 'time'");
  EXPECT_EQ(error_of(""), "dots.csv: empty file: no header line");
}

TEST(DotsCsv, RoundTripsWithGroundTruth) {
  DotFrame f;
  f.t = 1.25;
  f.slots[0] = Vec2(1, 2);
  f.slots[3] = Vec2(511.5, 300);
  GroundTruth gt;
  gt.pose = {rotation_from_ypr(0.1, 0.2, 0.3), Vec3(1, 2, 1000)};
  gt.slot_led = {2, 0, 0, -1};
  f.truth = gt;
  std::stringstream ss;
  DotsCsvWriter w(ss, true);
  w.write(f);
  DotsCsvReader r(ss, "mem");
  const auto g = r.next();
  ASSERT_TRUE(g.has_value() && g->truth.has_value());
  EXPECT_EQ(g->truth->slot_led, gt.slot_led);
  EXPECT_LT(rotation_angle_between(g->truth->pose.R, gt.pose.R), 1e-8);
  EXPECT_EQ(*g->slots[3], *f.slots[3]);
}

TEST(PosesCsv, NeverWritesANonFinitePose) {
  std::stringstream ss;
  PosesCsvWriter w(ss);
  PoseRecord r;
  r.pose.t = Vec3(0, NAN, 1000);
  EXPECT_THROW(w.write(r), std::logic_error);
  r.pose.t = Vec3(0, 0, 1000);
  r.pose.R(0, 0) = INFINITY;
  EXPECT_THROW(w.write(r), std::logic_error);
  EXPECT_EQ(ss.str(), "t_s,state,tx_mm,ty_mm,tz_mm,qw,qx,qy,qz\n");
}

TEST(PosesCsv, RoundTrips) {
  std::stringstream ss;
  PosesCsvWriter w(ss);
  w.write({0.5, PoseState::predicted, {rotation_from_ypr(0.3, 0, -0.2), Vec3(1, 2, 3)}});
  PosesCsvReader r(ss, "mem");
  const auto p = r.next();
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->state, PoseState::predicted);
  EXPECT_NEAR(p->pose.t.z(), 3.0, 1e-9);
}

TEST(LedModelJson, ParsesAndRejectsWithFieldNames) {
  const auto m = parse_led_model(R"({"leds_mm": [[1,0,0],[0,1,0],[-1,0,0],[0,0,2]], "half_angle_deg": 30})", "m.json");
  EXPECT_DOUBLE_EQ(m.leds_mm[3].z(), 2.0);
  auto err = [](const char* text) {
    try {
      (void)parse_led_model(text, "m.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(err(R"({"leds_mm": [[1,0,0],[0,1,0],[-1,0,0]]})"), "m.json: field 'leds_mm': expected four [x, y, z] points");
  EXPECT_EQ(err(R"({"leds_mm": [[1,0,0],[0,1,"a"],[-1,0,0],[0,0,2]]})"),
            "m.json: field 'leds_mm[1]': expected a number, got \"a\"");
  EXPECT_EQ(err(R"({"leds": []})"), "m.json: field 'leds': unknown field");
  EXPECT_EQ(err(R"({"leds_mm": [[0,0,0],[1,0,0],[2,0,0],[0,0,2]]})"),
            "m.json: field 'leds_mm': the first three LEDs are collinear");
  EXPECT_NE(err("{"), "");
  // Found by fuzz_led_model: a number too large for a double used to escape
  // as nlohmann's out_of_range instead of an InputError.
  EXPECT_NE(err(R"({"leds_mm": [[3E2222222222.5,135,3],[-6,16,6],[6,-66,3],[-5,-16.5,4]]})").find("m.json: not valid JSON"),
            std::string::npos);
}
