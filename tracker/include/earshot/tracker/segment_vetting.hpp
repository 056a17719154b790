// Offline vetting of the eskf's segments, for `track solve --smooth`.
//
// The filter restarts whenever the dot tracker (re)acquires the head or
// changes its explanation of the dots; the stretch until the next restart is
// a segment. A re-acquisition can be a wrong branch (the other root of three
// dots, a stray taken for an LED) that fits the dots as well as the truth:
// causally nothing tells it apart until the evidence arrives, so the forward
// filter gives it out. Offline both sides are known, and a wrong segment is
// the odd one out between its neighbours: linking the segment before it to
// the one after it through it costs far more than linking them directly.
//
// The cost of a link is the squared Mahalanobis distance of the later
// segment's first pose (with its own covariance) from the earlier one's last
// filter state carried across the gap (carried_mahalanobis2,
// motion_reach.hpp: an OU velocity at the largest process noise the eskf's
// manoeuvre test tries). A segment S between P and N is dropped when
// d(P, S) + d(S, N) - d(P, N) exceeds the 99.9 % point of chi-square with 6
// degrees of freedom (a generalised likelihood ratio for "S is an outlier
// of the chain"). Where P itself disowns S, a run of segments may be the odd
// one out together (a wrong branch followed through a restart). Nothing is
// tuned: the bound is the dot tracker's, and the reach grows with the gap by
// itself, so after a long gap only the far side can disown a segment.
//
// Dropped frames are not vouched for: `track solve --smooth` gives them out
// as lost, holding the last kept pose, as the live tracker does.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "earshot/tracker/eskf.hpp"

namespace earshot::tracker {

/// One stretch of the filter between restarts.
struct EskfSegment {
  std::size_t first = 0, last = 0;  ///< indices of its first and last step
  double t_first = 0.0;
  Pose first_pose;                ///< the filter's pose at its first step
  Mat6 first_cov = Mat6::Zero();  ///< and its covariance (the measurement's: a restart takes it as it is)
  EskfStep end;                   ///< its last step: state, velocities and covariance
};

/// The segments of a run of filter steps, fed the steps the smoother gets.
class SegmentCollector {
 public:
  void add(const EskfStep& step);
  [[nodiscard]] const std::vector<EskfSegment>& segments() const { return segs_; }
  [[nodiscard]] std::size_t steps() const { return steps_; }

 private:
  std::vector<EskfSegment> segs_;
  std::size_t steps_ = 0;
};

/// Runs of at most this many segments are tried (a bound on the work only:
/// a longer run spans more than the ~0.2 s beyond which every pose is within
/// reach and no link can fail).
inline constexpr std::size_t kMaxDroppedRun = 1;

/// Per step, whether its segment is kept (false: dropped as above). The
/// first and last segments are always kept (one side of them is unknown).
[[nodiscard]] std::vector<bool> vet_segments(std::span<const EskfSegment> segments, std::size_t steps,
                                             const EskfParams& q);

}  // namespace earshot::tracker
