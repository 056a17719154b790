// The webcam source with the detector its spec asks for (kept apart from
// the source itself so tests can give the source a detector of their own).
#include <stdexcept>

#include "earshot/errors.hpp"
#include "earshot/webcam/webcam_source.hpp"

namespace earshot::webcam {

std::unique_ptr<tracker::FrameSource> make_webcam_source(const WebcamSpec& spec, const WebcamOptions& options) {
  std::unique_ptr<DotDetector> detector;
  if (spec.beacon == WebcamSpec::Beacon::apriltag) {
    AprilTagOptions a;
    a.family = spec.family;
    a.id = spec.id;
    a.decimate = static_cast<float>(spec.decimate);
    try {
      detector = make_apriltag_detector(a);
    } catch (const std::invalid_argument& e) {
      throw InputError::at("webcam", 0, "family", e.what());
    }
  } else {
    detector = make_led_detector();
  }
  return std::make_unique<WebcamSource>(spec, std::move(detector), options);
}

}  // namespace earshot::webcam
