// The webcam source from a Y4M file with a scripted detector: frames, times,
// notes, the camera model (guessed, focal=, calib=), undistortion, labels,
// sizes, the thumbnail, describe(); a camera that is not there.
#include "earshot/webcam/webcam_source.hpp"
#include "earshot/webcam/y4m_writer.hpp"

#include <gtest/gtest.h>

#include <deque>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "earshot/errors.hpp"
#include "earshot/pose_slot.hpp"
#include "earshot/tracker/live/live_pipeline.hpp"
#include "earshot/tracker/live/live_tracker.hpp"

namespace earshot::tracker {
namespace {
using namespace earshot::webcam;  // the webcam module: sources, capture, files, lens

/// Returns scripted detections in order (none when the script runs out) and
/// remembers the views it was given.
class ScriptedDetector final : public webcam::DotDetector {
 public:
  explicit ScriptedDetector(std::deque<webcam::Detection> script) : script_(std::move(script)) {}
  webcam::Detection detect(const webcam::GrayView& v) override {
    views.push_back({v.width, v.height, static_cast<int>(v.stride), v.pixels.empty() ? -1 : v.pixels[0]});
    if (script_.empty()) return {};
    auto d = script_.front();
    script_.pop_front();
    return d;
  }
  [[nodiscard]] std::string describe() const override { return "scripted"; }
  struct Seen {
    int w, h, stride, first;
  };
  std::vector<Seen> views;

 private:
  std::deque<webcam::Detection> script_;
};

struct TempFile {
  std::filesystem::path path;
  explicit TempFile(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("earshot_ws_" + std::to_string(::getpid()) + "_" + name)) {}
  ~TempFile() { std::filesystem::remove(path); }
};

/// A mono video whose frame i is filled with grey level 10 * (i + 1), with
/// a bright 2x2 square at the top-left corner.
void write_video(const std::filesystem::path& path, int w, int h, int frames, int fps = 30) {
  std::ofstream out(path, std::ios::binary);
  Y4mWriter writer(out, w, h, fps);
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w * h));
  for (int i = 0; i < frames; ++i) {
    std::fill(px.begin(), px.end(), static_cast<std::uint8_t>(10 * (i + 1)));
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) px[static_cast<std::size_t>(y * w + x)] = 250;
    writer.write(px);
  }
}

webcam::Detection corners(bool labelled, double offset = 0.0) {
  webcam::Detection d;
  d.count = 4;
  d.labelled = labelled;
  d.tag_id = labelled ? 3 : -1;
  d.points = {{{100 + offset, 80, 12.4}, {200 + offset, 80, 12.6}, {200 + offset, 180, 30.0}, {100 + offset, 180, 0.2}}};
  return d;
}

WebcamSpec file_spec(const std::filesystem::path& p) {
  WebcamSpec s;
  s.device = p.string();
  return s;
}

WebcamOptions fast() {
  WebcamOptions o;
  o.pacing = Pacing::as_fast_as_possible;
  return o;
}

