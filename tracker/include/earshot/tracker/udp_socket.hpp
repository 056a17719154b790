// A bound UDP socket that receives datagrams with a timeout (RAII over the
// POSIX socket). Used by the opentrack and OSC sources.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>

namespace earshot::tracker {

class UdpReceiver {
 public:
  /// Binds `port` (0: any free port) on 127.0.0.1, or on every interface when
  /// `all_interfaces`. Throws std::runtime_error naming the port and the reason.
  explicit UdpReceiver(std::uint16_t port, bool all_interfaces = false);
  ~UdpReceiver();
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;

  /// One datagram into `buf`: its size (truncated datagrams report the size
  /// they had, so callers can tell), or -1 on timeout.
  long receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout);
  [[nodiscard]] std::uint16_t port() const { return port_; }

 private:
  int fd_ = -1;
  std::uint16_t port_ = 0;
};

/// Sends one datagram to 127.0.0.1:port (tests and tools). Throws on failure.
void send_udp_loopback(std::uint16_t port, std::span<const std::uint8_t> bytes);

}  // namespace earshot::tracker
