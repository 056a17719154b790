// Fuzzes the OSC pose decoder (liblo's deserialiser, our bundle walker, every
// sender convention's addresses and the single-axis state): any datagram
// becomes a finite pose within range, a recenter, or is dropped with a
// reason. Each input is decoded twice by one decoder, so the second pass
// starts from the state the first left (single-axis messages, /xyz).
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "earshot/tracker/sources/osc_pose.hpp"

namespace {

void check(const std::optional<earshot::tracker::PoseMessage>& m, const std::string& why) {
  namespace t = earshot::tracker;
  if (!m && why.empty()) std::abort();
  if (m && m->pose) {
    const auto& p = *m->pose;
    if (!t::to_eigen(p.position).allFinite() || t::to_eigen(p.position).norm() > t::kMaxPositionM) std::abort();
    if (!t::to_eigen(p.orientation).coeffs().allFinite() || std::abs(t::to_eigen(p.orientation).norm() - 1.0) > 1e-9) std::abort();
  }
  if (m && !m->pose && !m->recenter) std::abort();  // a message that asks for nothing is not ours
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  earshot::tracker::OscPoseDecoder decoder;
  for (int pass = 0; pass < 2; ++pass) {
    std::string why;
    const auto m = decoder.decode(std::span(data, size), &why);
    check(m, why);
  }
  return 0;
}