TEST(WebcamSource, PlaysAVideoThroughTheDetector) {
  TempFile video("play.y4m");
  write_video(video.path, 320, 240, 3, 30);
  auto det = std::make_unique<ScriptedDetector>(std::deque{corners(false), corners(true, 5.0)});
  auto* seen = det.get();
  WebcamSource src(file_spec(video.path), std::move(det), fast());
  EXPECT_EQ(src.describe(), "webcam:" + video.path.string() + " (320x240 @ 30 fps, scripted)");

  auto e = src.next(std::chrono::milliseconds(10));
  auto* note = std::get_if<SourceNote>(&e);
  ASSERT_TRUE(note);
  EXPECT_EQ(note->kind, SourceNote::Kind::connected);
  EXPECT_NE(note->message.find("320x240 @ 30 fps, scripted; focal length guessed (277 px, a 60 deg horizontal field of view)"),
            std::string::npos)
      << note->message;
  EXPECT_NE(note->message.find("focal=PIXELS or calib=FILE"), std::string::npos);

  e = src.next(std::chrono::milliseconds(10));
  auto* f = std::get_if<CameraFrame>(&e);
  ASSERT_TRUE(f);
  EXPECT_DOUBLE_EQ(f->dots.t, 0.0);
  EXPECT_FALSE(f->labelled);
  ASSERT_TRUE(f->dots.slots[2]);
  EXPECT_EQ(*f->dots.slots[2], Vec2(200, 180));  // no calibration: as detected
  EXPECT_EQ(f->dot_size, (std::array<int, 4>{12, 13, 30, 0}));

  e = src.next(std::chrono::milliseconds(10));
  f = std::get_if<CameraFrame>(&e);
  ASSERT_TRUE(f);
  EXPECT_DOUBLE_EQ(f->dots.t, 1.0 / 30.0);
  EXPECT_TRUE(f->labelled);
  EXPECT_EQ(*f->dots.slots[0], Vec2(105, 80));

  e = src.next(std::chrono::milliseconds(10));  // the script ran out: a frame without dots
  f = std::get_if<CameraFrame>(&e);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->dots.visible(), 0);

  e = src.next(std::chrono::milliseconds(10));
  note = std::get_if<SourceNote>(&e);
  ASSERT_TRUE(note);
  EXPECT_EQ(note->kind, SourceNote::Kind::ended);
  EXPECT_EQ(note->message, "video " + video.path.string() + " ended after 3 frames");

  ASSERT_EQ(seen->views.size(), 3u);
  EXPECT_EQ(seen->views[0].w, 320);
  EXPECT_EQ(seen->views[0].h, 240);
  EXPECT_EQ(seen->views[0].stride, 320);
  EXPECT_EQ(seen->views[1].first, 250);

  const auto cam = src.camera();
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->width, 320);
  EXPECT_EQ(cam->height, 240);
  EXPECT_NEAR(cam->fx, 160.0 / std::tan(M_PI / 6), 1e-9);
  EXPECT_FALSE(src.model());  // LEDs: the tracker's own model
}

TEST(WebcamSource, ThumbnailIsTheFrameSmallWithItsDots) {
  TempFile video("thumb.y4m");
  write_video(video.path, 640, 480, 2);
  WebcamSource src(file_spec(video.path), std::make_unique<ScriptedDetector>(std::deque{corners(true)}), fast());
  Thumbnail th;
  EXPECT_FALSE(src.thumbnail(th));  // no frame yet
  (void)src.next(std::chrono::milliseconds(1));  // connected
  (void)src.next(std::chrono::milliseconds(1));
  ASSERT_TRUE(src.thumbnail(th));
  EXPECT_EQ(th.width, 160);
  EXPECT_EQ(th.height, 120);
  EXPECT_EQ(th.frame, 1u);
  EXPECT_TRUE(th.labelled);
  // 4x4 boxes: the corner box holds the 2x2 square (250) and 12 pixels of 10.
  EXPECT_EQ(th.pixels[0], (4 * 250 + 12 * 10) / 16);
  EXPECT_EQ(th.pixels[1], 10);
  ASSERT_TRUE(th.dots[1]);
  EXPECT_NEAR(th.dots[1]->x(), (200 + 0.5) / 4 - 0.5, 1e-12);
  EXPECT_NEAR(th.dots[1]->y(), (80 + 0.5) / 4 - 0.5, 1e-12);
  (void)src.next(std::chrono::milliseconds(1));
  ASSERT_TRUE(src.thumbnail(th));
  EXPECT_EQ(th.frame, 2u);
  EXPECT_EQ(th.pixels[1], 20);
  EXPECT_FALSE(th.dots[0]);

  // A wide frame keeps its aspect.
  TempFile wide("wide.y4m");
  write_video(wide.path, 1280, 720, 1);
  WebcamSource w(file_spec(wide.path), std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}), fast());
  (void)w.next(std::chrono::milliseconds(1));
  (void)w.next(std::chrono::milliseconds(1));
  ASSERT_TRUE(w.thumbnail(th));
  EXPECT_EQ(th.width, 160);
  EXPECT_EQ(th.height, 90);
}

