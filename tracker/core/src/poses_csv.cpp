#include "earshot/tracker/core/poses_csv.hpp"

#include <algorithm>
#include <charconv>
#include <istream>
#include <ostream>
#include <stdexcept>

#include "earshot/csv_fields.hpp"

namespace earshot::tracker {

PosesCsvWriter::PosesCsvWriter(std::ostream& out) : out_(out) {
  out_ << "t_s,state,tx_mm,ty_mm,tz_mm,qw,qx,qy,qz\n";
}

void PosesCsvWriter::write(const PoseRecord& r) {
  if (!r.pose.finite() || !std::isfinite(r.t))
    throw std::logic_error("PosesCsvWriter: refusing to write a non-finite pose");
  const Quat q = r.pose.quaternion();
  // std::to_chars with a precision prints as printf's %.*g, which is what the
  // stream's setprecision(10) / setprecision(8) printed: the same bytes, at a
  // fraction of the stream's formatting cost.
  char buf[256];
  char* p = buf;
  char* const end = buf + sizeof buf;
  auto number = [&](double v, int precision) { p = std::to_chars(p, end, v, std::chars_format::general, precision).ptr; };
  number(r.t, 10);
  *p++ = ',';
  const std::string_view state = pose_state_name(r.state);
  p = std::copy(state.begin(), state.end(), p);
  for (const double v : {r.pose.t.x(), r.pose.t.y(), r.pose.t.z(), q.w(), q.x(), q.y(), q.z()}) {
    *p++ = ',';
    number(v, 8);
  }
  *p++ = '\n';
  out_.write(buf, p - buf);
}

PosesCsvReader::PosesCsvReader(std::istream& in, std::string origin)
    : in_(in), origin_(std::move(origin)) {}

std::optional<PoseRecord> PosesCsvReader::next() {
  static constexpr std::array<const char*, 9> cols{"t_s", "state", "tx_mm", "ty_mm", "tz_mm",
                                                   "qw",  "qx",    "qy",    "qz"};
  std::string line;
  while (std::getline(in_, line)) {
    ++line_;
    if (csv::trim(line).empty()) continue;
    const auto f = csv::split(line);
    if (line_ == 1) {
      if (f.empty() || csv::trim(f[0]) != "t_s")
        throw InputError::at(origin_, line_, "t_s", "expected the header t_s,state,tx_mm,...");
      continue;
    }
    if (f.size() < cols.size())
      throw InputError::at(origin_, line_, "", "expected 9 fields, found " + std::to_string(f.size()));
    PoseRecord r;
    r.t = csv::number(f[0], origin_, line_, cols[0]);
    const auto st = pose_state_from_name(csv::trim(f[1]));
    if (!st) throw InputError::at(origin_, line_, "state", "unknown state '" + std::string(f[1]) + "'");
    r.state = *st;
    double v[7];
    for (size_t i = 0; i < 7; ++i) v[i] = csv::number(f[2 + i], origin_, line_, cols[2 + i]);
    const Quat q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw InputError::at(origin_, line_, "qw", "quaternion is not unit length");
    r.pose = Pose::from(q, Vec3(v[0], v[1], v[2]));
    return r;
  }
  return std::nullopt;
}

}  // namespace earshot::tracker
