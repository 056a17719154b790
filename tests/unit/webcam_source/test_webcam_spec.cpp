// Webcam source specs: every option, the defaults, and for each way a spec
// can be wrong an error naming the field, the spec and the option.
#include <gtest/gtest.h>

#include <string>

#include "earshot/errors.hpp"
#include "../tracker/source_spec_error.hpp"
#include "earshot/tracker/live/source_spec.hpp"

namespace earshot::tracker {
namespace {
using namespace earshot::webcam;  // the webcam module: sources, capture, files, lens

using Beacon = WebcamSpec::Beacon;

using spec_tests::error_of;

TEST(WebcamSpec, DefaultsToTheFirstCameraAndLeds) {
  const SourceSpec s = parse_source_spec("webcam");
  EXPECT_EQ(s.kind, SourceSpec::Kind::webcam);
  EXPECT_FALSE(s.sends_poses());
  EXPECT_EQ(s.webcam.device, "/dev/video0");
  EXPECT_EQ(s.webcam.beacon, Beacon::leds);
  EXPECT_FALSE(s.webcam.focal_px);
  EXPECT_TRUE(s.webcam.calib.empty());
  EXPECT_EQ(s.webcam.max_width, 0);
  EXPECT_EQ(s.webcam.max_fps, 0);
  EXPECT_FALSE(s.webcam.is_file());
}

TEST(WebcamSpec, DevicesByPathNumberOrVideoFile) {
  EXPECT_EQ(parse_source_spec("webcam:/dev/video2").webcam.device, "/dev/video2");
  EXPECT_EQ(parse_source_spec("webcam:3").webcam.device, "/dev/video3");
  EXPECT_EQ(parse_source_spec("webcam:/dev/v4l/by-id/usb-cam-video-index0").webcam.device,
            "/dev/v4l/by-id/usb-cam-video-index0");
  const SourceSpec f = parse_source_spec("webcam:take:1.y4m,beacon=apriltag");
  EXPECT_EQ(f.webcam.device, "take:1.y4m");  // only the first colon splits
  EXPECT_TRUE(f.webcam.is_file());
  EXPECT_EQ(f.webcam.beacon, Beacon::apriltag);
}

TEST(WebcamSpec, EveryOption) {
  const SourceSpec s = parse_source_spec(
      "webcam:1,beacon=apriltag,size_mm=62.5,family=tag25h9,id=7,decimate=1,focal=910.5,calib=cam.yml,resolution=640x480,"
      "fps=60");
  const WebcamSpec& w = s.webcam;
  EXPECT_EQ(w.device, "/dev/video1");
  EXPECT_EQ(w.beacon, Beacon::apriltag);
  EXPECT_DOUBLE_EQ(w.size_mm, 62.5);
  EXPECT_EQ(w.family, "tag25h9");
  EXPECT_EQ(w.id, 7);
  EXPECT_DOUBLE_EQ(w.decimate, 1.0);
  EXPECT_DOUBLE_EQ(parse_source_spec("webcam,beacon=apriltag").webcam.decimate, 2.0) << "the default";
  ASSERT_TRUE(w.focal_px);
  EXPECT_DOUBLE_EQ(*w.focal_px, 910.5);
  EXPECT_EQ(w.calib, "cam.yml");
  EXPECT_EQ(w.max_width, 640);
  EXPECT_EQ(w.max_height, 480);
  EXPECT_EQ(w.max_fps, 60);
  // Options without a device.
  EXPECT_EQ(parse_source_spec("webcam,beacon=leds,fps=30").webcam.max_fps, 30);
  EXPECT_EQ(parse_source_spec("webcam,fps=30").webcam.device, "/dev/video0");
}

TEST(WebcamSpec, BadOptionsNameTheOptionAndTheSpec) {
  EXPECT_EQ(error_of("webcam,beacon=laser", "tracker"),
            "tracker: source 'webcam,beacon=laser': bad beacon 'laser' (leds or apriltag)");
  EXPECT_EQ(error_of("webcam,colour=red"),
            "--source: source 'webcam,colour=red': unknown webcam option 'colour' (beacon, size_mm, family, id, decimate, "
            "focal, calib, resolution, fps)");
  EXPECT_EQ(error_of("webcam,size_mm=60"),
            "--source: source 'webcam,size_mm=60': size_mm, family, id and decimate are for beacon=apriltag (the LED beacon's "
            "shape comes from --model)");
  EXPECT_EQ(error_of("webcam,fps=30,fps=60"), "--source: source 'webcam,fps=30,fps=60': webcam option 'fps' given twice");
  const std::pair<const char*, const char*> bad[] = {
      {"webcam,beacon=apriltag,size_mm=0", "bad size_mm '0'"},
      {"webcam,beacon=apriltag,size_mm=abc", "bad size_mm 'abc'"},
      {"webcam,beacon=apriltag,size_mm=nan", "bad size_mm 'nan'"},
      {"webcam,beacon=apriltag,id=-1", "bad tag id '-1'"},
      {"webcam,beacon=apriltag,id=1.5", "bad tag id '1.5'"},
      {"webcam,beacon=apriltag,decimate=0.5", "bad decimate '0.5'"},
      {"webcam,beacon=apriltag,decimate=9", "bad decimate '9'"},
      {"webcam,focal=0", "bad focal '0'"},
      {"webcam,focal=inf", "bad focal 'inf'"},
      {"webcam,resolution=640", "bad resolution '640'"},
      {"webcam,resolution=640x", "bad resolution '640x'"},
      {"webcam,resolution=8x8", "bad resolution '8x8'"},
      {"webcam,resolution=99999x480", "bad resolution '99999x480'"},
      {"webcam,fps=0", "bad fps '0'"},
      {"webcam,fps=30.5", "bad fps '30.5'"},
      {"webcam,fps=", "webcam option 'fps' has no value"},
      {"webcam,fps", "expected OPTION=VALUE, got 'fps'"},
      {"webcam,", "expected OPTION=VALUE, got ''"},
      {"webcam,=3", "expected OPTION=VALUE, got '=3'"},
      {"webcam:", "empty device after 'webcam:'"},
      {"webcam:,fps=3", "empty device after 'webcam:'"},
      {"webcam:2x", "bad camera number '2x'"},
  };
  for (const auto& [spec, why] : bad) {
    const std::string e = error_of(spec);
    EXPECT_NE(e.find(why), std::string::npos) << spec << " -> " << e;
    EXPECT_NE(e.find(std::string("source '") + spec + "'"), std::string::npos) << e;
  }
}

TEST(WebcamSpec, OtherWordsStartingWithWebcamAreUnknownSources) {
  EXPECT_NE(error_of("webcams").find("unknown source 'webcams'"), std::string::npos);
  EXPECT_NE(error_of("webcam@127.0.0.1").find("unknown source"), std::string::npos);
  // The list of spellings names the webcam's.
  EXPECT_NE(std::string(kSourceSpecs).find("webcam[:DEVICE][,beacon=leds|apriltag]"), std::string::npos);
}

}  // namespace
}  // namespace earshot::tracker