TEST(WebcamSource, FocalAndCalibrationGiveTheCameraModel) {
  TempFile video("calib.y4m");
  write_video(video.path, 640, 480, 1);
  TempFile calib("calib.yml");
  std::ofstream(calib.path) << "%YAML:1.0\n---\nimage_width: 320\nimage_height: 240\n"
                               "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                               "   data: [ 300., 0., 160., 0., 301., 120., 0., 0., 1. ]\n"
                               "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
                               "   data: [ -0.3, 0.1, 0.001, 0.002, 0. ]\n";
  WebcamSpec spec = file_spec(video.path);
  spec.calib = calib.path.string();
  WebcamSource src(spec, std::make_unique<ScriptedDetector>(std::deque{corners(false)}), fast());
  const auto cam = src.camera();
  ASSERT_TRUE(cam);
  EXPECT_DOUBLE_EQ(cam->fx, 600.0);  // calibrated at 320x240, capturing 640x480
  EXPECT_DOUBLE_EQ(cam->fy, 602.0);
  // The ideal camera's image holds every raw pixel's undistorted place: this
  // barrel lens moves the corners out, so it is larger and the principal
  // point moves with its origin.
  const UndistortedImage grown = undistorted_image(load_camera_calibration(calib.path).scaled_to(640, 480, "c"), 640, 480);
  EXPECT_GT(grown.offset.x(), 0.0);
  EXPECT_GT(grown.width, 640);
  EXPECT_GT(grown.height, 480);
  EXPECT_DOUBLE_EQ(cam->cx, 320.5 + grown.offset.x());
  EXPECT_DOUBLE_EQ(cam->cy, 240.5 + grown.offset.y());
  EXPECT_EQ(cam->width, grown.width);
  EXPECT_EQ(cam->height, grown.height);
  auto e = src.next(std::chrono::milliseconds(1));
  EXPECT_NE(std::get<SourceNote>(e).message.find("camera model from " + calib.path.string()), std::string::npos);
  e = src.next(std::chrono::milliseconds(1));
  const auto& f = std::get<CameraFrame>(e);
  const CameraCalibration c = load_camera_calibration(calib.path).scaled_to(640, 480, "c");
  const webcam::Detection sent = corners(false);
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& p = sent.points[k];
    ASSERT_TRUE(f.dots.slots[k]);
    const Vec2 want = c.undistort(Vec2(p.x, p.y)).value() + undistorted_image(c, 640, 480).offset;
    EXPECT_EQ(*f.dots.slots[k], want);
    EXPECT_GT((want - Vec2(p.x, p.y)).norm(), 1.0);  // the lens moved it
  }

  // focal= overrides the file's focal length, keeps its principal point.
  spec.focal_px = 700.0;
  WebcamSource g(spec, std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}), fast());
  EXPECT_DOUBLE_EQ(g.camera()->fx, 700.0);
  EXPECT_DOUBLE_EQ(g.camera()->cx, 320.5 + grown.offset.x());
  // focal= alone: centred principal point, pixel centres at whole numbers:
  // the middle of 640 pixels (0..639) is 319.5.
  WebcamSpec only = file_spec(video.path);
  only.focal_px = 800.0;
  WebcamSource h(only, std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}), fast());
  EXPECT_DOUBLE_EQ(h.camera()->fy, 800.0);
  EXPECT_DOUBLE_EQ(h.camera()->cx, 319.5);
  EXPECT_DOUBLE_EQ(h.camera()->cy, 239.5);
  EXPECT_NE(std::get<SourceNote>(h.next(std::chrono::milliseconds(1))).message.find("focal length 800 px (focal=)"),
            std::string::npos);

  // A calibration of another aspect ratio is refused, naming the file.
  std::ofstream(calib.path) << "%YAML:1.0\nimage_width: 640\nimage_height: 360\n"
                               "camera_matrix: {rows: 3, cols: 3, dt: d, data: [300, 0, 160, 0, 300, 120, 0, 0, 1]}\n";
  try {
    WebcamSource bad(spec, std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}), fast());
    ADD_FAILURE();
  } catch (const InputError& e2) {
    EXPECT_NE(std::string(e2.what()).find(calib.path.string() + ": field 'image_width': calibrated at 640x360"),
              std::string::npos)
        << e2.what();
  }
}

