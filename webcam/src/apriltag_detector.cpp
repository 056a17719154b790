// The AprilTag detector: libapriltag finds and decodes the tag; its corners,
// relabelled as the printed tag's (top-left first, clockwise as seen), are
// the beacon's four labelled points.
#include <apriltag/apriltag.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "earshot/webcam/dot_detector.hpp"
#include "tag_families.hpp"
#include "view_check.hpp"

namespace earshot::webcam {
namespace {

// libapriltag's p[k] wrap the tag counter-clockwise in its own tag frame
// (the homography maps (-1, 1), (1, 1), (1, -1), (-1, -1) to p[0..3]); in
// the image, y down, with the tag upright as printed, p[0] is the
// bottom-left corner, p[1] bottom-right, p[2] top-right, p[3] top-left
// (measured on rendered tags: tests/unit/webcam/test_apriltag_detector.cpp).
// Label k (tag_corners_mm) takes p[kLabelToCorner[k]].
constexpr int kLabelToCorner[4] = {3, 2, 1, 0};
// libapriltag's corners (line fit, then its edge refinement) sit on average
// this far below-right of ours (pixel centres at integers): +0.51 px on
// rendered tags (supersampled, blurred: what a camera gives), +0.39 on
// sharp whole-pixel ones (tests/unit/webcam measure both).
constexpr double kCentreShift = -0.5;
// Smaller frames cannot hold a decodable tag (its quads need room).
constexpr int kMinSide = 8;

struct DetectorDeleter {
  void operator()(apriltag_detector_t* d) const { apriltag_detector_destroy(d); }
};
struct DetectionsDeleter {
  void operator()(zarray_t* z) const { apriltag_detections_destroy(z); }
};

class AprilTagDetector final : public DotDetector {
 public:
  explicit AprilTagDetector(const AprilTagOptions& o) : opt_(o), family_(detail::create_family(o.family)) {
    if (o.id < -1 || (o.id >= 0 && static_cast<std::uint32_t>(o.id) >= family_->ncodes))
      throw std::invalid_argument("AprilTag family " + o.family + " has ids 0.." + std::to_string(family_->ncodes - 1) +
                                  " (or -1 for any), not " + std::to_string(o.id));
    if (!(o.decimate >= 1.0f) || !std::isfinite(o.decimate))
      throw std::invalid_argument("AprilTag decimate must be >= 1, not " + std::to_string(o.decimate));
    detector_.reset(apriltag_detector_create());
    if (!detector_) throw std::runtime_error("libapriltag could not create a detector");
    apriltag_detector_add_family(detector_.get(), family_.get());
    detector_->quad_decimate = o.decimate;
    detector_->nthreads = 1;
    detector_->refine_edges = true;
    // Blurs only the image the quads are segmented in (the corners are
    // refined on the frame itself): sensor noise otherwise breaks the
    // segmentation into many small pieces, 3x the time at 1280x720.
    detector_->quad_sigma = 0.8f;
    describe_ = "apriltag " + o.family + (o.id >= 0 ? " id " + std::to_string(o.id) : " any id");
  }

  // The detector holds the family (libapriltag does not own it): detector first.
  ~AprilTagDetector() override { detector_.reset(); }
  AprilTagDetector(const AprilTagDetector&) = delete;
  AprilTagDetector& operator=(const AprilTagDetector&) = delete;

  Detection detect(const GrayView& frame) override {
    Detection out;
    out.labelled = true;
    if (!detail::check_view(frame) || frame.width < kMinSide || frame.height < kMinSide) return out;
    // libapriltag takes a mutable image: a packed copy in our own buffer
    // (reused while the size stays).
    const auto w = static_cast<size_t>(frame.width), h = static_cast<size_t>(frame.height);
    if (copy_.size() != w * h) copy_.assign(w * h, 0);
    for (size_t y = 0; y < h; ++y)
      std::memcpy(copy_.data() + y * w, frame.pixels.data() + static_cast<std::ptrdiff_t>(y) * frame.stride, w);
    image_u8_t im{frame.width, frame.height, frame.width, copy_.data()};
    const std::unique_ptr<zarray_t, DetectionsDeleter> found(apriltag_detector_detect(detector_.get(), &im));
    if (!found) return out;
    const apriltag_detection_t* best = nullptr;
    for (int i = 0; i < zarray_size(found.get()); ++i) {
      apriltag_detection_t* d = nullptr;
      zarray_get(found.get(), i, &d);
      if (!d || (opt_.id >= 0 && d->id != opt_.id) || !plausible(*d, frame.width, frame.height)) continue;
      if (!best || d->decision_margin > best->decision_margin) best = d;
    }
    if (!best) return out;
    double side = 0.0;
    for (int k = 0; k < 4; ++k) {
      const double* a = best->p[k];
      const double* b = best->p[(k + 1) % 4];
      side += std::hypot(b[0] - a[0], b[1] - a[1]) / 4.0;
    }
    for (int k = 0; k < 4; ++k) {
      const double* c = best->p[kLabelToCorner[k]];
      out.points[static_cast<size_t>(k)] = {c[0] + kCentreShift, c[1] + kCentreShift, side};
    }
    out.count = 4;
    out.tag_id = best->id;
    return out;
  }

  [[nodiscard]] std::string describe() const override { return describe_; }

 private:
  /// A quad a printed tag can make: strictly convex, and every corner within
  /// two pixels of the frame (a tag whose bits were all read lies in view;
  /// libapriltag extrapolates corners from the edges, so a near-degenerate
  /// quad decoded from noise can put one hundreds of pixels away: found by
  /// fuzz_dot_detector).
  static bool plausible(const apriltag_detection_t& d, int width, int height) {
    constexpr double kMargin = 2.0;
    double sign = 0.0;
    for (int k = 0; k < 4; ++k) {
      const double* a = d.p[k];
      const double* b = d.p[(k + 1) % 4];
      const double* c = d.p[(k + 2) % 4];
      if (!std::isfinite(a[0]) || !std::isfinite(a[1])) return false;
      const double x = a[0] + kCentreShift, y = a[1] + kCentreShift;  // as reported
      if (x < -kMargin || y < -kMargin || x > width - 1 + kMargin || y > height - 1 + kMargin) return false;
      const double cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
      if (cross == 0.0 || (sign != 0.0 && (cross > 0.0) != (sign > 0.0))) return false;
      sign = cross;
    }
    return true;
  }

  AprilTagOptions opt_;
  detail::FamilyPtr family_;
  std::unique_ptr<apriltag_detector_t, DetectorDeleter> detector_;
  std::vector<std::uint8_t> copy_;
  std::string describe_;
};

}  // namespace

std::unique_ptr<DotDetector> make_apriltag_detector(const AprilTagOptions& options) {
  return std::make_unique<AprilTagDetector>(options);
}

}  // namespace earshot::webcam
