// A bound UDP socket that receives datagrams with a timeout (RAII over the
// POSIX socket). Used by the opentrack and OSC sources, which listen on
// 127.0.0.1 unless told otherwise: pose packets are unauthenticated, so a
// socket on every interface lets anyone on the network turn the listener's
// head.
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
  /// Binds `port` on the IPv4 address `address` (dotted quad: "127.0.0.1",
  /// "0.0.0.0" for every interface, or one interface's address). Throws
  /// std::runtime_error naming the address, the port and the reason.
  UdpReceiver(std::uint16_t port, const std::string& address);
  ~UdpReceiver();
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;

  /// One datagram into `buf`: its size (truncated datagrams report the size
  /// they had, so callers can tell), or -1 on timeout.
  long receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout);
  [[nodiscard]] std::uint16_t port() const { return port_; }
  /// The address the socket is bound to, as the kernel reports it (getsockname).
  [[nodiscard]] const std::string& address() const { return address_; }

 private:
  int fd_ = -1;
  std::uint16_t port_ = 0;
  std::string address_;
};

/// True when `text` is an IPv4 address in dotted-quad form.
[[nodiscard]] bool is_ipv4_address(const std::string& text);

/// Sends one datagram to 127.0.0.1:port (tests and tools). Throws on failure.
void send_udp_loopback(std::uint16_t port, std::span<const std::uint8_t> bytes);

}  // namespace earshot::tracker