TEST(WebcamSource, TagModelIsTheTagsCornersFacingTheCamera) {
  const LedModel m = tag_model(60.0);
  EXPECT_EQ(m.leds_mm[0], Vec3(-30, -30, 0));
  EXPECT_EQ(m.leds_mm[2], Vec3(30, 30, 0));
  EXPECT_EQ(m.axis, Vec3(0, 0, -1));
  TempFile video("tag.y4m");
  write_video(video.path, 64, 48, 1);
  WebcamSpec spec = file_spec(video.path);
  spec.beacon = WebcamSpec::Beacon::apriltag;
  spec.size_mm = 60.0;
  WebcamSource src(spec, std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}), fast());
  ASSERT_TRUE(src.model());
  EXPECT_EQ(src.model()->leds_mm, m.leds_mm);
}

TEST(WebcamSource, RealTimePacingWaitsForTheFramesTime) {
  TempFile video("paced.y4m");
  write_video(video.path, 32, 24, 2, 1);  // one frame per second
  WebcamSource src(file_spec(video.path), std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}));
  (void)src.next(std::chrono::milliseconds(1));  // connected
  EXPECT_TRUE(std::holds_alternative<CameraFrame>(src.next(std::chrono::milliseconds(1))));  // frame 0 is due at once
  const auto e = src.next(std::chrono::milliseconds(1));  // frame 1 is due a second later
  ASSERT_TRUE(std::holds_alternative<SourceNote>(e));
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::timeout);
}

TEST(WebcamSource, BadVideoFilesAreInputErrors) {
  TempFile video("bad.y4m");
  std::ofstream(video.path) << "YUV4MPEG2 W64 H48 F30:1 C420p10\n";
  EXPECT_THROW(WebcamSource(file_spec(video.path), std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{})),
               InputError);
  EXPECT_THROW(WebcamSource(file_spec("/nonexistent/take.y4m"),
                            std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{})),
               InputError);
}

TEST(WebcamSource, NoCameraThrowsOrKeepsSearching) {
  WebcamSpec spec;
  spec.device = "/dev/video97";
  try {
    WebcamSource src(spec, std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}));
    ADD_FAILURE();
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraError::Kind::no_device);
  }
  WebcamOptions wait;
  wait.wait_for_device = true;
  WebcamSource src(spec, std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}), wait);
  EXPECT_EQ(src.describe(), "webcam:/dev/video97 (not connected, scripted)");
  EXPECT_FALSE(src.camera());
  // The first attempt was made by the constructor; the next comes a retry interval later.
  auto e = src.next(std::chrono::milliseconds(1));
  EXPECT_EQ(std::get<SourceNote>(e).kind, SourceNote::Kind::timeout);
  e = src.next(std::chrono::milliseconds(static_cast<long>(WebcamSource::kRetrySeconds * 1000) + 50));
  if (std::get<SourceNote>(e).kind == SourceNote::Kind::timeout) e = src.next(std::chrono::milliseconds(1));
  const auto& n = std::get<SourceNote>(e);
  EXPECT_EQ(n.kind, SourceNote::Kind::searching);
  EXPECT_EQ(n.message.rfind("no camera at /dev/video97; connected cameras: ", 0), 0u) << n.message;
  // Not a camera at all: also an error before it ever worked.
  spec.device = "/dev/null";
  try {
    WebcamSource s2(spec, std::make_unique<ScriptedDetector>(std::deque<webcam::Detection>{}));
    ADD_FAILURE();
  } catch (const CameraError& e2) {
    EXPECT_EQ(e2.kind(), CameraError::Kind::not_capture);
  }
}

