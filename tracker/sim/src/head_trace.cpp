#include "earshot/tracker/sim/head_trace.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "earshot/errors.hpp"

namespace earshot::tracker {
namespace {

/// Source axes as columns in the camera frame (x right, y down, z away from
/// the camera), for a listener facing the camera at rest.
Mat3 axes_to_camera(bool with_position) {
  Mat3 M;
  if (with_position) {
    // right -> -x (the listener's right appears on the image's left), up -> -y, backward -> +z
    M << -1, 0, 0, 0, -1, 0, 0, 0, 1;
  } else {
    // forward -> -z, left -> +x, up -> -y
    M.col(0) = Vec3(0, 0, -1);
    M.col(1) = Vec3(1, 0, 0);
    M.col(2) = Vec3(0, -1, 0);
  }
  return M;
}

/// The source's forward and up directions (head axes).
Vec3 source_forward(bool with_position) { return with_position ? Vec3(0, 0, -1) : Vec3(1, 0, 0); }
Vec3 source_up(bool with_position) { return with_position ? Vec3(0, 1, 0) : Vec3(0, 0, 1); }

/// The +-40 deg heading sector the head occupies most often (1-degree
/// bins), and the mean heading of the samples in it.
double most_held_heading(const std::vector<Quat>& q, bool with_position) {
  const Vec3 f = source_forward(with_position), up = source_up(with_position);
  // Two horizontal axes of the world: forward at rest and up x forward.
  const Vec3 e1 = f, e2 = up.cross(f);
  std::vector<double> heading;
  heading.reserve(q.size());
  std::array<long, 360> bins{};
  for (const Quat& r : q) {
    const Vec3 d = r * f;
    const double h = std::atan2(d.dot(e2), d.dot(e1));
    heading.push_back(h);
    const int b = static_cast<int>(std::floor((h + std::numbers::pi) * 180.0 / std::numbers::pi));
    ++bins[static_cast<size_t>(((b % 360) + 360) % 360)];
  }
  long best = -1;
  int best_c = 0;
  for (int c = 0; c < 360; ++c) {
    long n = 0;
    for (int k = -40; k < 40; ++k) n += bins[static_cast<size_t>((c + k + 360) % 360)];
    if (n > best) {
      best = n;
      best_c = c;
    }
  }
  const double centre = (best_c + 0.5) * std::numbers::pi / 180.0 - std::numbers::pi;
  double sx = 0.0, sy = 0.0;
  for (double h : heading)
    if (std::abs(std::remainder(h - centre, 2.0 * std::numbers::pi)) <= 40.0 * std::numbers::pi / 180.0) {
      sx += std::cos(h);
      sy += std::sin(h);
    }
  return std::atan2(sy, sx);
}

}  // namespace

HeadTrace HeadTrace::from_samples(std::vector<double> t, std::vector<Quat> q, std::vector<Vec3> pos_m,
                                  const HeadTraceOptions& o) {
  if (t.empty() || t.size() != q.size() || (!pos_m.empty() && pos_m.size() != t.size()))
    throw InputError::at("head trace", 0, "", "needs matching samples");
  const bool with_position = !pos_m.empty();
  HeadTrace h;
  h.o_ = o;
  const double t0 = t.front();
  for (auto& v : t) v -= t0;
  for (auto& r : q) r.normalize();
  h.front_rad_ = most_held_heading(q, with_position);
  const Quat front(Eigen::AngleAxisd(-h.front_rad_, source_up(with_position)));
  const Mat3 M = axes_to_camera(with_position);
  h.t_ = std::move(t);
  h.q_.reserve(q.size());
  for (const Quat& r : q) {
    Quat c(Mat3(M * (front * r).toRotationMatrix() * M.transpose()));
    if (!h.q_.empty() && h.q_.back().dot(c) < 0.0) c.coeffs() = -c.coeffs();  // the shorter arc
    h.q_.push_back(c);
  }
  if (with_position) {
    Vec3 mean = Vec3::Zero();
    for (const Vec3& p : pos_m) mean += p;
    mean /= static_cast<double>(pos_m.size());
    h.p_mm_.reserve(pos_m.size());
    for (const Vec3& p : pos_m) h.p_mm_.push_back(o.rest_mm + 1000.0 * (M * (front * (p - mean))));
  }
  return h;
}

Pose HeadTrace::at(double t) const {
  const size_t n = t_.size();
  size_t k = static_cast<size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin());
  k = std::clamp<size_t>(k, 1, std::max<size_t>(n - 1, 1));
  const size_t i = n > 1 ? k - 1 : 0, j = n > 1 ? k : 0;
  const double span = t_[j] - t_[i];
  const double a = span > 0.0 ? std::clamp((t - t_[i]) / span, 0.0, 1.0) : 0.0;
  const Quat q = q_[i].slerp(a, q_[j]);
  const Mat3 R = q.toRotationMatrix();
  Vec3 c;
  if (!p_mm_.empty()) c = (1.0 - a) * p_mm_[i] + a * p_mm_[j];
  else c = o_.rest_mm + o_.pivot_mm - R * o_.pivot_mm;  // the neck pivot stays where it was
  return {R, c};
}

HeadTrace HeadTrace::parse(std::istream& in, std::string_view origin, const HeadTraceOptions& o) {
  std::string line;
  long n = 0;
  if (!std::getline(in, line)) throw InputError::at(origin, 1, "", "empty head trace");
  ++n;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const bool with_position = line == "t_s,qw,qx,qy,qz,x_m,y_m,z_m";
  if (!with_position && line != "t_s,qw,qx,qy,qz")
    throw InputError::at(origin, 1, "header", "expected t_s,qw,qx,qy,qz[,x_m,y_m,z_m]");
  std::vector<double> t;
  std::vector<Quat> q;
  std::vector<Vec3> p;
  const size_t cols = with_position ? 8 : 5;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::array<double, 8> v{};
    size_t c = 0, at = 0;
    for (; c < cols && at <= line.size(); ++c) {
      const size_t comma = std::min(line.find(',', at), line.size());
      const std::string item = line.substr(at, comma - at);
      char* end = nullptr;
      v[c] = std::strtod(item.c_str(), &end);
      if (item.empty() || *end != '\0' || !std::isfinite(v[c])) throw InputError::at(origin, n, "", "not a number: '" + item + "'");
      at = comma + 1;
    }
    if (c != cols || at <= line.size()) throw InputError::at(origin, n, "", "expected " + std::to_string(cols) + " columns");
    if (!t.empty() && !(v[0] >= t.back())) throw InputError::at(origin, n, "t_s", "time goes back");
    const Quat r(v[1], v[2], v[3], v[4]);
    if (!(r.norm() > 0.5)) throw InputError::at(origin, n, "", "not a unit quaternion");
    t.push_back(v[0]);
    q.push_back(r);
    if (with_position) p.emplace_back(v[5], v[6], v[7]);
  }
  if (t.size() < 2) throw InputError::at(origin, n, "", "a head trace needs two samples");
  return from_samples(std::move(t), std::move(q), std::move(p), o);
}

HeadTrace HeadTrace::load(const std::filesystem::path& path, const HeadTraceOptions& o) {
  std::ifstream in(path);
  if (!in) throw InputError::at(path.string(), 0, "", "cannot open file");
  return parse(in, path.string(), o);
}

}  // namespace earshot::tracker
