// The panner in use, and the switch to a new one (another SOFA set) without
// a gap or a click: a new panner starts with an empty FIFO and empty
// convolution history, so for kWarm frames both run on the same input and
// the old one is heard; then the output fades from old to new over kFade
// frames (a raised cosine: earshot/audio/crossfade.hpp); then the old one is
// released (finished()) for the worker to free. Real-time safe: scratch buffers are allocated at construction, and
// update() / process() never allocate, lock or do I/O.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "binaural_panner.hpp"

namespace earshot::lv2 {

class PannerSwitch {
 public:
  /// Frames both panners run before the fade (covers the new one's FIFO
  /// latency and most of an HRIR's history), and the fade's length.
  static constexpr std::size_t kWarm = 512, kFade = 512;

  explicit PannerSwitch(std::unique_ptr<BinauralPanner> first);

  /// Starts the switch to `next`. A switch still under way is cut short: the
  /// panner that was fading out is returned (free it off the audio thread).
  [[nodiscard]] std::unique_ptr<BinauralPanner> switch_to(std::unique_ptr<BinauralPanner> next);
  /// The panner that has faded out, once (then empty until the next switch).
  [[nodiscard]] std::unique_ptr<BinauralPanner> finished();

  void update(const PannerParams& p);
  /// As BinauralPanner::process (any frames; `in` may alias an output).
  void process(const float* in, float* left, float* right, std::size_t frames);
  void reset();

  [[nodiscard]] BinauralPanner& current() { return *current_; }
  [[nodiscard]] bool switching() const { return old_ != nullptr; }

 private:
  static constexpr std::size_t kChunk = 1024;
  std::unique_ptr<BinauralPanner> current_, old_, done_;
  std::size_t since_ = 0;  // frames since the switch began
  std::vector<float> in_, old_l_, old_r_;
};

}  // namespace earshot::lv2
