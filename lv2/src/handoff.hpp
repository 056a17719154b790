// Objects crossing between the audio thread and the LV2 worker, owned by
// the plugin instance the whole time: N atomic slots. One side put()s an
// object and sends the slot's number in a worker message; the other take()s
// it. Whatever is still in a slot when the instance goes (a host that
// cleans up with work or answers pending) is freed then, never leaked.
// put() and take() are an atomic compare-exchange or exchange: no lock, no
// allocation, safe on the audio thread.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <memory>

namespace earshot::lv2 {

template <class T, std::size_t N>
class Handoff {
 public:
  Handoff() {
    for (auto& s : slots_) s.store(nullptr, std::memory_order_relaxed);
  }
  ~Handoff() {
    for (auto& s : slots_) std::unique_ptr<T> owned(s.exchange(nullptr, std::memory_order_acquire));
  }
  Handoff(const Handoff&) = delete;
  Handoff& operator=(const Handoff&) = delete;

  /// Moves `p` into a free slot and returns its number; -1 when every slot
  /// is taken (then `p` stays with the caller).
  int put(std::unique_ptr<T>& p) {
    for (std::size_t i = 0; i < N; ++i) {
      T* expected = nullptr;
      if (slots_[i].compare_exchange_strong(expected, p.get(), std::memory_order_release, std::memory_order_relaxed)) {
        (void)p.release();  // the slot owns it now
        return static_cast<int>(i);
      }
    }
    return -1;
  }

  /// The object in slot `i` (empty for a bad number or an empty slot).
  [[nodiscard]] std::unique_ptr<T> take(int i) {
    if (i < 0 || static_cast<std::size_t>(i) >= N) return {};
    return std::unique_ptr<T>(slots_[static_cast<std::size_t>(i)].exchange(nullptr, std::memory_order_acquire));
  }

 private:
  std::array<std::atomic<T*>, N> slots_;
};

}  // namespace earshot::lv2
