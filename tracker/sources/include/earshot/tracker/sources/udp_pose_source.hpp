// A pose source fed by UDP datagrams (opentrack, OSC): each datagram is
// decoded by a PacketDecoder (a function, or an object that keeps state
// between datagrams, e.g. OSC's single-axis messages); one that does not
// decode is counted and dropped, never trusted. Times come from the steady
// clock at arrival. It listens on 127.0.0.1 unless given another address:
// pose packets are unauthenticated, and anyone who can reach the socket can
// turn the listener's head.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string>

#include "earshot/tracker/core/frame_source.hpp"
#include "earshot/tracker/sources/udp_socket.hpp"

namespace earshot::tracker {

/// What one datagram asks for: a head pose (audio world frame, time unset)
/// and/or a recenter.
struct PoseMessage {
  std::optional<HeadPose> pose;
  bool recenter = false;
};

/// Decodes one datagram; nullopt with `why` set when it is malformed. Called
/// on the tracker thread only, one datagram at a time.
using PacketDecoder = std::function<std::optional<PoseMessage>(std::span<const std::uint8_t>, std::string* why)>;

/// Largest position accepted from a pose packet, metres: beyond is absurd.
inline constexpr double kMaxPositionM = 10.0;

class UdpPoseSource final : public FrameSource {
 public:
  /// `name` as in "opentrack" or "osc"; listens on 127.0.0.1 or every interface.
  UdpPoseSource(std::string name, std::uint16_t port, bool all_interfaces, PacketDecoder decoder);
  /// Listens on the IPv4 address `listen` ("127.0.0.1", "0.0.0.0", ...).
  UdpPoseSource(std::string name, std::uint16_t port, const std::string& listen, PacketDecoder decoder);
  SourceEvent next(std::chrono::milliseconds timeout) override;
  [[nodiscard]] std::string describe() const override { return name_ + ":" + std::to_string(socket_.port()); }
  [[nodiscard]] std::uint64_t dropped() const override { return dropped_; }
  [[nodiscard]] std::uint16_t port() const { return socket_.port(); }
  /// The bound address (getsockname), e.g. "127.0.0.1".
  [[nodiscard]] const std::string& listen_address() const { return socket_.address(); }
  [[nodiscard]] const std::string& last_error() const { return last_error_; }

 private:
  std::string name_;
  UdpReceiver socket_;
  PacketDecoder decoder_;
  std::uint64_t dropped_ = 0;
  std::string last_error_;
  bool pending_recenter_ = false;  ///< a packet held a pose and a recenter: the recenter comes next
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace earshot::tracker
