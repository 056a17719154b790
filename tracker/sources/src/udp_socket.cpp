#include "earshot/tracker/sources/udp_socket.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace earshot::tracker {
namespace {

sockaddr_in address(std::uint16_t port, bool any) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(any ? INADDR_ANY : INADDR_LOOPBACK);
  return a;
}

}  // namespace

bool is_ipv4_address(const std::string& text) {
  in_addr a{};
  return ::inet_pton(AF_INET, text.c_str(), &a) == 1;
}

UdpReceiver::UdpReceiver(std::uint16_t port, bool all_interfaces)
    : UdpReceiver(port, std::string(all_interfaces ? "0.0.0.0" : "127.0.0.1")) {}

UdpReceiver::UdpReceiver(std::uint16_t port, const std::string& address) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  if (::inet_pton(AF_INET, address.c_str(), &a.sin_addr) != 1)
    throw std::runtime_error("cannot listen on '" + address + "': not an IPv4 address (e.g. 127.0.0.1 or 0.0.0.0)");
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error(std::string("UDP socket: ") + std::strerror(errno));
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    const int err = errno;
    ::close(fd_);
    throw std::runtime_error("cannot listen on UDP " + address + ":" + std::to_string(port) + ": " + std::strerror(err));
  }
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &len);
  port_ = ntohs(bound.sin_port);
  char text[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &bound.sin_addr, text, sizeof text);
  address_ = text;
}

UdpReceiver::~UdpReceiver() { ::close(fd_); }

long UdpReceiver::receive(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) {
  pollfd p{fd_, POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return -1;
  // MSG_TRUNC: the real length, so an oversized packet is seen as such.
  const ssize_t n = ::recv(fd_, buf.data(), buf.size(), MSG_TRUNC);
  return n < 0 ? -1 : static_cast<long>(n);
}

void send_udp_loopback(std::uint16_t port, std::span<const std::uint8_t> bytes) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error(std::string("UDP socket: ") + std::strerror(errno));
  const sockaddr_in a = address(port, false);
  const ssize_t n = ::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&a), sizeof a);
  const int err = errno;
  ::close(fd);
  if (n < 0) throw std::runtime_error(std::string("UDP send: ") + std::strerror(err));
}

}  // namespace earshot::tracker
