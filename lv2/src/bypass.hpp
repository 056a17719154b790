// The plugin's bypass (lv2:enabled): switched off, the output is the input
// on both channels, delayed by the renderer's latency so that it lines up
// with what the plugin played before and hosts' latency compensation holds;
// switching fades between the two over kFadeFrames (no click). The renderer
// keeps running while bypassed, so switching back is seamless too.
//
// The host may pass the same buffer for the input and an output: the input
// is copied, a chunk at a time, before the renderer writes over it. No
// allocation after construction; real-time safe.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace earshot::lv2 {

class Bypass {
 public:
  /// Frames of the fade between the rendered output and the dry input.
  static constexpr std::size_t kFadeFrames = 1024;
  static constexpr std::size_t kChunk = 128;

  /// `latency`: frames the dry input is delayed by (the renderer's). Allocates.
  explicit Bypass(std::size_t latency) : delay_(std::max<std::size_t>(latency, 1), 0.0f), latency_(latency) {}

  /// Renders `frames` of `in` with `render(in, left, right, n)` (in chunks)
  /// and mixes in the delayed input as far as the fade towards `enabled` has
  /// gone. Safe with `in` equal to `left` or `right`.
  template <class Render>
  void process(const float* in, float* left, float* right, std::uint32_t frames, bool enabled, Render&& render) {
    const float target = enabled ? 1.0f : 0.0f;
    const float step = 1.0f / static_cast<float>(kFadeFrames);
    std::array<float, kChunk> dry{};
    for (std::uint32_t at = 0; at < frames;) {
      const std::uint32_t n = std::min<std::uint32_t>(frames - at, kChunk);
      std::copy(in + at, in + at + n, dry.begin());
      render(in + at, left + at, right + at, n);
      for (std::uint32_t i = 0; i < n; ++i) {
        float delayed = dry[i];
        if (latency_ > 0) {
          delayed = delay_[pos_];
          delay_[pos_] = dry[i];
          pos_ = pos_ + 1 == delay_.size() ? 0 : pos_ + 1;
        }
        if (wet_ != target) wet_ = wet_ < target ? std::min(target, wet_ + step) : std::max(target, wet_ - step);
        if (wet_ < 1.0f) {
          left[at + i] = wet_ * left[at + i] + (1.0f - wet_) * delayed;
          right[at + i] = wet_ * right[at + i] + (1.0f - wet_) * delayed;
        }
      }
      at += n;
    }
  }

  /// 1: the rendered output only; 0: the dry input only.
  [[nodiscard]] float wet() const { return wet_; }
  /// Straight to the state `enabled` asks for, no fade (the first block after activate).
  void reset(bool enabled) { wet_ = enabled ? 1.0f : 0.0f; }

 private:
  std::vector<float> delay_;
  std::size_t latency_ = 0, pos_ = 0;
  float wet_ = 1.0f;
};

}  // namespace earshot::lv2
