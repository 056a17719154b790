// V4L2 capture without a camera: every error a person can meet names the
// device and says what to do; the mode choice; the device list.
#include "earshot/webcam/v4l2_camera.hpp"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <cerrno>
#include <filesystem>
#include <fstream>

#include <unistd.h>
#include "../scratch_path.hpp"

namespace earshot::tracker {
namespace {
using namespace earshot::webcam;  // the webcam module: sources, capture, files, lens

using Kind = CameraError::Kind;

CameraError open_error(const std::string& device) {
  try {
    V4l2Camera cam(device);
  } catch (const CameraError& e) {
    return e;
  }
  ADD_FAILURE() << device << " opened";
  return CameraError(Kind::io, "");
}

TEST(V4l2Camera, NoSuchDeviceListsTheCamerasThereAre) {
  const CameraError e = open_error("/dev/video97");
  EXPECT_EQ(e.kind(), Kind::no_device);
  EXPECT_EQ(std::string(e.what()).rfind("no camera at /dev/video97; connected cameras: ", 0), 0u) << e.what();
  EXPECT_EQ(camera_open_error("/dev/video0", ENOENT, {}).what(),
            std::string("no camera at /dev/video0; connected cameras: none (is it plugged in? `v4l2-ctl "
                        "--list-devices` lists them)"));
  EXPECT_EQ(camera_open_error("/dev/video0", ENODEV, {"/dev/video2", "/dev/video3"}).what(),
            std::string("no camera at /dev/video0; connected cameras: /dev/video2, /dev/video3"));
}

TEST(V4l2Camera, BusyAndPermissionNameTheFix) {
  const CameraError busy = camera_open_error("/dev/video0", EBUSY, {});
  EXPECT_EQ(busy.kind(), Kind::busy);
  EXPECT_STREQ(busy.what(), "/dev/video0 is busy: another program is using the camera (close it; `fuser /dev/video0` "
                            "shows which)");
  const CameraError perm = camera_open_error("/dev/video1", EACCES, {});
  EXPECT_EQ(perm.kind(), Kind::permission);
  EXPECT_STREQ(perm.what(), "no permission to open /dev/video1: the user is not in the 'video' group (run `sudo usermod "
                            "-aG video $USER`, then log out and in again)");
  EXPECT_EQ(camera_open_error("/dev/video1", EPERM, {}).kind(), Kind::permission);
  EXPECT_EQ(camera_open_error("/dev/video1", EIO, {}).kind(), Kind::io);
}

TEST(V4l2Camera, PermissionDeniedFromARealOpen) {
  if (::geteuid() == 0) GTEST_SKIP() << "root opens any file: EACCES cannot happen";
  const auto path = earshot::test::scratch_path("video_noperm");
  std::ofstream(path) << "x";
  std::filesystem::permissions(path, std::filesystem::perms::none);
  const CameraError e = open_error(path.string());
  EXPECT_EQ(e.kind(), Kind::permission) << e.what();
  std::filesystem::remove(path);
}

TEST(V4l2Camera, DevicesThatAreNotCamerasAreRefused) {
  const CameraError null = open_error("/dev/null");
  EXPECT_EQ(null.kind(), Kind::not_capture);
  EXPECT_EQ(std::string(null.what()).rfind("/dev/null is not a video device", 0), 0u) << null.what();
  const auto path = earshot::test::scratch_path("video_file");
  std::ofstream(path) << "not a camera";
  const CameraError file = open_error(path.string());
  EXPECT_EQ(file.kind(), Kind::not_capture) << file.what();
  EXPECT_NE(std::string(file.what()).find(path.string() + " is not a video device"), std::string::npos);
  std::filesystem::remove(path);
}

TEST(V4l2Camera, ListsVideoDevicesInNumberOrder) {
  const auto dir = earshot::test::scratch_path("dev");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* n : {"video10", "video2", "video0", "videox", "video", "audio1", "video3a"}) std::ofstream(dir / n);
  const auto list = list_video_devices(dir);
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0], (dir / "video0").string());
  EXPECT_EQ(list[1], (dir / "video2").string());
  EXPECT_EQ(list[2], (dir / "video10").string());
  std::filesystem::remove_all(dir);
  EXPECT_TRUE(list_video_devices(dir).empty());
}

TEST(V4l2Camera, ChoosesTheFastestModeWithinTheLimits) {
  const auto M = [](int w, int h, int fps) { return CaptureMode{V4L2_PIX_FMT_MJPEG, w, h, 1, fps}; };
  const std::vector<CaptureMode> offered = {M(1920, 1080, 30), M(1280, 720, 30), M(1280, 720, 60), M(640, 480, 30),
                                            M(640, 480, 60), M(640, 480, 120), M(320, 240, 120)};
  auto m = choose_capture_mode(offered, 1280, 720, 0);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->width, 640);  // 120 fps wins; the larger of the two 120 fps sizes
  EXPECT_DOUBLE_EQ(m->fps(), 120.0);
  m = choose_capture_mode(offered, 1280, 720, 60);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->width, 1280);
  EXPECT_DOUBLE_EQ(m->fps(), 60.0);
  m = choose_capture_mode(offered, 1920, 1080, 30);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->width, 1920);
  EXPECT_FALSE(choose_capture_mode(offered, 300, 200, 0));
  EXPECT_FALSE(choose_capture_mode({}, 1280, 720, 0));
  // 30000/1001 is 29.97 fps, under a 30 fps limit.
  const CaptureMode ntsc{V4L2_PIX_FMT_YUYV, 640, 480, 1001, 30000};
  EXPECT_TRUE(choose_capture_mode(std::span(&ntsc, 1), 640, 480, 30));
  EXPECT_EQ(fourcc_name(V4L2_PIX_FMT_MJPEG), "MJPG");
}

}  // namespace
}  // namespace earshot::tracker
