#include "ambi_decoder.hpp"

#include <algorithm>

namespace earshot::lv2 {

AmbiDecoder::AmbiDecoder(std::shared_ptr<const ambisonics::DecoderFilters> filters, double sample_rate)
    : rate_(sample_rate),
      filters_(std::move(filters)),
      bed_(*filters_, kBlock),
      in_(filters_->channels() * kBlock, 0.0f),
      out_l_(kBlock, 0.0f),
      out_r_(kBlock, 0.0f) {
  bed_.reset(head_);
}

void AmbiDecoder::process(const float* const* in, float* left, float* right, std::size_t frames) {
  const std::size_t C = channels();
  std::size_t done = 0;
  while (done < frames) {
    const std::size_t n = std::min(frames - done, kBlock - fill_);
    // Every input first: the host may pass one of them as an output buffer.
    for (std::size_t c = 0; c < C; ++c) {
      float* dst = in_.data() + c * kBlock + fill_;
      if (in && in[c]) std::copy_n(in[c] + done, n, dst);
      else std::fill_n(dst, n, 0.0f);
    }
    std::copy_n(out_l_.begin() + static_cast<std::ptrdiff_t>(fill_), n, left + done);
    std::copy_n(out_r_.begin() + static_cast<std::ptrdiff_t>(fill_), n, right + done);
    fill_ += n;
    done += n;
    if (fill_ == kBlock) {
      render_block();
      fill_ = 0;
    }
  }
}

void AmbiDecoder::render_block() {
  bed_.set_orientation(head_);
  bed_.process(in_, out_l_, out_r_);
}

void AmbiDecoder::reset() {
  std::fill(in_.begin(), in_.end(), 0.0f);
  std::fill(out_l_.begin(), out_l_.end(), 0.0f);
  std::fill(out_r_.begin(), out_r_.end(), 0.0f);
  fill_ = 0;
  bed_.reset(head_);
}

}  // namespace earshot::lv2
