#include "earshot/tracker/sources/udp_pose_source.hpp"

#include <array>

namespace earshot::tracker {

UdpPoseSource::UdpPoseSource(std::string name, std::uint16_t port, bool all_interfaces, PacketDecoder decoder)
    : name_(std::move(name)), socket_(port, all_interfaces), decoder_(std::move(decoder)) {}

UdpPoseSource::UdpPoseSource(std::string name, std::uint16_t port, const std::string& listen, PacketDecoder decoder)
    : name_(std::move(name)), socket_(port, listen), decoder_(std::move(decoder)) {}

SourceEvent UdpPoseSource::next(std::chrono::milliseconds timeout) {
  if (pending_recenter_) {
    pending_recenter_ = false;
    const double now = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    return make_note(SourceNote::Kind::recenter, "recenter requested", now);
  }
  std::array<std::uint8_t, 2048> buf{};
  const long n = socket_.receive(buf, timeout);
  if (n < 0) return make_note(SourceNote::Kind::timeout);
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string why;
  if (static_cast<std::size_t>(n) > buf.size()) {
    ++dropped_;
    last_error_ = describe() + ": packet of " + std::to_string(n) + " bytes is too long";
    return make_note(SourceNote::Kind::timeout);
  }
  auto m = decoder_(std::span(buf.data(), static_cast<std::size_t>(n)), &why);
  if (!m) {
    ++dropped_;
    last_error_ = describe() + ": " + why;
    return make_note(SourceNote::Kind::timeout);
  }
  if (m->pose) {
    // A packet (an OSC bundle) may also ask to recenter; the pose comes
    // first, the recenter is the next event and applies from the next pose.
    pending_recenter_ = m->recenter;
    m->pose->t = t;
    return *m->pose;
  }
  return make_note(m->recenter ? SourceNote::Kind::recenter : SourceNote::Kind::timeout, "recenter requested", t);
}

}  // namespace earshot::tracker
