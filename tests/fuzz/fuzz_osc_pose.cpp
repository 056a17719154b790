// Fuzzes the OSC pose handler (liblo's deserialiser and our addresses): any
// datagram becomes a finite pose within range, a recenter, or is dropped
// with a reason.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "earshot/tracker/osc_pose.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace t = earshot::tracker;
  std::string why;
  const auto m = t::decode_osc(std::span(data, size), &why);
  if (!m && why.empty()) std::abort();
  if (m && m->pose) {
    const auto& p = *m->pose;
    if (!p.position_m.allFinite() || p.position_m.norm() > t::kMaxPositionM) std::abort();
    if (!p.orientation.coeffs().allFinite() || std::abs(p.orientation.norm() - 1.0) > 1e-9) std::abort();
  }
  if (m && !m->pose && !m->recenter) std::abort();  // a message that asks for nothing is not ours
  return 0;
}
