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
// of the chain"). The most outlying segment goes first, so that a wrong
// neighbour is gone before a segment is judged by it, and a run of wrong
// segments goes one at a time. Only where P's end and N's start lie within
// the eskf's gap limit (0.25 s) is there a verdict: beyond it the filter
// links nothing, and every pose is within reach. Nothing is tuned: the bound
// is the dot tracker's.
//
// Dropped frames are not vouched for: `track solve --smooth` gives them out
// as lost, holding the last kept pose, as the live tracker does.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "earshot/tracker/filter/eskf.hpp"

namespace earshot::tracker {

/// Per step, whether its segment (RtsSmoother::segments) is kept (false:
/// dropped as above). The first and last segments are always kept (one side
/// of them is unknown).
[[nodiscard]] std::vector<bool> vet_segments(std::span<const EskfSegment> segments, std::size_t steps,
                                             const EskfParams& q);

}  // namespace earshot::tracker
