// How many frames the dots can decide at all: a bound on what any causal
// tracker can track without a flip (tracker_motion --ambiguity, issue 18
// part 3).
//
// Each frame's dots admit several explanations: a labelling of three or four
// of them (the rest strays), a pose (a P3P root for three, an LM minimum for
// four), and for every LED it leaves unseen whether that LED is out of view
// or dropped out. The oracle scores each by its evidence under the model that
// generated the walk:
//   - the pixels: the camera's noise variance sigma^2 (1/12 px^2 for integer
//     pixels, 64/12 for 8-px cells), each LED dot a Gaussian density, each
//     stray uniform over the image (the share of frames with one times
//     1 / area), each LED that would be in view but is unseen a dropout
//     (the walk's share of dropped LED frames);
//   - the head's motion: the pose's predicted density under the state a
//     causal tracker could know, an eskf fed the true explanation's pose on
//     every frame decided so far (and nothing on the others), carried to
//     the frame with the walk's own Ornstein-Uhlenbeck velocity. The walk
//     reflects its velocity at the box's bounds, which no OU model expects,
//     so the prior is a mixture: 90 % at the walk's acceleration noise, 10 %
//     at the eskf's largest manoeuvre scale.
// The Wii camera keeps a visible dot in its slot (SlotMemory): labels known
// at the last fed frame carry over to slots seen without a break since.
// For four dots the evidence integrates the pose (linear-Gaussian Laplace):
// N(dots | pose*) (2 pi)^3 |C|^1/2 N(pose*; prediction, P + C), with C the
// pose's covariance from the dots; for three dots the same, C then being the
// near-singular covariance of an exact fit.
//
// A frame is decided when the best explanation within kFlipDeg of the truth
// beats every explanation beyond it by 100 : 1 (what the dot tracker asks
// before it gives a pose out); "rival within 100 : 1" when the truth's side
// is ahead by less; "rival ahead" when a pose beyond kFlipDeg is more likely
// than every pose near the truth: any rule that gives a pose out there flips,
// so a tracker that never flips must hold that frame; "none near" when no
// explanation, fused with the motion prior, is within kFlipDeg of the truth
// (the pixel noise itself: 8-px cells on the near-planar beacon).
// Near and far are judged on each explanation's pose fused with the motion
// prior (a Kalman update): what a filter on that branch would give out.
#pragma once

#include <optional>
#include <vector>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/track/dot_evidence.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/filter/eskf.hpp"
#include "earshot/tracker/core/led_model.hpp"

namespace earshot::tracker::bench {

/// What generated the walk, as far as a tracker could know it.
struct GenerativeModel {
  EvidenceModel evidence{};
  OuMotion motion{};  ///< the head's velocity process
};

/// The GenerativeModel of `walk` with the given RMS speeds per axis and
/// OU correlation time (Simulator::step: q = 2 rms^2 / tau).
[[nodiscard]] GenerativeModel walk_model(double pixel_variance, double ang_rms_deg_s, double speed_mm_s,
                                         double dropped_share, double stray_share);

enum class Verdict { decided, within_100, rival_ahead, none_near };

struct FrameJudgement {
  Verdict verdict = Verdict::decided;
  double log_ratio = 0.0;  ///< ln(evidence near the truth / evidence beyond kFlipDeg)
  int explanations = 0;    ///< counted (poses within 20 nats of the best)
};

/// Which frames the oracle's state is fed the true explanation on: only the
/// decided ones (what a causal tracker that gives out only decided frames
/// could know), or every frame (a tracker that somehow always followed the
/// right branch: the most any causal tracker can know, so a frame not decided
/// even then is lost to every rule).
enum class StateFeed { decided_frames, every_frame };

class AmbiguityOracle {
 public:
  AmbiguityOracle(const Camera& cam, const LedModel& model, GenerativeModel g, StateFeed feed = StateFeed::decided_frames);
  /// Judges a frame with ground truth and 3 or more LEDs seen; feeds the
  /// oracle's state when the frame is decided.
  FrameJudgement judge(const DotFrame& f);
  /// Every frame, judged or not, before judge(): which slots stayed lit.
  void see(const DotFrame& f) { slots_.see(f); }

 private:
  [[nodiscard]] std::optional<DotExplanation> truth(const DotFrame& f) const;

  Camera cam_;
  LedModel model_;
  GenerativeModel g_;
  StateFeed feed_;
  PoseEskf state_;
  SlotMemory slots_;
};

}  // namespace earshot::tracker::bench
