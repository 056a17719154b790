// The LED detector on hand-drawn frames: sub-pixel centroids, saturation,
// distractors, exposure changes, degenerate frames and bad views.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <stdexcept>

#include "earshot/webcam/dot_detector.hpp"
#include "frame_drawing.hpp"

namespace earshot::webcam {
namespace {

using testing::Canvas;
using testing::rms_to_nearest;
using Truth = std::vector<std::array<double, 2>>;

/// Four spots at random sub-pixel positions, well apart, in a 320x240 frame.
Truth four_positions(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> frac(0.0, 1.0);
  Truth t;
  const std::array<std::array<int, 2>, 4> base{{{80, 60}, {230, 70}, {90, 180}, {240, 170}}};
  for (const auto& b : base) t.push_back({b[0] + frac(rng), b[1] + frac(rng)});
  return t;
}

TEST(LedDetector, CentroidsOfCleanSpotsAreSubPixel) {
  // Unsaturated spots (sigma 1 px, peak 200) on a flat background: the only
  // error left is 8-bit rounding and the skirt outside the window (below
  // one grey level): a few thousandths of a pixel.
  auto det = make_led_detector();
  std::mt19937_64 rng(1);
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    Canvas c(320, 240, 20.0);
    const Truth t = four_positions(rng);
    for (const auto& p : t) c.spot(p[0], p[1], 1.0, 200.0);
    const Detection d = det->detect(c.view());
    ASSERT_EQ(d.count, 4);
    EXPECT_FALSE(d.labelled);
    EXPECT_EQ(d.tag_id, -1);
    worst = std::max(worst, rms_to_nearest(d, t));
  }
  std::printf("clean spots: worst RMS %.4f px\n", worst);
  EXPECT_LT(worst, 0.02);
}

TEST(LedDetector, SaturatedSpotsStillCentroidWell) {
  // Peak 3000 clipped at 255: a flat top ~4 px across; the skirt carries the
  // sub-pixel position.
  auto det = make_led_detector();
  std::mt19937_64 rng(2);
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    Canvas c(320, 240, 20.0);
    const Truth t = four_positions(rng);
    for (const auto& p : t) c.spot(p[0], p[1], 1.5, 3000.0);
    const GrayView v = c.view();
    int saturated = 0;
    for (auto b : c.bytes) saturated += b == 255;
    ASSERT_GT(saturated, 4 * 9);  // the tops really are flat
    const Detection d = det->detect(v);
    ASSERT_EQ(d.count, 4);
    worst = std::max(worst, rms_to_nearest(d, t));
    for (int i = 0; i < 4; ++i) EXPECT_GT(d.points[static_cast<size_t>(i)].size, 9.0);
  }
  std::printf("saturated spots: worst RMS %.4f px\n", worst);
  EXPECT_LT(worst, 0.05);
}

TEST(LedDetector, NoisyTexturedFrame) {
  // Read + shot noise (sigma ~3 grey levels) on a textured background: the
  // centroid error follows the noise over the spot's flux.
  auto det = make_led_detector();
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  double sum2 = 0.0;
  int count = 0;
  for (int trial = 0; trial < 50; ++trial) {
    Canvas c(320, 240, 0.0);
    for (int y = 0; y < 240; ++y)
      for (int x = 0; x < 320; ++x) c.at(x, y) = 25.0 + 10.0 * std::sin(x / 17.0) * std::cos(y / 23.0);
    const Truth t = four_positions(rng);
    for (const auto& p : t) c.spot(p[0], p[1], 1.2, 600.0);
    for (double& p : c.v) p += std::sqrt(0.08 * p + 2.25) * n(rng);
    const Detection d = det->detect(c.view());
    ASSERT_EQ(d.count, 4);
    const double r = rms_to_nearest(d, t);
    sum2 += r * r;
    ++count;
  }
  const double rms = std::sqrt(sum2 / count);
  std::printf("noisy spots: RMS %.4f px\n", rms);
  EXPECT_LT(rms, 0.1);
}

TEST(LedDetector, ALampBiggerThanAnLedIsRejected) {
  Canvas c(320, 240, 20.0);
  std::mt19937_64 rng(4);
  const Truth t = four_positions(rng);
  for (const auto& p : t) c.spot(p[0], p[1], 1.2, 400.0);
  c.disc(160.0, 120.0, 32.0, 2000.0);  // ~3200 px saturated, far more light than the LEDs
  auto det = make_led_detector();
  const Detection d = det->detect(c.view());
  ASSERT_EQ(d.count, 4);
  EXPECT_LT(rms_to_nearest(d, t), 0.05);
  for (int i = 0; i < 4; ++i) EXPECT_GT(std::hypot(d.points[static_cast<size_t>(i)].x - 160.0, d.points[static_cast<size_t>(i)].y - 120.0), 40.0);
}

TEST(LedDetector, AFifthDimmerBlobIsNotChosen) {
  auto det = make_led_detector();
  Canvas c(320, 240, 20.0);
  std::mt19937_64 rng(5);
  const Truth t = four_positions(rng);
  for (const auto& p : t) c.spot(p[0], p[1], 1.2, 400.0);
  c.spot(160.3, 120.6, 0.8, 120.0);  // a small dim reflection
  Detection d = det->detect(c.view());
  ASSERT_EQ(d.count, 4);
  EXPECT_LT(rms_to_nearest(d, t), 0.05);
  for (size_t i = 0; i < 4; ++i) EXPECT_GT(std::hypot(d.points[i].x - 160.3, d.points[i].y - 120.6), 10.0);
  // The reflection alone is found when the LEDs are gone: it was seen, and lost on brightness.
  Canvas only(320, 240, 20.0);
  only.spot(160.3, 120.6, 0.8, 120.0);
  d = det->detect(only.view());
  ASSERT_EQ(d.count, 1);
  EXPECT_NEAR(d.points[0].x, 160.3, 0.05);
  EXPECT_NEAR(d.points[0].y, 120.6, 0.05);
}

