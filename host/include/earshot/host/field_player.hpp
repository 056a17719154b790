// A bed's player: a FieldStream (scenes/field_stream.hpp) read ahead on the
// control thread into a lock-free ring, and the plugin's field callback
// (esSourceAmbisonicCallback) taking each block from the ring on the audio
// thread. The file is read, converted and resampled only on the control
// thread (pump(), from SceneSources::move: once per block offline, once per
// control tick live), never in esRender.
//
// One writer (pump), one reader (the callback): the ring's two indices are
// atomics (release stores, acquire loads). The callback never allocates,
// locks or does I/O; what the ring lacks (the control thread fell behind)
// is silence, counted in underruns().
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "earshot/earshot.h"
#include "earshot/scenes/field_stream.hpp"

namespace earshot::host {

class FieldPlayer {
 public:
  /// Opens the bed's file (throws InputError naming it) and fills the ring.
  /// `ahead_frames`: how far pump() reads ahead (at least two blocks).
  FieldPlayer(const scenes::SceneBed& bed, double sample_rate, std::size_t ahead_frames);

  [[nodiscard]] int order() const { return stream_.order(); }
  [[nodiscard]] std::size_t channels() const { return stream_.channels(); }
  [[nodiscard]] const scenes::FieldStream& stream() const { return stream_; }

  /// Control thread: reads the file until the ring holds `ahead_frames`
  /// (or the bed has ended).
  void pump();
  /// Blocks the audio thread found short (silence instead).
  [[nodiscard]] std::uint64_t underruns() const { return underruns_.load(std::memory_order_relaxed); }

  /// The callback for esSourceAmbisonicCallback (`user` is this player).
  static void pull(void* user, float* out, ESuint channels, ESuint frames);

 private:
  void take(float* planar, std::size_t channels, std::size_t frames);  // audio thread

  scenes::FieldStream stream_;
  std::size_t capacity_;         // frames the ring holds (one slot kept free)
  std::vector<float> ring_;      // capacity_ frames, interleaved
  std::vector<float> chunk_;     // pump()'s read buffer
  std::atomic<std::size_t> write_{0}, read_{0};  // frame indices into the ring
  std::atomic<std::uint64_t> underruns_{0};
  std::atomic<bool> ended_{false};  // nothing more will come (set by pump)
};

}  // namespace earshot::host
