#include "opencv_pnp.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <vector>

namespace earshot::bench {

OpenCvPnp::OpenCvPnp(const tracker::Camera& cam, const tracker::LedModel& model, CvMethod m)
    : cam_(cam), model_(model), method_(m) {}

std::optional<tracker::Pose> OpenCvPnp::solve(std::span<const tracker::Correspondence> dots) {
  std::vector<cv::Point3d> obj;
  std::vector<cv::Point2d> img;
  for (const auto& d : dots) {
    const auto& p = model_.leds_mm[static_cast<size_t>(d.led)];
    obj.emplace_back(p.x(), p.y(), p.z());
    img.emplace_back(d.pixel.x(), d.pixel.y());
  }
  const cv::Matx33d K(cam_.fx, 0, cam_.cx, 0, cam_.fy, cam_.cy, 0, 0, 1);
  cv::Mat rvec(3, 1, CV_64F, rvec_), tvec(3, 1, CV_64F, tvec_);
  bool ok = false;
  try {
    if (method_ == CvMethod::iterative && have_prev_) {
      ok = cv::solvePnP(obj, img, K, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE);
    } else {
      ok = cv::solvePnP(obj, img, K, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_SQPNP);
      if (ok && method_ == CvMethod::sqpnp_refine) cv::solvePnPRefineLM(obj, img, K, cv::noArray(), rvec, tvec);
    }
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok || !cv::checkRange(rvec) || !cv::checkRange(tvec)) {
    have_prev_ = false;
    return std::nullopt;
  }
  have_prev_ = true;
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  tracker::Pose p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p.R(r, c) = R(r, c);
    p.t[r] = tvec_[r];
  }
  return p;
}

}  // namespace earshot::bench
