// PoseSlot: one writer (the tracker thread) publishes head poses; any number
// of readers (the audio callback, the GUI) load the newest one without ever
// blocking the writer or taking a lock.
//
// A sequence lock over atomic words: the writer makes the sequence odd,
// stores the pose's words, makes it even again; a reader copies the words
// and keeps the copy only if the sequence was even and unchanged around it,
// so a pose is never torn. Every access is atomic, so the slot is free of
// data races by the C++ memory model. The ordering comes from release
// stores and acquire loads of the words themselves rather than from fences
// (Boehm's seqlock without fences): a reader that sees any new word also sees
// the odd sequence that preceded it. On x86 these are plain moves, and
// ThreadSanitizer models them (it does not model fences). A reader
// retries only while a write is in flight (a few dozen nanoseconds at a
// 1 kHz write rate); `try_load` never retries, for callers that must not.
// A non-finite pose is refused at `publish`: bad numbers stop at the edge.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <optional>
#include <type_traits>

#include "earshot/head_pose.hpp"

namespace earshot {

class PoseSlot {
 public:
  PoseSlot() { store_words(HeadPose{}); }
  PoseSlot(const PoseSlot&) = delete;
  PoseSlot& operator=(const PoseSlot&) = delete;

  /// Writer side (one thread only). Returns false, publishing nothing, for a
  /// non-finite pose. The sequence number is assigned here.
  bool publish(HeadPose p) {
    if (!p.finite()) return false;
    const std::uint64_t s = seq_.load(std::memory_order_relaxed);
    p.sequence = s / 2 + 1;
    seq_.store(s + 1, std::memory_order_relaxed);
    store_words(p);  // release: orders the odd sequence before each word
    seq_.store(s + 2, std::memory_order_release);
    return true;
  }

  /// Reader side, any thread: the newest pose, never torn.
  [[nodiscard]] HeadPose load() const {
    for (;;)
      if (auto p = try_load()) return *p;
  }

  /// One attempt: nullopt when a write was in flight.
  [[nodiscard]] std::optional<HeadPose> try_load() const {
    const std::uint64_t s1 = seq_.load(std::memory_order_acquire);
    if (s1 & 1u) return std::nullopt;
    std::array<std::uint64_t, kWords> w;
    // acquire: a word from a newer write makes its odd sequence visible below.
    for (std::size_t i = 0; i < kWords; ++i) w[i] = words_[i].load(std::memory_order_acquire);
    if (seq_.load(std::memory_order_relaxed) != s1) return std::nullopt;
    HeadPose p;
    std::memcpy(static_cast<void*>(&p), w.data(), sizeof(HeadPose));  // HeadPose is trivially copyable
    return p;
  }

 private:
  static_assert(std::is_trivially_copyable_v<HeadPose>);
  static constexpr std::size_t kWords = (sizeof(HeadPose) + 7) / 8;

  void store_words(const HeadPose& p) {
    std::array<std::uint64_t, kWords> w{};
    std::memcpy(w.data(), &p, sizeof(HeadPose));
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(w[i], std::memory_order_release);
  }

  alignas(64) std::atomic<std::uint64_t> seq_{0};
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "PoseSlot needs lock-free 64-bit atomics");

}  // namespace earshot
