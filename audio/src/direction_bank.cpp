#include "earshot/audio/direction_bank.hpp"

#include <algorithm>
#include <stdexcept>

#include "earshot/audio/spectral_kernels.hpp"

namespace earshot::audio {
namespace {

/// 2B floats rounded up to whole 64-byte lines, so every lane's input starts
/// aligned (the FFT's fast path).
std::size_t input_stride(std::size_t block) { return (2 * block + 15) / 16 * 16; }

}  // namespace

DirectionBank::DirectionBank(std::shared_ptr<const HrtfSpectra> spectra)
    : spectra_(std::move(spectra)),
      block_(spectra_ ? spectra_->block() : 0),
      parts_(spectra_ ? spectra_->partitions() : 0),
      stride_(partition_stride(block_)),
      measurements_(spectra_ ? spectra_->measurements() : 0),
      fft_(2 * std::max<std::size_t>(block_, 1)) {
  if (!spectra_) throw std::invalid_argument("DirectionBank: no HRTF spectra");
  const std::size_t lanes = 2 * measurements_, P = 2 * stride_;
  lanes_.assign(lanes, Lane{});
  input_.assign(lanes * input_stride(block_), 0.0f);
  active_.reserve(lanes);
  ahead_.assign(parts_ * 2 * P, 0.0f);
  ahead_used_.assign(parts_ * 2, 0);
  spectrum_.assign(stride_, {});
  planar_.assign(P, 0.0f);
  time_.assign(2 * block_, 0.0f);
  r_.resize(block_);
  r2_.resize(block_);
  for (std::size_t i = 0; i < block_; ++i) {
    r_[i] = (static_cast<float>(i) + 1.0f) / static_cast<float>(block_);
    r2_[i] = r_[i] * r_[i];
  }
}

void DirectionBank::add(std::size_t m, std::size_t ear, std::span<const float> x, GainCurve gain) {
  if (m >= measurements_ || ear > 1 || x.size() < block_) return;
  const std::size_t l = lane_index(m, ear);
  Lane& lane = lanes_[l];
  if (!lane.listed) {
    lane.listed = true;
    active_.push_back(static_cast<std::uint32_t>(l));
  }
  lane.has_input = true;
  float* in = input_.data() + l * input_stride(block_) + half_ * block_;
  kernels::add_shaped(x.data(), gain.c0, gain.c1, gain.c2, r_.data(), r2_.data(), in, block_);
}

void DirectionBank::prefetch(std::size_t m) const {
  if (m >= measurements_) return;
  for (std::size_t ear = 0; ear < 2; ++ear) {
    const float* in = input_.data() + lane_index(m, ear) * input_stride(block_) + half_ * block_;
    for (std::size_t i = 0; i < block_; i += 16) __builtin_prefetch(in + i, 1, 3);
  }
}

namespace {
/// The lines of n values from p onwards, asked for ahead of use.
template <class T>
void prefetch_lines(const T* p, std::size_t n) {
  const auto* bytes = reinterpret_cast<const char*>(p);
  for (std::size_t b = 0; b < n * sizeof(T); b += 64) __builtin_prefetch(bytes + b, 0, 3);
}
}  // namespace

void DirectionBank::process(std::span<float> left, std::span<float> right) {
  const std::size_t B = block_, bins = B + 1, P = 2 * stride_, in_stride = input_stride(B);
  lanes_run_ = 0;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < active_.size(); ++k) {
    const std::uint32_t l = active_[k];
    if (k + 1 < active_.size()) {
      // The next lane's input and spectra (several KB, streamed from the
      // outer caches) arrive while this lane's FFT runs.
      const std::size_t next = active_[k + 1];
      prefetch_lines(input_.data() + next * in_stride, 2 * B);
      const auto ne = static_cast<hrtf::Ear>(next & 1);
      const auto head = spectra_->head(next >> 1, ne);
      const auto tail = spectra_->tail(next >> 1, ne);
      prefetch_lines(head.data(), head.size());
      prefetch_lines(tail.data(), tail.size());
    }
    Lane& lane = lanes_[l];
    float* in = input_.data() + l * in_stride;
    // Listed lanes have input this block or the last: the window is not silence.
    float* x = planar_.data();
    // With half_ == 0 the window is [this | previous]: rotated by B, which
    // flips the sign of odd bins.
    fft_.forward_planar(std::span<const float>(in, 2 * B), x, stride_, half_ == 0);
    const std::size_t ear = l & 1;
    const auto e = static_cast<hrtf::Ear>(ear);
    const float* head = spectra_->head(l >> 1, e).data();
    const std::int16_t* tail = spectra_->tail(l >> 1, e).data();
    const float* scale = spectra_->tail_scale(l >> 1, e).data();
    // Partition p's product belongs to the output p blocks ahead.
    kernels::multiply_add(x, head, ahead_.data() + (now_ * 2 + ear) * P, stride_);
    ahead_used_[now_ * 2 + ear] = 1;
    for (std::size_t p = 1, slot = now_; p < parts_; ++p) {
      slot = slot + 1 == parts_ ? 0 : slot + 1;  // (now_ + p) % parts_, without a division per partition
      kernels::multiply_add_scaled(x, tail + (p - 1) * P, scale[p - 1], ahead_.data() + (slot * 2 + ear) * P, stride_);
      ahead_used_[slot * 2 + ear] = 1;
    }
    ++lanes_run_;
    // This block's half becomes the previous block; the next block adds
    // into the other half, which must start at zero.
    if (lane.prev_input) std::fill_n(in + (1 - half_) * B, B, 0.0f);
    lane.prev_input = lane.has_input;
    lane.has_input = false;
    if (lane.prev_input)
      active_[kept++] = l;  // its last block still enters the next FFT
    else
      lane.listed = false;
  }
  active_.resize(kept);

  for (std::size_t ear = 0; ear < 2; ++ear) {
    const std::size_t a = now_ * 2 + ear;
    if (!ahead_used_[a]) continue;
    float* acc = ahead_.data() + a * P;
    kernels::to_interleaved(acc, stride_, spectrum_.data(), bins);
    std::fill_n(acc, P, 0.0f);  // free for the block parts_ ahead
    ahead_used_[a] = 0;
    fft_.inverse_destroying(std::span(spectrum_).first(bins), time_);
    float* out = ear == 0 ? left.data() : right.data();
    const float* y = time_.data() + B;  // overlap-save: the last B samples are the block
    for (std::size_t i = 0; i < B; ++i) out[i] += y[i];
  }
  now_ = (now_ + 1) % parts_;
  half_ = 1 - half_;
}

void DirectionBank::reset() {
  std::fill(lanes_.begin(), lanes_.end(), Lane{});
  std::fill(input_.begin(), input_.end(), 0.0f);
  std::fill(ahead_.begin(), ahead_.end(), 0.0f);
  std::fill(ahead_used_.begin(), ahead_used_.end(), 0);
  active_.clear();
  half_ = 1;
}

}  // namespace earshot::audio
