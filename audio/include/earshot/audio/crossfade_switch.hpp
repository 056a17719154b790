// The unit in use (a renderer, a panner: anything that renders audio) and
// the switch to a new one (another HRTF set) without a gap or a click. A new
// unit starts with empty delay lines and convolution history, so for kWarm
// frames both run on the same input and only the old one is heard; then the
// output moves from the old one's to the new one's over kFade frames
// (crossfade_gain, a raised cosine); then the old one is handed back
// (finished()) to be freed off the audio thread.
//
// Feeding both units the same input and rendering the old one is the
// caller's (what "input" is differs: a renderer's source blocks, a panner's
// mono input); the switch owns the units, counts the frames and blends.
// Real-time safe: switch_to, blend, finished and cut only move pointers and
// do arithmetic.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <utility>

#include "earshot/audio/crossfade.hpp"

namespace earshot::audio {

template <typename Unit>
class CrossfadeSwitch {
 public:
  /// Frames both units run before the fade (covers a new unit's FIFO
  /// latency and most of an HRIR's history), and the fade's length.
  static constexpr std::size_t kWarm = 512, kFade = 512;

  explicit CrossfadeSwitch(std::unique_ptr<Unit> first = nullptr) : current_(std::move(first)) {}

  /// Makes `next` the unit in use and starts fading from the one before. A
  /// switch still under way is cut short: the unit that was fading out is
  /// returned (free it off the audio thread).
  [[nodiscard]] std::unique_ptr<Unit> switch_to(std::unique_ptr<Unit> next) {
    std::unique_ptr<Unit> dropped = std::move(old_);
    old_ = std::move(current_);
    current_ = std::move(next);
    since_ = 0;
    return dropped;
  }

  [[nodiscard]] Unit& current() { return *current_; }
  [[nodiscard]] const Unit& current() const { return *current_; }
  /// The unit fading out (render it on the same input), or null.
  [[nodiscard]] Unit* fading() { return old_.get(); }
  [[nodiscard]] bool switching() const { return old_ != nullptr; }

  /// Blends the next left.size() frames of a switch: each output frame
  /// becomes g x its value + (1 - g) x the fading unit's (`old_left`,
  /// `old_right`, as long as `left`). When the fade is complete the fading
  /// unit is released to finished(). Nothing to do without a switch.
  void blend(std::span<float> left, std::span<float> right, std::span<const float> old_left,
             std::span<const float> old_right) {
    if (!old_) return;
    for (std::size_t i = 0; i < left.size(); ++i) {
      const float g = crossfade_gain(since_ + i, kWarm, kFade);
      left[i] = g * left[i] + (1.0f - g) * old_left[i];
      right[i] = g * right[i] + (1.0f - g) * old_right[i];
    }
    since_ += left.size();
    if (since_ >= kWarm + kFade) done_ = std::move(old_);
  }

  /// Frames of the switch under way blended so far.
  [[nodiscard]] std::size_t frames_blended() const { return since_; }
  /// Frames until the fade is complete (0 without a switch).
  [[nodiscard]] std::size_t frames_left() const { return old_ && since_ < kWarm + kFade ? kWarm + kFade - since_ : 0; }

  /// Ends a switch at once (after a reset there is nothing to fade from):
  /// the fading unit goes to finished().
  void cut() {
    if (old_) done_ = std::move(old_);
  }

  /// The unit that has faded out, once (then null until the next one).
  [[nodiscard]] std::unique_ptr<Unit> finished() { return std::move(done_); }

 private:
  std::unique_ptr<Unit> current_, old_, done_;
  std::size_t since_ = 0;  // frames since the switch began
};

}  // namespace earshot::audio
