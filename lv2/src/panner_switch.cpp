#include "panner_switch.hpp"

#include <algorithm>
#include <span>

namespace earshot::lv2 {

PannerSwitch::PannerSwitch(std::unique_ptr<BinauralPanner> first)
    : switch_(std::move(first)), in_(kChunk), old_l_(kChunk), old_r_(kChunk) {}

void PannerSwitch::update(const PannerParams& p) {
  switch_.current().update(p);
  if (BinauralPanner* old = switch_.fading()) old->update(p);
}

void PannerSwitch::reset() {
  switch_.current().reset();
  switch_.cut();  // nothing to fade from after a reset
}

void PannerSwitch::process(const float* in, float* left, float* right, std::size_t frames) {
  std::size_t done = 0;
  while (done < frames) {
    BinauralPanner* old = switch_.fading();
    if (!old) {  // no switch, or it completed within this call: the new panner alone
      switch_.current().process(in + done, left + done, right + done, frames - done);
      return;
    }
    const std::size_t n = std::min(kChunk, frames - done);
    // The input first: the host may have given one buffer for input and output.
    std::copy_n(in + done, n, in_.begin());
    old->process(in_.data(), old_l_.data(), old_r_.data(), n);
    switch_.current().process(in_.data(), left + done, right + done, n);
    switch_.blend(std::span(left + done, n), std::span(right + done, n), std::span(old_l_.data(), n),
                  std::span(old_r_.data(), n));
    done += n;
  }
}

}  // namespace earshot::lv2
