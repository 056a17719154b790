// How far a pose is from every motion a head could have made since the
// eskf's last state: the test the dot tracker's re-acquisitions
// (dot_tracker.hpp) and the smoother's segment vetting (segment_vetting.hpp)
// put a pose to.
//
// Across a gap a constant-velocity extrapolation overshoots: head velocity
// decorrelates over ~0.5 s (rotation) and ~1 s (translation), the figures
// eskf.hpp's q comes from. So the state is carried with an Ornstein-
// Uhlenbeck velocity of those correlation times (kHeadRotationTauS and
// kHeadTranslationTauS, carry_ou: eskf.hpp), its
// acceleration noise at the largest scale the eskf's manoeuvre test tries
// (kMaxManoeuvreScale): a pose outside the 99.9 % bound of chi-square with 6
// degrees of freedom is one that no head motion the filter accepts explains.
#pragma once

#include "earshot/tracker/filter/eskf.hpp"

namespace earshot::tracker {

/// 99.9 % point of chi-square with 6 degrees of freedom.
inline constexpr double kChi2SixDof999 = 22.46;

/// The OU head motion at `scale` times the literature q of `q`.
[[nodiscard]] OuMotion head_motion(const EskfParams& q, double scale = 1.0);

/// Squared Mahalanobis distance of pose `p` from `pred`, whose spread
/// (rotation rad, translation mm: the eskf's left perturbation) is `spread`.
[[nodiscard]] double pose_mahalanobis2(const Pose& p, const Pose& pred, const Mat6& spread);

/// Squared Mahalanobis distance of pose `p` at time `t` (>= from.t) from the
/// filter state `from` (its updated pose, velocities and covariance) carried
/// to t at the largest manoeuvre noise, as above. `p_cov` is p's own
/// covariance where p is an estimate too (the two spreads add).
[[nodiscard]] double carried_mahalanobis2(const EskfStep& from, const EskfParams& q, double t, const Pose& p,
                                          const Mat6& p_cov = Mat6::Zero());

}  // namespace earshot::tracker
