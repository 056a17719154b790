#include "earshot/tracker/pose_track_writer.hpp"

#include <iomanip>
#include <ostream>

namespace earshot::tracker {

PoseTrackWriter::PoseTrackWriter(std::ostream& out) : out_(out) { out_ << "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n"; }

bool PoseTrackWriter::write(const HeadPose& p) {
  if (!p.finite() || (any_ && p.t <= last_t_)) return false;
  any_ = true;
  last_t_ = p.t;
  out_ << std::setprecision(10) << p.t << std::setprecision(8);
  for (double v : p.position) out_ << ',' << v;
  for (double v : p.orientation) out_ << ',' << v;
  out_ << '\n';
  return true;
}

}  // namespace earshot::tracker
