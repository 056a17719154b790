#include "earshot/scenes/pose_track.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>

#include "earshot/errors.hpp"

namespace earshot::scenes {
namespace {

constexpr const char* kCols[] = {"t_s", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"};

double field(std::string_view s, const std::string& origin, long line, const char* name) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.remove_suffix(1);
  double v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || p != s.data() + s.size())
    throw InputError::at(origin, line, name, "not a number: '" + std::string(s) + "'");
  if (!std::isfinite(v)) throw InputError::at(origin, line, name, "not a finite number");
  return v;
}

}  // namespace

PoseTrack PoseTrack::read(std::istream& in, const std::string& origin) {
  PoseTrack tr;
  std::string line;
  long n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line == "\r") continue;
    if (n == 1) {
      if (line.rfind("t_s,", 0) != 0) throw InputError::at(origin, n, "t_s", "expected the header t_s,x_m,y_m,z_m,qw,qx,qy,qz");
      continue;
    }
    std::vector<std::string_view> f;
    std::string_view rest(line);
    for (;;) {
      const auto c = rest.find(',');
      f.push_back(rest.substr(0, c));
      if (c == std::string_view::npos) break;
      rest.remove_prefix(c + 1);
    }
    if (f.size() < 8) throw InputError::at(origin, n, "", "expected 8 fields, found " + std::to_string(f.size()));
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = field(f[static_cast<std::size_t>(i)], origin, n, kCols[i]);
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (std::abs(qn - 1.0) > 1e-3) throw InputError::at(origin, n, "qw", "quaternion is not unit length");
    if (!tr.rows_.empty() && v[0] <= tr.rows_.back().t)
      throw InputError::at(origin, n, "t_s", "times must increase");
    tr.rows_.push_back({v[0], {v[1], v[2], v[3]}, {v[4] / qn, v[5] / qn, v[6] / qn, v[7] / qn}});
  }
  if (tr.rows_.empty()) throw InputError::at(origin, 0, "", "no poses in the track");
  return tr;
}

PoseTrack PoseTrack::load(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError::at(path.string(), 0, "", "cannot open file");
  return read(in, path.string());
}

audio::ListenerState PoseTrack::at(double t) const {
  audio::ListenerState s;
  const auto it = std::upper_bound(rows_.begin(), rows_.end(), t, [](double x, const Row& r) { return x < r.t; });
  if (it == rows_.begin() || it == rows_.end()) {
    const Row& r = it == rows_.begin() ? rows_.front() : rows_.back();
    s.position = r.p;
    s.orientation = r.q;
    return s;
  }
  const Row& a = *(it - 1);
  const Row& b = *it;
  const double u = (t - a.t) / (b.t - a.t);
  for (int i = 0; i < 3; ++i) s.position[static_cast<std::size_t>(i)] = a.p[static_cast<std::size_t>(i)] + u * (b.p[static_cast<std::size_t>(i)] - a.p[static_cast<std::size_t>(i)]);
  // Slerp along the shorter arc.
  double dot = 0;
  audio::Quat qb = b.q;
  for (int i = 0; i < 4; ++i) dot += a.q[static_cast<std::size_t>(i)] * qb[static_cast<std::size_t>(i)];
  if (dot < 0) {
    for (double& c : qb) c = -c;
    dot = -dot;
  }
  double wa = 1 - u, wb = u;
  if (dot < 0.9995) {
    const double th = std::acos(std::min(1.0, dot));
    wa = std::sin((1 - u) * th) / std::sin(th);
    wb = std::sin(u * th) / std::sin(th);
  }
  double norm = 0;
  for (int i = 0; i < 4; ++i) {
    s.orientation[static_cast<std::size_t>(i)] = wa * a.q[static_cast<std::size_t>(i)] + wb * qb[static_cast<std::size_t>(i)];
    norm += s.orientation[static_cast<std::size_t>(i)] * s.orientation[static_cast<std::size_t>(i)];
  }
  for (double& c : s.orientation) c /= std::sqrt(norm);
  return s;
}

}  // namespace earshot::scenes