TEST(LedDetector, ExposureChangesKeepTheSpots) {
  // The threshold follows the frame: the same scene at a third and at twice
  // the exposure (background 20 -> 7 and 40) gives the same four spots.
  auto det = make_led_detector();
  std::mt19937_64 rng(6);
  const Truth t = four_positions(rng);
  for (const double g : {0.33, 1.0, 2.0}) {
    Canvas c(320, 240, 20.0);
    for (const auto& p : t) c.spot(p[0], p[1], 1.2, 250.0);
    c.scale(g);
    const Detection d = det->detect(c.view());
    ASSERT_EQ(d.count, 4) << "gain " << g;
    EXPECT_LT(rms_to_nearest(d, t), 0.06) << "gain " << g;
  }
}

TEST(LedDetector, DegenerateFramesFindNothing) {
  auto det = make_led_detector();
  EXPECT_EQ(det->detect(GrayView{}).count, 0);
  std::vector<std::uint8_t> none;
  EXPECT_EQ(det->detect(GrayView{none, 0, 10, 0}).count, 0);
  for (const std::uint8_t level : {std::uint8_t{0}, std::uint8_t{255}, std::uint8_t{128}})
    for (const auto& size : std::vector<std::array<int, 2>>{{1, 1}, {2, 3}, {3, 3}, {7, 5}, {640, 480}}) {
      std::vector<std::uint8_t> px(static_cast<size_t>(size[0] * size[1]), level);
      EXPECT_EQ(det->detect(GrayView{px, size[0], size[1], size[0]}).count, 0)
          << int(level) << " " << size[0] << "x" << size[1];
    }
  // A single bright pixel in a tiny frame is still an LED.
  std::vector<std::uint8_t> px(25, 10);
  px[12] = 200;
  const Detection d = det->detect(GrayView{px, 5, 5, 5});
  ASSERT_EQ(d.count, 1);
  EXPECT_DOUBLE_EQ(d.points[0].x, 2.0);
  EXPECT_DOUBLE_EQ(d.points[0].y, 2.0);
  EXPECT_DOUBLE_EQ(d.points[0].size, 1.0);
}

TEST(LedDetector, PaddedRowsAndChangingSizes) {
  // A stride beyond the width: the padding (bright here) is not image.
  auto det = make_led_detector();
  std::mt19937_64 rng(7);
  const Truth t = four_positions(rng);
  Canvas c(320, 240, 20.0);
  for (const auto& p : t) c.spot(p[0], p[1], 1.2, 300.0);
  const GrayView packed = c.view();
  const Detection a = det->detect(packed);
  const int stride = 352;
  std::vector<std::uint8_t> padded(static_cast<size_t>(stride) * 239 + 320, 255);
  for (int y = 0; y < 240; ++y)
    std::copy_n(c.bytes.begin() + y * 320, 320, padded.begin() + static_cast<std::ptrdiff_t>(y) * stride);
  // A smaller frame in between: the scratch buffers follow the size.
  Canvas small(64, 48, 20.0);
  small.spot(30.25, 20.75, 1.0, 200.0);
  const Detection s = det->detect(small.view());
  ASSERT_EQ(s.count, 1);
  EXPECT_NEAR(s.points[0].x, 30.25, 0.02);
  const Detection b = det->detect(GrayView{padded, 320, 240, stride});
  ASSERT_EQ(a.count, 4);
  ASSERT_EQ(b.count, 4);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(a.points[i].x, b.points[i].x);
    EXPECT_DOUBLE_EQ(a.points[i].y, b.points[i].y);
  }
}

TEST(LedDetector, BadViewsThrow) {
  auto det = make_led_detector();
  std::vector<std::uint8_t> px(100, 0);
  EXPECT_THROW((void)det->detect(GrayView{px, -1, 10, 10}), std::invalid_argument);
  EXPECT_THROW((void)det->detect(GrayView{px, 10, -1, 10}), std::invalid_argument);
  EXPECT_THROW((void)det->detect(GrayView{px, 10, 10, 9}), std::invalid_argument);   // stride < width
  EXPECT_THROW((void)det->detect(GrayView{px, 10, 11, 10}), std::invalid_argument);  // span too short
  EXPECT_THROW((void)det->detect(GrayView{px, 10, 10, 11}), std::invalid_argument);  // 109 bytes needed
  EXPECT_NO_THROW((void)det->detect(GrayView{px, 10, 10, 10}));
  EXPECT_NO_THROW((void)det->detect(GrayView{px, 9, 10, 10}));  // 99 bytes: fits
  try {
    (void)det->detect(GrayView{px, 10, 11, 10});
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("10x11"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)make_led_detector(LedOptions{10.0, 5.0}), std::invalid_argument);
}

TEST(LedDetector, PureNoiseFindsNothing) {
  auto det = make_led_detector();
  std::mt19937_64 rng(8);
  std::normal_distribution<double> n(30.0, 3.0);
  Canvas c(640, 480, 0.0);
  for (double& p : c.v) p = n(rng);
  EXPECT_EQ(det->detect(c.view()).count, 0);
  EXPECT_EQ(det->describe(), "leds");
}

}  // namespace
}  // namespace earshot::webcam
