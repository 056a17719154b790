#include "earshot/audio/binaural_convolver.hpp"

#include <algorithm>
#include <stdexcept>

#include "earshot/audio/hrtf_spectra.hpp"
#include "earshot/audio/spectral_kernels.hpp"

namespace earshot::audio {

BinauralConvolver::BinauralConvolver(std::size_t block, std::size_t max_filter_length)
    : block_(block),
      parts_(std::max<std::size_t>(1, block ? (max_filter_length + block - 1) / block : 1)),
      stride_(partition_stride(block)) {
  if (block == 0) throw std::invalid_argument("BinauralConvolver: block must be > 0");
  for (auto& in : input_) in.assign(2 * block, 0.0f);
  padded_.assign(2 * block, 0.0f);
  spectrum_.assign(stride_, {});
  for (auto& h : history_) h.assign(parts_ * 2 * stride_, 0.0f);
  for (auto& bank : filters_)
    for (auto& ear : bank) ear.assign(parts_ * 2 * stride_, 0.0f);
}

void BinauralConvolver::reset() {
  for (auto& in : input_) std::fill(in.begin(), in.end(), 0.0f);
  for (auto& h : history_) std::fill(h.begin(), h.end(), 0.0f);
}

void BinauralConvolver::set_filters(std::span<const float> left, std::span<const float> right, const RealFft& fft) {
  if (left.size() > parts_ * block_ || right.size() > parts_ * block_)
    throw std::invalid_argument("BinauralConvolver: filter longer than max_filter_length");
  if (fft.size() != 2 * block_) throw std::invalid_argument("BinauralConvolver: FFT size must be twice the block");
  const auto banks = begin_filter_update();
  for (std::size_t ear = 0; ear < 2; ++ear) {
    const std::span<const float> ir = ear == 0 ? left : right;
    // Partition p holds taps [pB, pB + B) zero-padded to 2B.
    for (std::size_t p = 0; p < parts_; ++p) {
      std::fill(padded_.begin(), padded_.end(), 0.0f);
      const std::size_t from = p * block_;
      if (from < ir.size())
        std::copy_n(ir.begin() + static_cast<std::ptrdiff_t>(from), std::min(block_, ir.size() - from), padded_.begin());
      std::fill_n(banks[ear].begin() + static_cast<std::ptrdiff_t>(p * 2 * stride_), 2 * stride_, 0.0f);
      fft.forward(padded_, std::span(spectrum_).first(block_ + 1));
      kernels::to_planar(spectrum_.data(), block_ + 1, banks[ear].data() + p * 2 * stride_, stride_);
    }
  }
  end_filter_update();
}

std::array<std::span<float>, 2> BinauralConvolver::begin_filter_update() {
  // The first filters take effect at once; later ones go to the other bank
  // and are crossfaded in during the next process().
  const int target = have_filters_ ? 1 - current_ : current_;
  return {std::span(filters_[target][0]), std::span(filters_[target][1])};
}

void BinauralConvolver::end_filter_update() {
  pending_ = have_filters_;
  have_filters_ = true;
}

void BinauralConvolver::process(std::span<const float> left_in, std::span<const float> right_in, BinauralBus& bus) {
  const std::size_t B = block_, bins = B + 1, P = 2 * stride_;  // P: floats per planar partition
  head_ = (head_ + 1) % parts_;
  const int cur = current_, next = 1 - cur;
  for (std::size_t ear = 0; ear < 2; ++ear) {
    AlignedVector<float>& in = input_[ear];
    std::copy_n(in.begin() + static_cast<std::ptrdiff_t>(B), B, in.begin());
    std::copy_n((ear == 0 ? left_in : right_in).begin(), B, in.begin() + static_cast<std::ptrdiff_t>(B));
    float* hist = history_[ear].data();
    bus.fft().forward(in, std::span(spectrum_).first(bins));
    kernels::to_planar(spectrum_.data(), bins, hist + head_ * P, stride_);
    if (!pending_) {
      float* acc = bus.accumulator(ear, BinauralBus::Fade::steady);
      for (std::size_t p = 0; p < parts_; ++p) {
        // Partition p meets the input spectrum of p blocks ago.
        const std::size_t h = (head_ + parts_ - p) % parts_;
        kernels::multiply_add(hist + h * P, filters_[cur][ear].data() + p * P, acc, stride_);
      }
    } else {
      float* out = bus.accumulator(ear, BinauralBus::Fade::out);
      float* in_acc = bus.accumulator(ear, BinauralBus::Fade::in);
      for (std::size_t p = 0; p < parts_; ++p) {
        const std::size_t h = (head_ + parts_ - p) % parts_;
        kernels::multiply_add2(hist + h * P, filters_[cur][ear].data() + p * P, filters_[next][ear].data() + p * P,
                               out, in_acc, stride_);
      }
    }
  }
  if (pending_) {
    current_ = next;
    pending_ = false;
  }
}

}  // namespace earshot::audio
