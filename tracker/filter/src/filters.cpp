#include "earshot/tracker/filter/filters.hpp"

#include <algorithm>
#include <span>

namespace earshot::tracker {

PoseOneEuro::PoseOneEuro(OneEuroParams translation, OneEuroParams rotation)
    : trans_(translation), rot_(rotation) {}

void PoseOneEuro::reset() {
  trans_.reset();
  rot_.reset();
  have_ = false;
}

Pose PoseOneEuro::filter(const Pose& p, double t) {
  Pose out;
  out.t = trans_.filter(p.t, t);
  // Rotation: filter the rotation vector relative to a reference that moves
  // with the output, so the filtered quantity stays small (no wrap at pi).
  if (!have_) {
    R_ref_ = p.R;
    have_ = true;
  }
  const Vec3 w = log_so3(R_ref_.transpose() * p.R);
  const Vec3 wf = rot_.filter(w, t);
  out.R = R_ref_ * exp_so3(wf);
  if (wf.norm() > 0.25) {  // re-anchor: the output becomes the new reference
    R_ref_ = out.R;
    rot_.shift(-wf);
  }
  return out;
}

Pose MedianPoseFilter::filter(const Pose& p) {
  ring_[static_cast<size_t>(head_)] = p;
  head_ = (head_ + 1) % 5;
  n_ = std::min(n_ + 1, 5);
  std::array<double, 5> v{};
  const auto n = static_cast<std::size_t>(n_);
  auto median = [&](auto get) {
    const std::span<double> w(v.data(), n);
    for (std::size_t i = 0; i < n; ++i) w[i] = get(ring_[i]);
    // Middle element(s) by selection; a std::sort of a run of unknown length
    // made g++ 12 warn (-Warray-bounds) on its unrolled insertion sort.
    const auto mid = w.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(w.begin(), mid, w.end());
    if (n % 2) return *mid;
    return 0.5 * (*std::max_element(w.begin(), mid) + *mid);
  };
  Pose out;
  for (int a = 0; a < 3; ++a) out.t[a] = median([a](const Pose& q) { return q.t[a]; });
  Vec3 w;
  for (int a = 0; a < 3; ++a)
    w[a] = median([&, a](const Pose& q) { return log_so3(p.R.transpose() * q.R)[a]; });
  out.R = p.R * exp_so3(w);
  return out;
}

void ConstantVelocity::observe(const Pose& p, double t) {
  if (n_ > 0 && !(t > t1_)) {  // same time again: replace the newest
    p1_ = p;
    return;
  }
  p0_ = p1_;
  t0_ = t1_;
  p1_ = p;
  t1_ = t;
  n_ = std::min(n_ + 1, 2);
}

std::optional<Pose> ConstantVelocity::predict(double t) const {
  if (n_ == 0) return std::nullopt;
  if (n_ == 1) return p1_;
  const double dt = t1_ - t0_;
  if (!(dt > 0.0)) return p1_;
  const double s = (t - t1_) / dt;
  Pose out;
  out.t = p1_.t + s * (p1_.t - p0_.t);
  out.R = exp_so3(s * log_so3(p1_.R * p0_.R.transpose())) * p1_.R;
  return out;
}

}  // namespace earshot::tracker
