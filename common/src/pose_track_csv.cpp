#include "earshot/pose_track_csv.hpp"

#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <istream>
#include <ostream>

#include "earshot/csv_fields.hpp"

namespace earshot {
namespace {

constexpr std::array<const char*, 8> kColumns{"t_s", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"};

}  // namespace

std::vector<HeadPose> read_pose_track_csv(std::istream& in, const std::string& origin) {
  std::vector<HeadPose> rows;
  std::string line;
  long n = 0;
  bool has_state = false;  // a recording's ninth column
  while (std::getline(in, line)) {
    ++n;
    if (csv::trim(line).empty() || line == "\r") continue;
    const auto f = csv::split(line);
    if (n == 1) {
      if (csv::trim(f[0]) != "t_s") throw InputError::at(origin, n, "t_s", "expected the header t_s,x_m,y_m,z_m,qw,qx,qy,qz");
      has_state = f.size() > kColumns.size() && csv::trim(f[kColumns.size()]) == "state";
      continue;
    }
    const std::size_t want = kColumns.size() + (has_state ? 1 : 0);
    if (f.size() < want)
      throw InputError::at(origin, n, "", "expected " + std::to_string(want) + " fields, found " + std::to_string(f.size()));
    std::array<double, 8> v{};
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = csv::number(f[i], origin, n, kColumns[i]);
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (std::abs(qn - 1.0) > 1e-3) throw InputError::at(origin, n, "qw", "quaternion is not unit length");
    if (!rows.empty() && v[0] <= rows.back().t) throw InputError::at(origin, n, "t_s", "times must increase");
    HeadPose& p = rows.emplace_back();
    p.t = v[0];
    p.position = {v[1], v[2], v[3]};
    p.orientation = {v[4] / qn, v[5] / qn, v[6] / qn, v[7] / qn};
    p.state = PoseState::tracking;
    if (has_state) {
      const auto s = pose_state_from_name(csv::trim(f[kColumns.size()]));
      if (!s) throw InputError::at(origin, n, "state", "expected searching, tracking, predicted or lost");
      p.state = *s;
    }
  }
  if (rows.empty()) throw InputError::at(origin, 0, "", "no poses in the track");
  return rows;
}

std::vector<HeadPose> load_pose_track_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError::at(path.string(), 0, "", "cannot open file");
  return read_pose_track_csv(in, path.string());
}

PoseTrackCsvWriter::PoseTrackCsvWriter(std::ostream& out, bool with_state) : out_(out), with_state_(with_state) {
  out_ << (with_state_ ? "t_s,x_m,y_m,z_m,qw,qx,qy,qz,state\n" : "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n");
}

bool PoseTrackCsvWriter::write(const HeadPose& p) {
  if (!p.finite() || (any_ && p.t <= last_t_)) return false;
  any_ = true;
  last_t_ = p.t;
  out_ << std::setprecision(10) << p.t << std::setprecision(8);
  for (double v : p.position) out_ << ',' << v;
  for (double v : p.orientation) out_ << ',' << v;
  if (with_state_) out_ << ',' << pose_state_name(p.state);
  out_ << '\n';
  return true;
}

}  // namespace earshot