/// The live tracker takes the source's camera: dots at x = 1100 in a
/// 1280x720 video are inside it (the Wii camera is 1024 wide).
TEST(WebcamSource, LiveTrackerUsesTheSourcesCamera) {
  TempFile video("wide_dots.y4m");
  write_video(video.path, 1280, 720, 5);
  std::deque<webcam::Detection> script;
  for (int i = 0; i < 5; ++i) {
    webcam::Detection d;
    d.count = 2;
    d.points = {{{1100, 600, 4}, {1150, 650, 4}, {}, {}}};
    script.push_back(d);
  }
  PoseSlot slot;
  LiveTracker tracker(std::make_unique<WebcamSource>(file_spec(video.path), std::make_unique<ScriptedDetector>(script), fast()),
                      slot);
  while (tracker.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const auto st = tracker.status();
  EXPECT_TRUE(st.error.empty()) << st.error;
  EXPECT_EQ(st.frames, 5u);
  EXPECT_EQ(st.rejected_dots, 0u);
  EXPECT_TRUE(st.camera);
  Thumbnail th;
  ASSERT_TRUE(tracker.thumbnail(th));
  EXPECT_EQ(th.frame, 5u);
  // The same frames against the configured Wii camera would drop every dot.
  LivePipeline wii;
  CameraFrame f;
  f.dots.slots[0] = Vec2(1100, 600);
  (void)wii.process(f, 0.0);
  EXPECT_EQ(wii.counters().rejected_dots, 1u);
}

// A wide lens (k1 = -0.44) moves the raw image's corners ~100 px out. A
// tag near the corner of the view keeps its four corners: the ideal
// camera's image holds where the lens sends them, so the live pipeline
// takes them all (it drops dots outside the camera's image) and solves.
TEST(WebcamSource, ATagNearTheEdgeOfAWideLensKeepsAllFourCorners) {
  TempFile video("wide_lens.y4m");
  write_video(video.path, 640, 480, 1);
  TempFile calib("wide_lens.yml");
  std::ofstream(calib.path) << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                               "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                               "   data: [ 600., 0., 319.5, 0., 600., 239.5, 0., 0., 1. ]\n"
                               "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
                               "   data: [ -0.44, 0.2, 0., 0., 0. ]\n";
  WebcamSpec spec = file_spec(video.path);
  spec.calib = calib.path.string();
  spec.beacon = WebcamSpec::Beacon::apriltag;
  spec.size_mm = 60.0;
  webcam::Detection tag;
  tag.count = 4;
  tag.labelled = true;
  tag.tag_id = 0;
  // Within 35 px of the top-left corner: each undistorts to outside the raw 640x480.
  tag.points = {{{4, 4, 1}, {34, 5, 1}, {33, 34, 1}, {3, 33, 1}}};
  WebcamSource src(spec, std::make_unique<ScriptedDetector>(std::deque{tag}), fast());
  (void)src.next(std::chrono::milliseconds(1));  // connected
  const auto e = src.next(std::chrono::milliseconds(1));
  const auto& f = std::get<CameraFrame>(e);
  const Camera cam = src.camera().value();
  const CameraCalibration lens = load_camera_calibration(calib.path);
  for (std::size_t k = 0; k < 4; ++k) {
    ASSERT_TRUE(f.dots.slots[k]) << "corner " << k << " dropped by the source";
    const Vec2 raw_ideal = lens.undistort(Vec2(tag.points[k].x, tag.points[k].y)).value();
    EXPECT_TRUE(raw_ideal.x() < 0.0 || raw_ideal.y() < 0.0) << "corner " << k << " should leave the raw image";
    EXPECT_TRUE(cam.inside(*f.dots.slots[k])) << "corner " << k << " at " << f.dots.slots[k]->transpose()
                                              << " outside the ideal camera's " << cam.width << "x" << cam.height;
  }
  LivePipeline pipeline(with_source_model(LiveConfig{}, src));
  const auto pose = pipeline.process(e, 0.0);
  EXPECT_EQ(pipeline.counters().rejected_dots, 0u);
  ASSERT_TRUE(pose);
  EXPECT_EQ(pose->state, PoseState::tracking);
}

}  // namespace
}  // namespace earshot::tracker
