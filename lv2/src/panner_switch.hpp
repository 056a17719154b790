// The panner in use, and the switch to a new one (another SOFA set) without
// a gap or a click: the project's one HRTF switch (audio::CrossfadeSwitch:
// both run on the same input for a warm-up, then a raised-cosine fade, then
// the old one is released, finished(), for the worker to free), fed the
// panner's way: the host's buffer of any length, in chunks the scratch
// buffers hold. Real-time safe: scratch buffers are allocated at
// construction, and update() / process() never allocate, lock or do I/O.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "binaural_panner.hpp"
#include "earshot/audio/crossfade_switch.hpp"

namespace earshot::lv2 {

class PannerSwitch {
 public:
  using Switch = audio::CrossfadeSwitch<BinauralPanner>;
  static constexpr std::size_t kWarm = Switch::kWarm, kFade = Switch::kFade;

  explicit PannerSwitch(std::unique_ptr<BinauralPanner> first);

  /// Starts the switch to `next`. A switch still under way is cut short: the
  /// panner that was fading out is returned (free it off the audio thread).
  [[nodiscard]] std::unique_ptr<BinauralPanner> switch_to(std::unique_ptr<BinauralPanner> next) {
    return switch_.switch_to(std::move(next));
  }
  /// The panner that has faded out, once (then empty until the next switch).
  [[nodiscard]] std::unique_ptr<BinauralPanner> finished() { return switch_.finished(); }

  void update(const PannerParams& p);
  /// As BinauralPanner::process (any frames; `in` may alias an output).
  void process(const float* in, float* left, float* right, std::size_t frames);
  void reset();

  [[nodiscard]] BinauralPanner& current() { return switch_.current(); }
  [[nodiscard]] bool switching() const { return switch_.switching(); }

 private:
  static constexpr std::size_t kChunk = 1024;
  Switch switch_;
  std::vector<float> in_, old_l_, old_r_;
};

}  // namespace earshot::lv2
