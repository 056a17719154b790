#include "earshot/tracker/filter/segment_vetting.hpp"

#include <algorithm>

#include "earshot/tracker/filter/motion_reach.hpp"

namespace earshot::tracker {
namespace {

/// Squared Mahalanobis distance of `later`'s first pose from `earlier`'s last
/// state carried across the gap (both spreads added).
double distance2(const EskfSegment& earlier, const EskfSegment& later, const EskfParams& q) {
  return carried_mahalanobis2(earlier.end, q, later.t_first, later.first_pose, later.first_cov);
}

}  // namespace

std::vector<bool> vet_segments(std::span<const EskfSegment> segs, std::size_t steps, const EskfParams& q) {
  std::vector<bool> kept(steps, true);
  const std::size_t n = segs.size();
  if (n < 3) return kept;
  // Kept segments as a doubly linked list; the most outlying one goes first,
  // so that a wrong neighbour is gone before a segment is judged by it.
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = i - 1;  // wraps for 0: never read (the ends are never judged)
    next[i] = i + 1;
  }
  auto outlier_ratio = [&](std::size_t i) {
    const EskfSegment &p = segs[prev[i]], &s = segs[i], &nx = segs[next[i]];
    // Beyond the eskf's own horizon nothing links P to N: no verdict.
    if (nx.t_first - p.end.t > q.max_gap_s) return 0.0;
    return distance2(p, s, q) + distance2(s, nx, q) - distance2(p, nx, q);
  };
  std::vector<double> glr(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) glr[i] = outlier_ratio(i);
  for (;;) {
    const auto worst = static_cast<std::size_t>(std::max_element(glr.begin(), glr.end()) - glr.begin());
    if (!(glr[worst] > kChi2SixDof999)) break;
    glr[worst] = 0.0;
    std::fill(kept.begin() + static_cast<std::ptrdiff_t>(segs[worst].first),
              kept.begin() + static_cast<std::ptrdiff_t>(segs[worst].last) + 1, false);
    const std::size_t p = prev[worst], nx = next[worst];
    next[p] = nx;
    prev[nx] = p;
    if (p > 0) glr[p] = outlier_ratio(p);
    if (nx + 1 < n) glr[nx] = outlier_ratio(nx);
  }
  return kept;
}

}  // namespace earshot::tracker
