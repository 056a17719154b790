// OpenCV's solvePnP as the reference solver for benchmarks: handed the true
// labels, it gets the same dots our tracker sees.
#pragma once

#include <optional>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/correspondence.hpp"

namespace earshot::bench {

enum class CvMethod {
  iterative,     ///< SOLVEPNP_ITERATIVE from the previous pose (SQPNP when none)
  sqpnp_refine,  ///< SOLVEPNP_SQPNP per frame, then solvePnPRefineLM
};

class OpenCvPnp {
 public:
  OpenCvPnp(const tracker::Camera& cam, const tracker::LedModel& model, CvMethod m);
  /// Pose from four labelled dots, or nullopt when OpenCV fails.
  std::optional<tracker::Pose> solve(std::span<const tracker::Correspondence> dots);
  void reset() { have_prev_ = false; }

 private:
  tracker::Camera cam_;
  tracker::LedModel model_;
  CvMethod method_;
  bool have_prev_ = false;
  double rvec_[3]{}, tvec_[3]{};
};

}  // namespace earshot::bench
