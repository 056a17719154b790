// The pose pipeline for dots that come labelled (a tag's corners: slot k is
// model point k): solve -> filter, with the DotTracker's states (tracking,
// predicted, lost) and filters, but no labeller.
//
// A planar beacon seen small has two poses that fit one frame almost
// equally well (the tag tilted towards or away from the line of sight). On
// acquisition both are followed, each from its own prediction. The output
// keeps the branch it gave out while tracking and switches only when the
// rival explains the corners 100 : 1 better (their summed squared
// residuals over the pixel variance: a sequential probability ratio test);
// a rival goes once the evidence is 100 : 1 against it, or after three
// times `disambiguation_frames` without a decision.
#pragma once

#include <vector>

#include "earshot/tracker/track/dot_tracker.hpp"

namespace earshot::tracker {

class LabelledTracker {
 public:
  LabelledTracker(const Camera& cam, const LedModel& model, TrackerConfig cfg = {});

  /// Slot k of `frame` is model point k. TrackResult::slot_led is k for every
  /// slot that holds a dot while tracking.
  TrackResult process(const DotFrame& frame);
  void reset();
  /// The eskf filter (its last step feeds the offline smoother).
  [[nodiscard]] const PoseEskf& eskf() const { return eskf_; }

 private:
  struct Hypothesis {
    Pose pose;
    ConstantVelocity cv;
    double cost_sum = 0.0;
    double ssr_sum = 0.0;  ///< squared residuals over every corner it explained (px^2)
    int frames = 0;
    long id = 0;
    double rms = 0.0;
    bool seen = false;  ///< solved in this frame
  };
  bool fits(const Pose& p, const LabelledDots& dots, double& rms) const;
  /// The branch given out: the one given out last frame unless a rival is
  /// 100 : 1 more likely; drops rivals the evidence has ruled out.
  const Hypothesis* choose_branch();
  TrackResult finish(TrackResult r, const LabelledDots& dots);

  Camera cam_;
  LedModel model_;
  TrackerConfig cfg_;
  std::vector<Hypothesis> hyps_;
  long next_id_ = 0, output_id_ = 0;
  PoseOneEuro one_euro_;
  MedianPoseFilter median_;
  PoseEskf eskf_;
  PixelNoiseEstimator pixel_noise_;
  ConstantVelocity cv_;
  std::optional<Pose> last_output_;
  double last_solve_t_ = -1e300;
};

}  // namespace earshot::tracker
