// The evidence for each explanation of a frame's dots: which dots are which
// LEDs (the rest strays), which pose (a P3P root of three, an LM minimum of
// four) and, for each LED left unseen, whether it is out of view or dropped
// out. Used by the dot tracker to re-acquire from three dots after a loss,
// and by tracker_motion --ambiguity to count the frames no rule can decide.
//
// The evidence of an explanation is the probability of the dots under it,
// with the pose integrated against the head's motion (a linear-Gaussian
// Laplace step):
//   N(dots | pose*) (2 pi)^3 |C|^1/2 N(pose*; prediction, P + C)
// with pose* the explanation's pose, C its covariance from the dots (near
// singular for three dots: an exact fit says little along the direction that
// separates a near-planar beacon's roots, and the integral knows it), and P
// the spread of the prediction. Each LED dot is a Gaussian of the camera's
// pixel variance, each stray uniform over the image (times the share of
// frames with a stray), each LED the pose puts in view but unseen a dropout
// (the share of LED frames dropped). The prediction is a mixture: the
// filter's own process noise, and a small weight at the largest manoeuvre
// the eskf allows (a head reverses or a turn starts, which no constant
// noise expects). Without a prediction the poses compete on the dots alone.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/correspondence.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/filter/eskf.hpp"
#include "earshot/tracker/core/led_model.hpp"

namespace earshot::tracker {

/// What the camera and the head are expected to do.
struct EvidenceModel {
  double pixel_variance = 1.0 / 12.0;  ///< px^2 per coordinate
  double dropped_share = 0.05;         ///< of LED frames in view, dropped
  double stray_share = 0.2;            ///< of frames, with a stray
  double wide_weight = 0.1;            ///< of the prediction, at the manoeuvre's spread
};

/// The prediction at the frame's time: at the filter's process noise and at
/// the manoeuvre's (the same state carried with two noises).
struct MotionPrior {
  CarriedPose nominal, wide;
};

struct DotExplanation {
  Pose pose;
  LabelledDots dots;
  std::array<int, kSlots> slot_led{-1, -1, -1, -1};  ///< LED 0-3 per slot, -1 stray or empty
  int strays = 0;
  /// Only two LEDs, the other dots strays: no pose of its own (the
  /// prediction's), the dots' density with the pose integrated out.
  bool partial = false;
  double log_evidence = -1e300;
  Mat6 cov = Mat6::Identity();  ///< the pose's covariance from its dots
  /// The pose fused with the prediction (a Kalman update): what a filter
  /// on this explanation gives out. With 8-px cells the thesis beacon's
  /// per-frame pose is itself 20 degrees off on some frames; the fused is not.
  Pose fused;
};

/// Every labelling of 3 or 4 of the frame's dots and every pose it admits
/// whose LEDs face the camera (four dots: fits beyond 60 sigma^2 left out),
/// and every labelling of 2 of them as a partial explanation.
[[nodiscard]] std::vector<DotExplanation> explain_dots(const DotFrame& f, const Camera& cam, const LedModel& model,
                                                       double pixel_variance);

/// Fills e.log_evidence, e.cov and e.fused (see above).
void score_explanation(DotExplanation& e, const Camera& cam, const LedModel& model, const EvidenceModel& m,
                       const std::optional<MotionPrior>& prior);

/// The likeliest explanation with a pose and ln of its odds against the
/// likeliest one whose pose is more than `far_rad` from its own or that is
/// partial (+inf when none is).
struct EvidenceChoice {
  int best = -1;
  double log_odds = 0.0;
};
[[nodiscard]] EvidenceChoice choose_explanation(const std::vector<DotExplanation>& all, double far_rad);

/// The Wii camera keeps a dot in its slot while it stays visible: a slot
/// seen without a break since the last frame whose labels were known still
/// holds the same LED. An explanation that gives it another LED (or calls it
/// a stray) is possible only if, in one frame, the LED vanished and a new
/// dot took the freed slot: ln 0.01 for each such slot.
class SlotMemory {
 public:
  /// Every frame, before its explanations are scored: an empty slot breaks.
  void see(const DotFrame& f);
  /// A frame whose labels are known (tracked, or the truth in the bound).
  void label(const std::array<int, kSlots>& slot_led);
  [[nodiscard]] double log_prior(const std::array<int, kSlots>& slot_led) const;
  void reset() { *this = SlotMemory{}; }

 private:
  std::array<int, kSlots> led_{-1, -1, -1, -1};  ///< -1: no LED known in the slot
};

/// Where the head is over the long run, learnt from tracked poses: their
/// mean (rotation about it by its log) and covariance, forgetting over
/// ~`memory` samples (a minute at 100 Hz). After a loss longer than the
/// eskf's gap limit the carried state says little (an OU velocity carried
/// for seconds spreads over tens of degrees), and where the listener
/// usually is says more: the dot tracker weighs it in as the prior's wide
/// component.
class PoseDistribution {
 public:
  explicit PoseDistribution(double memory = 6000.0) : memory_(memory) {}
  void add(const Pose& p);
  /// The mean with the covariance (at least 5 deg and 20 mm per axis);
  /// nullopt before 100 poses.
  [[nodiscard]] std::optional<CarriedPose> prior() const;
  void reset() { *this = PoseDistribution{memory_}; }

 private:
  double memory_;
  double n_ = 0.0;
  Pose mean_;
  Mat6 cov_ = Mat6::Zero();
};

/// The camera's dropouts and strays, learnt from tracked frames: the share of
/// LEDs the tracked pose puts in view that were not seen, and of frames with
/// a dot no LED explains. Both start from a weak prior (2 % over 400 LED
/// frames, 5 % over 100 frames) so a few seconds of tracking outweigh it.
class CameraBehaviour {
 public:
  void observe(int leds_in_view, int leds_seen, bool stray);
  [[nodiscard]] double dropped_share() const;
  [[nodiscard]] double stray_share() const;
  void reset() { *this = CameraBehaviour{}; }

 private:
  double led_frames_ = 400.0, dropped_ = 8.0;
  double frames_ = 100.0, strays_ = 5.0;
};

}  // namespace earshot::tracker
