#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "calibration_sim.hpp"
#include "earshot/errors.hpp"

using namespace earshot::tracker;
using namespace calibration_sim;

namespace {

CalibrationOptions options_for(const LedModel& truth, int a = 0, int b = 1) {
  CalibrationOptions o;
  o.scale = {(truth.leds_mm[static_cast<size_t>(a)] - truth.leds_mm[static_cast<size_t>(b)]).norm(), a, b};
  return o;
}

std::string error_of(const std::vector<DotFrame>& frames, const LedModel& start, const CalibrationOptions& o) {
  try {
    (void)calibrate_led_model(frames, start, Camera(), o, "session.csv");
  } catch (const earshot::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ScaleBar, ParsesDistanceAndLeds) {
  const ScaleBar s = parse_scale_bar("170.5:0-3");
  EXPECT_DOUBLE_EQ(s.mm, 170.5);
  EXPECT_EQ(s.a, 0);
  EXPECT_EQ(s.b, 3);
}

TEST(ScaleBar, RejectsWhatIsNotTwoDistinctLeds) {
  auto msg = [](const char* t) {
    try {
      (void)parse_scale_bar(t);
    } catch (const earshot::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(msg("170:1-1").find("the two LEDs must differ"), std::string::npos) << msg("170:1-1");
  EXPECT_NE(msg("170:0-4").find("LED '4' is not one of 0, 1, 2, 3"), std::string::npos) << msg("170:0-4");
  EXPECT_NE(msg("-3:0-1").find("not a positive number"), std::string::npos) << msg("-3:0-1");
  EXPECT_NE(msg("170").find("expected D:A-B"), std::string::npos) << msg("170");
  EXPECT_NE(msg("170:0-1x").find("--scale-mm"), std::string::npos);
}

TEST(RigidAlign, RecoversAKnownMotion) {
  const LedModel m;
  Pose truth;
  truth.R = rotation_from_ypr(0.3, -0.2, 1.1);
  truth.t = Vec3(10, -20, 5);
  std::array<Vec3, 4> moved;
  for (size_t j = 0; j < 4; ++j) moved[j] = truth.apply(m.leds_mm[j]);
  const Pose p = rigid_align(m.leds_mm, moved);
  EXPECT_LT(rotation_angle_between(p.R, truth.R), 1e-9);
  EXPECT_LT((p.t - truth.t).norm(), 1e-9);
  EXPECT_LT(max_of(led_errors_after_alignment(moved, m.leds_mm)), 1e-9);
}

// A short seated session (15 s, integer pixels) from a model off by 3 mm per
// LED: the calibration comes within 0.5 mm of the truth (after the rigid
// alignment the free gauge needs), says how certain it is, and keeps the
// starting model's frame (its LEDs stay near the starting ones).
TEST(LedCalibration, RecoversTheModelFromAShortSeatedSession) {
  const LedModel truth;
  const LedModel start = perturbed(truth, 3.0, 11);
  const auto frames = session(Camera(), truth, MotionProfile::seated, 401, 1500);
  ASSERT_GT(max_of(led_errors_after_alignment(start.leds_mm, truth.leds_mm)), 1.5);
  std::vector<CalibrationIteration> its;
  CalibrationOptions o = options_for(truth);
  o.on_iteration = [&](const CalibrationIteration& i) { its.push_back(i); };
  const CalibrationResult r = calibrate_led_model(frames, start, Camera(), o, "session.csv");
  const auto err = led_errors_after_alignment(r.model.leds_mm, truth.leds_mm);
  EXPECT_LT(max_of(err), 0.5) << err[0] << " " << err[1] << " " << err[2] << " " << err[3];
  EXPECT_LT(r.rms_after_px, r.rms_before_px);
  // Integer pixels: the per-frame pose takes up 6 of each frame's 8 noisy
  // coordinates, so the residual (~0.2 px per dot) is below the noise.
  EXPECT_LT(r.rms_after_px, 0.3);
  EXPECT_NEAR(r.pixel_sigma_px, 1.0 / std::sqrt(12.0), 0.08);  // rounding noise per coordinate
  for (const auto& s : r.led_sigma_mm) {
    EXPECT_GT(s.minCoeff(), 0.0);
    EXPECT_LT(s.maxCoeff(), 0.5);
  }
  ASSERT_EQ(r.weakest.size(), 3u);
  EXPECT_GE(r.weakest[1].sigma_mm, 0.0);
  EXPECT_LE(r.weakest[1].sigma_mm, r.weakest[0].sigma_mm);
  // The head frame stays the user's: the calibrated LEDs lie near the starting ones.
  for (size_t j = 0; j < 4; ++j) EXPECT_LT(r.moved_mm[j], 6.0);
  EXPECT_EQ(r.model.axis, start.axis);
  EXPECT_EQ(r.model.half_angle, start.half_angle);
  // Convergence was reported, from the start to the end.
  ASSERT_GE(its.size(), 3u);
  EXPECT_EQ(its.front().round, 1);
  EXPECT_EQ(its.front().iteration, 0);
  EXPECT_EQ(its.back().round, 2);
  EXPECT_LT(max_of(led_errors_after_alignment(its.back().leds_mm, truth.leds_mm)), 0.5);
}

// The ruler fixes the size: a rig 2 % larger than the model (the same shape)
// with the ruler reading its real distance comes out 2 % larger, the ruler
// pair exactly at the measured distance.
TEST(LedCalibration, TheRulerSetsTheScale) {
  LedModel big;
  for (auto& p : big.leds_mm) p *= 1.02;
  const auto frames = session(Camera(), big, MotionProfile::seated, 402, 1500);
  CalibrationOptions o = options_for(big, 2, 3);
  const CalibrationResult r = calibrate_led_model(frames, LedModel(), Camera(), o, "session.csv");
  EXPECT_NEAR((r.model.leds_mm[2] - r.model.leds_mm[3]).norm(), o.scale.mm, 1e-9);
  EXPECT_LT(max_of(led_errors_after_alignment(r.model.leds_mm, big.leds_mm)), 0.5);
  // And a ruler reading far from the model (cm for mm) is refused, naming the option.
  o.scale.mm /= 10.0;
  const std::string e = error_of(frames, LedModel(), o);
  EXPECT_NE(e.find("--scale-mm"), std::string::npos) << e;
  EXPECT_NE(e.find("measure again"), std::string::npos) << e;
}

// A still head: the dots hardly move, nothing tells the LEDs' depths apart.
TEST(LedCalibration, RefusesAStillHead) {
  const LedModel truth;
  std::vector<DotFrame> frames;
  Simulator sim(Camera(), truth, {});
  Pose p;
  p.R = rotation_from_ypr(0.05, -0.03, 0.02);
  p.t = Vec3(10, 5, 900);
  for (int i = 0; i < 1000; ++i) frames.push_back(sim.observe(p, 0.01 * i));
  const std::string e = error_of(frames, perturbed(truth, 3.0, 5), options_for(truth));
  EXPECT_NE(e.find("session.csv: too little motion"), std::string::npos) << e;
  EXPECT_NE(e.find("turning your head"), std::string::npos) << e;
}

// A recording where the fourth LED is hardly ever in view.
TEST(LedCalibration, RefusesTooFewFourDotFrames) {
  const LedModel truth;
  auto frames = session(Camera(), truth, MotionProfile::seated, 403, 1500);
  for (size_t i = 0; i < frames.size(); ++i)
    if (i % 20 != 0) frames[i].slots[static_cast<size_t>(i % 4)].reset();
  const std::string e = error_of(frames, truth, options_for(truth));
  EXPECT_NE(e.find("too few frames with all four LEDs"), std::string::npos) << e;
}

// Little rotation but not none: the adjustment runs, and the uncertainty it
// computes is what refuses the result, with advice on the motion.
TEST(LedCalibration, RefusesAnUndeterminedModelWithAdvice) {
  const LedModel truth;
  std::vector<DotFrame> frames;
  Simulator sim(Camera(), truth, {});
  for (int i = 0; i < 1500; ++i) {
    Pose p;
    const double ph = 0.01 * i;
    p.R = rotation_from_ypr(0.08 * std::sin(ph), 0.01 * std::sin(1.7 * ph), 0.0);
    p.t = Vec3(30 * std::sin(0.3 * ph), 10, 900);
    frames.push_back(sim.observe(p, 0.01 * i));
  }
  CalibrationOptions o = options_for(truth);
  o.min_turn_deg = 2.0;  // past the motion check: the uncertainty decides here
  o.max_led_sigma_mm = 0.05;
  const std::string e = error_of(frames, perturbed(truth, 3.0, 6), o);
  EXPECT_NE(e.find("does not determine the model"), std::string::npos) << e;
  EXPECT_NE(e.find("least determined"), std::string::npos) << e;
  EXPECT_NE(e.find("nod further up and down"), std::string::npos) << e;
}

TEST(LedCalibration, SavedModelReadsBack) {
  LedModel m = perturbed(LedModel(), 2.0, 3);
  m.half_angle = 0.6;
  const auto path = std::filesystem::temp_directory_path() / ("led_cal_" + std::to_string(::getpid()) + ".json");
  save_led_model(m, path.string());
  const LedModel back = load_led_model(path);
  std::filesystem::remove(path);
  for (size_t j = 0; j < 4; ++j) EXPECT_LT((back.leds_mm[j] - m.leds_mm[j]).norm(), 1e-3);
  EXPECT_NEAR(back.half_angle, 0.6, 1e-9);
  EXPECT_LT((back.axis - m.axis).norm(), 1e-12);
}
