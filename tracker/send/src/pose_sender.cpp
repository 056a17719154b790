#include "earshot/tracker/send/pose_sender.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "earshot/tracker/sources/opentrack_packet.hpp"
#include "earshot/tracker/sources/osc_pose.hpp"

namespace earshot::tracker {
namespace {

static_assert(sizeof(sockaddr_in) <= 16, "PoseSender keeps a sockaddr_in in 16 bytes");

/// Room for the datagrams of one pose: at most two, each under 128 bytes
/// (the longest, /earshot/pose/quat with 7 floats, is 60).
struct Datagrams {
  std::array<std::array<std::uint8_t, 128>, 2> bytes{};
  std::array<std::size_t, 2> size{};
  std::size_t count = 0;

  void osc(std::string_view address, std::span<const float> args) {
    size[count] = write_osc_floats(bytes[count], address, args);
    ++count;
  }
};

template <std::size_t N>
std::array<float, N> floats(const std::array<double, N>& v) {
  std::array<float, N> f{};
  for (std::size_t i = 0; i < N; ++i) f[i] = static_cast<float>(v[i]);
  return f;
}

/// The datagrams of `pose` in the spec's format, without allocating.
void format(const SendSpec& spec, const HeadPose& pose, Datagrams& d) {
  d.count = 0;
  const Quat head = Quat(pose.orientation[0], pose.orientation[1], pose.orientation[2], pose.orientation[3]).normalized();
  if (spec.kind == SendSpec::Kind::opentrack) {
    const auto packet = encode_opentrack(pose_to_opentrack(pose));
    std::copy(packet.begin(), packet.end(), d.bytes[0].begin());
    d.size[0] = packet.size();
    d.count = 1;
    return;
  }
  switch (spec.format) {
    case SendSpec::Format::earshot: {
      const std::array<double, 7> v{pose.position[0], pose.position[1], pose.position[2], head.w(),
                                    head.x(),         head.y(),         head.z()};
      d.osc("/earshot/pose/quat", floats(v));
      break;
    }
    case SendSpec::Format::sparta: {
      // The position first: SPARTA's 6DoFconv takes it; the orientation last,
      // so a receiver that keeps both (ours does) ends on the whole pose.
      const Vec3 p = earshot_to_saf(Vec3(pose.position[0], pose.position[1], pose.position[2]));
      d.osc("/xyz", floats(std::array<double, 3>{p.x(), p.y(), p.z()}));
      d.osc("/ypr", floats(sparta_ypr(head)));
      break;
    }
    case SendSpec::Format::iem: d.osc("/SceneRotator/quaternions", floats(scene_rotator_quaternions(head))); break;
    case SendSpec::Format::iem_ypr: d.osc("/SceneRotator/ypr", floats(scene_rotator_ypr(head))); break;
  }
}

std::string where(const SendSpec& s) { return "send '" + s.text + "'"; }

}  // namespace

std::vector<std::vector<std::uint8_t>> pose_datagrams(const SendSpec& spec, const HeadPose& pose) {
  Datagrams d;
  format(spec, pose, d);
  std::vector<std::vector<std::uint8_t>> out;
  for (std::size_t i = 0; i < d.count; ++i) out.emplace_back(d.bytes[i].begin(), d.bytes[i].begin() + static_cast<std::ptrdiff_t>(d.size[i]));
  return out;
}

PoseSender::PoseSender(SendSpec spec) : spec_(std::move(spec)) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(spec_.host.c_str(), nullptr, &hints, &found);
  if (rc != 0 || !found)
    throw std::runtime_error(where(spec_) + ": cannot resolve host '" + spec_.host + "' to an IPv4 address: " +
                             ::gai_strerror(rc));
  sockaddr_in a{};
  std::memcpy(&a, found->ai_addr, std::min<std::size_t>(found->ai_addrlen, sizeof a));
  ::freeaddrinfo(found);
  a.sin_family = AF_INET;
  a.sin_port = htons(spec_.port);
  std::memcpy(address_.data(), &a, sizeof a);
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error(where(spec_) + ": UDP socket: " + std::strerror(errno));
}

PoseSender::~PoseSender() {
  if (fd_ >= 0) ::close(fd_);
}

bool PoseSender::send(std::span<const std::uint8_t> bytes) {
  const ssize_t n = ::sendto(fd_, bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL,
                             reinterpret_cast<const sockaddr*>(address_.data()), sizeof(sockaddr_in));
  if (n == static_cast<ssize_t>(bytes.size())) return true;
  const int err = n < 0 ? errno : EMSGSIZE;
  if (err == EAGAIN || err == EWOULDBLOCK || err == ENOBUFS) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
  } else {
    failed_.fetch_add(1, std::memory_order_relaxed);
    last_error_.store(err, std::memory_order_relaxed);
  }
  return false;
}

void PoseSender::offer(const HeadPose& pose, Clock::time_point now) {
  // A bucket of 1.5 poses refilled at rate_hz: no more than the rate on
  // average, and a pose that comes a little early still finds a token.
  constexpr double kBucket = 1.5;
  if (started_) {
    const double dt = std::chrono::duration<double>(now - last_).count();
    if (dt > 0.0) tokens_ = std::min(kBucket, tokens_ + dt * spec_.rate_hz);
  }
  started_ = true;
  last_ = std::max(last_, now);
  if (tokens_ < 1.0) return;
  tokens_ -= 1.0;
  if (!pose.finite()) return;  // never on the wire (the slot refuses them already)
  Datagrams d;
  format(spec_, pose, d);
  bool whole = true;
  for (std::size_t i = 0; i < d.count && whole; ++i) whole = d.size[i] > 0 && send(std::span(d.bytes[i].data(), d.size[i]));
  if (whole) sent_.fetch_add(1, std::memory_order_relaxed);
}

SendCounters PoseSender::counters() const {
  return {sent_.load(std::memory_order_relaxed), dropped_.load(std::memory_order_relaxed),
          failed_.load(std::memory_order_relaxed), last_error_.load(std::memory_order_relaxed)};
}

std::string PoseSender::describe() const {
  std::string s = spec_.kind == SendSpec::Kind::osc ? "osc " : "opentrack ";
  s += spec_.host + ":" + std::to_string(spec_.port);
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g/s", spec_.rate_hz);
  s += spec_.kind == SendSpec::Kind::osc ? " (" + std::string(send_format_name(spec_.format)) + ", " + rate + ")"
                                         : std::string(" (") + rate + ")";
  return s;
}

PoseSenders::PoseSenders(const std::vector<SendSpec>& specs) {
  for (const SendSpec& s : specs) senders_.push_back(std::make_unique<PoseSender>(s));
}

std::string PoseSenders::summary() const {
  std::string out;
  for (const auto& s : senders_) {
    const SendCounters c = s->counters();
    out += "sent " + std::to_string(c.sent) + " poses to " + s->describe();
    if (c.dropped) out += ", " + std::to_string(c.dropped) + " dropped (socket full)";
    if (c.failed) out += ", " + std::to_string(c.failed) + " failed (" + std::strerror(c.last_error) + ")";
    out += "\n";
  }
  return out;
}

}  // namespace earshot::tracker
