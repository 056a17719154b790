// Poses CSV: the tracker's output (contract):
//   t_s,state,tx_mm,ty_mm,tz_mm,qw,qx,qy,qz
// the beacon pose in the camera frame; state is tracking, predicted or lost.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

#include "earshot/tracker/geometry.hpp"

namespace earshot::tracker {

enum class TrackState { searching, tracking, predicted, lost };

[[nodiscard]] std::string_view to_string(TrackState s);
[[nodiscard]] std::optional<TrackState> track_state_from(std::string_view s);

struct PoseRecord {
  double t = 0.0;
  TrackState state = TrackState::lost;
  Pose pose;
};

class PosesCsvWriter {
 public:
  explicit PosesCsvWriter(std::ostream& out);
  /// Writes one row. A non-finite pose is never written: throws std::logic_error.
  void write(const PoseRecord& r);

 private:
  std::ostream& out_;
};

class PosesCsvReader {
 public:
  PosesCsvReader(std::istream& in, std::string origin);
  std::optional<PoseRecord> next();  ///< throws InputError on a bad line

 private:
  std::istream& in_;
  std::string origin_;
  long line_ = 0;
};

}  // namespace earshot::tracker
