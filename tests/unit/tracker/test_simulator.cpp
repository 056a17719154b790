#include <gtest/gtest.h>

#include <sstream>

#include "earshot/tracker/simulator.hpp"

using namespace earshot::tracker;

TEST(Simulator, IsDeterministicForASeed) {
  const Camera cam;
  const LedModel model;
  SimulatorConfig cfg;
  cfg.seed = 42;
  cfg.dropout_rate = 0.01;
  cfg.stray_rate = 0.01;
  auto dump = [&] {
    Simulator sim(cam, model, cfg);
    std::stringstream ss;
    DotsCsvWriter w(ss, true);
    for (int i = 0; i < 500; ++i) w.write(sim.next());
    return ss.str();
  };
  EXPECT_EQ(dump(), dump());
}

TEST(Simulator, DotsMatchGroundTruthAndKeepTheirSlots) {
  const Camera cam;
  const LedModel model;
  SimulatorConfig cfg;
  cfg.pixels = PixelModel::exact;
  Simulator sim(cam, model, cfg);
  std::array<int, 4> prev{0, 0, 0, 0};
  int kept = 0;
  for (int i = 0; i < 3000; ++i) {
    const DotFrame f = sim.next();
    ASSERT_TRUE(f.truth.has_value());
    for (size_t s = 0; s < 4; ++s) {
      const int led = f.truth->slot_led[s];
      EXPECT_EQ(f.slots[s].has_value(), led != 0);
      if (led > 0) {
        const Vec2 px = cam.project(f.truth->pose.apply(model.leds_mm[static_cast<size_t>(led - 1)]));
        EXPECT_LT((px - *f.slots[s]).norm(), 1e-9);
        EXPECT_TRUE(cam.inside(px));
      }
      // A dot visible in two consecutive frames stays in its slot.
      for (size_t o = 0; o < 4; ++o)
        if (led > 0 && prev[o] == led) {
          EXPECT_EQ(o, s);
          ++kept;
        }
    }
    prev = f.truth->slot_led;
  }
  EXPECT_GT(kept, 5000);
}

TEST(Simulator, LedsTurnedBeyondTheBeamAreNotSeen) {
  const Camera cam;
  const LedModel model;
  Simulator sim(cam, model, {});
  // Yawed 60 degrees: beyond the 45-degree half-angle for every LED.
  const DotFrame f = sim.observe({rotation_from_ypr(60 * M_PI / 180, 0, 0), Vec3(0, 0, 1000)}, 0.0);
  EXPECT_EQ(f.visible(), 0);
  const DotFrame g = sim.observe({rotation_from_ypr(20 * M_PI / 180, 0, 0), Vec3(0, 0, 1000)}, 0.01);
  EXPECT_EQ(g.visible(), 4);
}

TEST(Simulator, QuantizesToMultiplesOfEight) {
  const Camera cam;
  const LedModel model;
  SimulatorConfig cfg;
  cfg.pixels = PixelModel::quantize8;
  Simulator sim(cam, model, cfg);
  for (int i = 0; i < 200; ++i) {
    const DotFrame f = sim.next();
    for (const auto& s : f.slots)
      if (s) {
        EXPECT_EQ(std::fmod(s->x(), 8.0), 0.0);
        EXPECT_EQ(std::fmod(s->y(), 8.0), 0.0);
      }
  }
}
