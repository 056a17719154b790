#include "panner_switch.hpp"

#include <algorithm>

#include "earshot/audio/crossfade.hpp"

namespace earshot::lv2 {

PannerSwitch::PannerSwitch(std::unique_ptr<BinauralPanner> first)
    : current_(std::move(first)), in_(kChunk), old_l_(kChunk), old_r_(kChunk) {}

std::unique_ptr<BinauralPanner> PannerSwitch::switch_to(std::unique_ptr<BinauralPanner> next) {
  std::unique_ptr<BinauralPanner> dropped = std::move(old_);  // a switch cut short
  old_ = std::move(current_);
  current_ = std::move(next);
  since_ = 0;
  return dropped;
}

std::unique_ptr<BinauralPanner> PannerSwitch::finished() { return std::move(done_); }

void PannerSwitch::update(const PannerParams& p) {
  current_->update(p);
  if (old_) old_->update(p);
}

void PannerSwitch::reset() {
  current_->reset();
  if (old_) {
    done_ = std::move(old_);  // nothing to fade from after a reset
  }
}

void PannerSwitch::process(const float* in, float* left, float* right, std::size_t frames) {
  if (!old_) {
    current_->process(in, left, right, frames);
    return;
  }
  std::size_t done = 0;
  while (done < frames) {
    const std::size_t n = std::min(kChunk, frames - done);
    // The input first: the host may have given one buffer for input and output.
    std::copy_n(in + done, n, in_.begin());
    old_->process(in_.data(), old_l_.data(), old_r_.data(), n);
    current_->process(in_.data(), left + done, right + done, n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t t = since_ + i;
      const float g = audio::crossfade_gain(t, kWarm, kFade);
      left[done + i] = g * left[done + i] + (1.0f - g) * old_l_[i];
      right[done + i] = g * right[done + i] + (1.0f - g) * old_r_[i];
    }
    since_ += n;
    done += n;
    if (since_ >= kWarm + kFade) {
      done_ = std::move(old_);
      // The rest of this call goes to the new panner alone.
      if (done < frames) current_->process(in + done, left + done, right + done, frames - done);
      return;
    }
  }
}

}  // namespace earshot::lv2
