// esGetTrackerImage (ABI 1.3): a webcam source playing a rendered Y4M video
// (the renderer `earshot track simulate-video` uses) gives the host the
// video's frame, box-downscaled to the thumbnail, with the tag's corners
// where the projected truth puts them; sources without a picture (the
// simulator, a webcam not plugged in) say so;
// bad arguments are refused as esGetTrackerState refuses them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "earshot/earshot.h"
#include "earshot/webcam/video_sim.hpp"
#include "earshot/webcam/y4m_writer.hpp"
#include "tracker_world.hpp"

namespace {

namespace webcam = earshot::webcam;

using World = earshot::plugin_tests::TrackerWorld;

/// A short AprilTag video, kept in memory as well as written.
struct Video {
  webcam::VideoSimConfig cfg;
  std::vector<webcam::VideoFrame> frames;
  std::string path;
};

Video render_video(int frames) {
  Video v;
  v.cfg.beacon = webcam::BeaconKind::apriltag;
  v.cfg.width = 640, v.cfg.height = 480, v.cfg.fps = 30.0;
  v.cfg.tag_size_mm = 80.0;
  v.cfg.seed = 7;
  v.path = (std::filesystem::temp_directory_path() /
            ("earshot_tracker_image_" + std::to_string(::getpid()) + ".y4m"))
               .string();
  webcam::VideoSimulator sim(v.cfg);
  webcam::Y4mWriter out(v.path, v.cfg.width, v.cfg.height, 30);
  for (int i = 0; i < frames; ++i) {
    v.frames.push_back(sim.next());
    out.write(v.frames.back().pixels);
  }
  out.close();
  return v;
}

TEST(TrackerImage, WebcamVideoFrameDownscaledWithItsDots) {
  constexpr int kFrames = 6;
  const Video v = render_video(kFrames);
  World t;
  const std::string spec = "webcam:" + v.path + ",beacon=apriltag,size_mm=80";
  ASSERT_EQ(esAttachTracker(t.w, spec.c_str()), ES_OK) << esGetErrorMessage(t.w);

  // The last frame's picture stays after the video ended (the tracker holds).
  std::unique_ptr<EStrackerimage> im;
  for (int i = 0; i < 1000; ++i) {
    im = t.image();
    if (im->available && im->frame == kFrames) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::filesystem::remove(v.path);
  ASSERT_TRUE(im->available);
  ASSERT_EQ(im->frame, ESuint{kFrames});
  EXPECT_EQ(im->camera_width, 640u);
  EXPECT_EQ(im->camera_height, 480u);
  ASSERT_EQ(im->width, 160u);  // 640x480 fits 160x120 at a quarter
  ASSERT_EQ(im->height, 120u);
  EXPECT_NEAR(im->time, (kFrames - 1) / 30.0, 1e-9);

  // The picture is the frame's 4x4 boxes averaged (to a level of rounding).
  const webcam::VideoFrame& f = v.frames.back();
  double frame_sum = 0, thumb_sum = 0;
  int worst = 0;
  for (int ty = 0; ty < 120; ++ty)
    for (int tx = 0; tx < 160; ++tx) {
      int box = 0;
      for (int y = 4 * ty; y < 4 * ty + 4; ++y)
        for (int x = 4 * tx; x < 4 * tx + 4; ++x) box += f.pixels[std::size_t(y * 640 + x)];
      const int got = im->pixels[ty * 160 + tx];
      worst = std::max(worst, std::abs(got - box / 16));
      thumb_sum += got;
    }
  for (auto p : f.pixels) frame_sum += p;
  const double frame_mean = frame_sum / (640.0 * 480.0), thumb_mean = thumb_sum / (160.0 * 120.0);
  std::printf("frame mean %.2f, thumbnail mean %.2f, worst pixel off its box by %d\n", frame_mean, thumb_mean, worst);
  EXPECT_NEAR(thumb_mean, frame_mean, 1.0);
  EXPECT_LE(worst, 1);
  // The rest of the buffer is zero (nothing left from before).
  for (std::size_t i = 160 * 120; i < sizeof im->pixels; ++i) ASSERT_EQ(im->pixels[i], 0);

  // The tag's corners, labelled, where the truth projects them (scaled by a
  // quarter, pixel centres kept: (p + 0.5) / 4 - 0.5).
  ASSERT_EQ(im->dot_count, 4u) << "the tag was not found in the last frame";
  for (ESuint i = 0; i < im->dot_count; ++i) {
    const EStrackerimagedot& d = im->dots[i];
    ASSERT_GE(d.label, 0);
    ASSERT_LT(d.label, 4);
    const auto& truth = f.points[std::size_t(d.label)];
    ASSERT_TRUE(truth.has_value());
    const double ex = (truth->x() + 0.5) / 4.0 - 0.5, ey = (truth->y() + 0.5) / 4.0 - 0.5;
    std::printf("corner %d: (%.2f, %.2f), truth (%.2f, %.2f) thumbnail px\n", d.label, double(d.x), double(d.y), ex, ey);
    EXPECT_NEAR(d.x, ex, 0.5);
    EXPECT_NEAR(d.y, ey, 0.5);
  }
}

TEST(TrackerImage, SourcesWithoutAPicture) {
  World t;
  auto im = t.image();  // no tracker
  EXPECT_EQ(im->available, ES_FALSE);
  EXPECT_EQ(im->camera_width, 0u);
  EXPECT_EQ(im->width, 0u);

  ASSERT_EQ(esAttachTracker(t.w, "sim"), ES_OK) << esGetErrorMessage(t.w);
  // The simulator runs (frames arrive), yet it has dots only: the Wii camera's.
  for (int i = 0; i < 300; ++i) {
    EStrackerstate s{};
    s.size = sizeof s;
    ASSERT_EQ(esGetTrackerState(t.w, &s), ES_OK);
    if (s.frames > 3) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  im = t.image();
  EXPECT_EQ(im->available, ES_FALSE);
  EXPECT_EQ(im->camera_width, ESuint{ES_CAMERA_WIDTH});
  EXPECT_EQ(im->camera_height, ESuint{ES_CAMERA_HEIGHT});
  EXPECT_EQ(im->width, 0u);
  EXPECT_EQ(im->dot_count, 0u);

  // A webcam that is not there (yet): no picture, and no size to scale by.
  ASSERT_EQ(esAttachTracker(t.w, "webcam:/dev/video97"), ES_OK) << esGetErrorMessage(t.w);
  im = t.image();
  EXPECT_EQ(im->available, ES_FALSE);
  EXPECT_EQ(im->camera_width, 0u);
  EXPECT_EQ(im->camera_height, 0u);
}

TEST(TrackerImage, Misuse) {
  World t;
  EXPECT_EQ(esGetTrackerImage(t.w, nullptr), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("NULL"), std::string::npos);
  auto im = std::make_unique<EStrackerimage>();
  im->size = sizeof(EStrackerimage) - 4;  // an older, smaller struct
  EXPECT_EQ(esGetTrackerImage(t.w, im.get()), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("sizeof(EStrackerimage)"), std::string::npos);
  im->size = sizeof(EStrackerimage);
  EXPECT_EQ(esGetTrackerImage(0, im.get()), ES_INVALID_WORLD);
  ESworld gone = t.w;
  esDestroyWorld(t.w);
  t.w = 0;
  EXPECT_EQ(esGetTrackerImage(gone, im.get()), ES_INVALID_WORLD);
  // From another thread than the control thread.
  World u;
  ESenum from_other = ES_OK;
  std::thread([&] { from_other = esGetTrackerImage(u.w, im.get()); }).join();
  EXPECT_EQ(from_other, ES_WRONG_THREAD);
}

}  // namespace
