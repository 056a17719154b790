// Fuzzes the opentrack UDP decoder: any datagram becomes a plausible, finite
// pose or is dropped with a reason.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "earshot/tracker/sources/opentrack_packet.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace t = earshot::tracker;
  std::string why;
  const auto m = t::decode_opentrack(std::span(data, size), &why);
  if (!m && why.empty()) std::abort();  // a dropped packet always says why
  if (m) {
    if (!m->pose) std::abort();
    const auto& p = *m->pose;
    if (!t::to_eigen(p.position).allFinite() || t::to_eigen(p.position).norm() > 2.0 * t::kMaxPositionM) std::abort();
    if (!t::to_eigen(p.orientation).coeffs().allFinite() || std::abs(t::to_eigen(p.orientation).norm() - 1.0) > 1e-9) std::abort();
  }
  return 0;
}
