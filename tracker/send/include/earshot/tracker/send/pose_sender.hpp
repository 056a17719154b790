// Pose output: the tracker's listener poses sent on to other programs (IEM's
// SceneRotator, SPARTA's plug-ins, opentrack, another Earshot) as each
// expects them (send_spec.hpp has the formats).
//
// Called on the tracker thread with every pose it publishes (the poses
// `track live --record` writes), a sender never blocks it: its UDP socket is
// non-blocking and a datagram the kernel cannot take at once is dropped and
// counted. It sends at most `rate_hz` poses a second on average on the
// steady clock (a bucket of one and a half poses, so jitter in the source's
// timing does not halve the rate), always the newest: a source faster than
// that, or running faster than real time (a replay with --fast), is thinned,
// not queued. Opening resolves the host and creates the socket (throws
// std::runtime_error naming the spec); nothing after that allocates.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "earshot/head_pose.hpp"
#include "earshot/tracker/send/send_spec.hpp"

namespace earshot::tracker {

/// What a sender did, for status lines (read from any thread).
struct SendCounters {
  std::uint64_t sent = 0;     ///< poses sent whole (every datagram of the format taken)
  std::uint64_t dropped = 0;  ///< poses not sent: the socket's buffer was full (EWOULDBLOCK, ENOBUFS)
  std::uint64_t failed = 0;   ///< poses not sent: another error (no route, ...); see last_error
  int last_error = 0;         ///< errno of the last failure, 0 if none
};

/// The datagrams one pose makes in a format (tests, tools): each as bytes.
[[nodiscard]] std::vector<std::vector<std::uint8_t>> pose_datagrams(const SendSpec& spec, const HeadPose& pose);

class PoseSender {
 public:
  using Clock = std::chrono::steady_clock;

  /// Resolves the host (IPv4) and opens a non-blocking UDP socket. Throws
  /// std::runtime_error "send 'SPEC': ..." when the host does not resolve or
  /// the socket cannot be made.
  explicit PoseSender(SendSpec spec);
  ~PoseSender();
  PoseSender(const PoseSender&) = delete;
  PoseSender& operator=(const PoseSender&) = delete;

  /// The newest pose at steady time `now`: sent when the rate allows,
  /// otherwise skipped (a later one will go). Tracker thread only; never blocks.
  void offer(const HeadPose& pose, Clock::time_point now);

  [[nodiscard]] SendCounters counters() const;
  [[nodiscard]] const SendSpec& spec() const { return spec_; }
  /// "osc 127.0.0.1:9000 (sparta, 100/s)".
  [[nodiscard]] std::string describe() const;

 private:
  bool send(std::span<const std::uint8_t> bytes);

  SendSpec spec_;
  int fd_ = -1;
  std::array<std::uint8_t, 16> address_{};  // sockaddr_in, resolved once
  double tokens_ = 1.5;                      // the rate bucket
  Clock::time_point last_{};
  bool started_ = false;
  std::atomic<std::uint64_t> sent_{0}, dropped_{0}, failed_{0};
  std::atomic<int> last_error_{0};
};

/// Every sender of a tracker: offers each pose to each.
class PoseSenders {
 public:
  PoseSenders() = default;
  /// Opens one sender per spec (throws as PoseSender does; none is left open).
  explicit PoseSenders(const std::vector<SendSpec>& specs);
  void offer(const HeadPose& pose, PoseSender::Clock::time_point now) {
    for (auto& s : senders_) s->offer(pose, now);
  }
  [[nodiscard]] bool empty() const { return senders_.empty(); }
  [[nodiscard]] const std::vector<std::unique_ptr<PoseSender>>& senders() const { return senders_; }
  /// One line per sender: where, how many sent, dropped, failed.
  [[nodiscard]] std::string summary() const;

 private:
  std::vector<std::unique_ptr<PoseSender>> senders_;
};

}  // namespace earshot::tracker
