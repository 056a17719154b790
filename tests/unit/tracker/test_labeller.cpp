#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "earshot/tracker/track/labeller.hpp"
#include "random_poses.hpp"

using namespace earshot::tracker;

TEST(Labeller, AcquiresEverySlotOrderAtAnyRoll) {
  std::mt19937_64 rng(17);
  const Camera cam;
  const LedModel model;
  const Labeller labeller(cam, model);
  int poses = 0;
  for (int i = 0; i < 60; ++i) {
    const Pose truth = fixtures::random_visible_pose(rng, cam, model);
    std::array<int, 4> order{0, 1, 2, 3};
    int orders = 0;
    do {
      const DotFrame f = fixtures::frame_of(truth, cam, model, order);
      const auto hyps = labeller.acquire(f);
      ASSERT_FALSE(hyps.empty()) << "pose " << i;
      // The best hypothesis is the truth (noise-free dots fit it exactly).
      EXPECT_EQ(hyps.front().slot_led, order) << "pose " << i << " order " << orders;
      EXPECT_LT(rotation_angle_between(hyps.front().pose.R, truth.R), 1e-6);
      ++orders;
    } while (std::next_permutation(order.begin(), order.end()));
    EXPECT_EQ(orders, 24);
    ++poses;
  }
  EXPECT_EQ(poses, 60);
}

TEST(Labeller, FollowsThroughSlotSwapsAndThreeDots) {
  std::mt19937_64 rng(19);
  const Camera cam;
  const LedModel model;
  const Labeller labeller(cam, model);
  for (int i = 0; i < 200; ++i) {
    const Pose truth = fixtures::random_visible_pose(rng, cam, model);
    const Pose predicted{exp_so3(Vec3(0.01, 0.01, -0.02)) * truth.R, truth.t + Vec3(4, -4, 10)};
    std::array<int, 4> order{3, 1, 0, 2};
    if (i % 2) order[static_cast<size_t>(i % 4)] = -1;  // one LED unseen
    const auto l = labeller.follow(fixtures::frame_of(truth, cam, model, order), predicted);
    ASSERT_TRUE(l.has_value());
    EXPECT_EQ(l->slot_led, order);
  }
}

TEST(Labeller, RejectsDotsThatDoNotFitTheModel) {
  // Four dots in a square: no pose of the thesis beacon projects to it.
  const Camera cam;
  const LedModel model;
  const Labeller labeller(cam, model);
  DotFrame f;
  f.slots = {Vec2(400, 300), Vec2(600, 300), Vec2(600, 500), Vec2(400, 500)};
  EXPECT_TRUE(labeller.acquire(f).empty());
}

TEST(ThesisLabeller, LabelsAnUprightBeaconInAnySlotOrder) {
  const Camera cam;
  const LedModel model;
  const Pose upright{rotation_from_ypr(0.2, -0.1, 0.05), Vec3(30, -20, 1100)};
  std::array<int, 4> order{0, 1, 2, 3};
  do {
    ThesisLabeller tl;
    const auto dots = tl.label(fixtures::frame_of(upright, cam, model, order));
    ASSERT_TRUE(dots.has_value());
    for (const auto& c : dots->view())
      EXPECT_LT((c.pixel - cam.project(upright.apply(model.leds_mm[static_cast<size_t>(c.led)]))).norm(), 1e-9);
  } while (std::next_permutation(order.begin(), order.end()));
}
