#include "earshot/audio/room_reverb.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "earshot/errors.hpp"

namespace earshot::audio {
namespace {
constexpr double kMaxPredelayS = 0.3 + 0.1;  // EFX's longest reflections + late reverb delays
float db_gain(double db) { return db <= -120.0 ? 0.0f : static_cast<float>(std::pow(10.0, db / 20.0)); }
}  // namespace

LateReverbType late_reverb_type(std::string_view name) {
  if (name == "fdn") return LateReverbType::fdn;
  if (name == "schroeder") return LateReverbType::schroeder;
  throw InputError("unknown reverb '" + std::string(name) + "' (available: fdn, schroeder)");
}

RoomReverb::RoomReverb(double sample_rate, std::size_t block, const RoomParams& p, LateReverbType type)
    : rate_(sample_rate), block_(block), type_(type), early_(sample_rate, block) {
  validate(p);
  if (type == LateReverbType::fdn)
    fdn_.emplace(sample_rate, block);
  else
    schroeder_.emplace(sample_rate, block);
  filtered_.assign(block, 0.0f);
  late_in_.assign(block, 0.0f);
  late_l_.assign(block, 0.0f);
  late_r_.assign(block, 0.0f);
  predelay_ring_.assign(std::bit_ceil(static_cast<std::size_t>(std::ceil(kMaxPredelayS * sample_rate)) + block + 1),
                        0.0f);
  predelay_mask_ = predelay_ring_.size() - 1;
  update(p);
}

void RoomReverb::update(const RoomParams& p) {
  validate(p);
  params_ = p;
  const double f_hf = std::min(p.hf_reference_hz, 0.45 * rate_);
  const auto shelf = high_shelf4(f_hf / 2.2, f_hf, std::max(p.gain_hf, 1e-6), rate_);
  for (std::size_t s = 0; s < 2; ++s) input_filter_[s].set(shelf[s]);
  early_.update(p);
  double latency = 0.0;
  if (fdn_) {
    fdn_->update(p);
    latency = fdn_->latency_s();
  } else {
    schroeder_->update(p);
    latency = schroeder_->latency_s();
  }
  const double late_start = std::max(0.0, p.reflections_delay_s + p.late_reverb_delay_s - latency);
  predelay_ = std::min(predelay_ring_.size() - block_ - 1, static_cast<std::size_t>(std::lround(late_start * rate_)));
  wet_ = db_gain(p.wet_db) * static_cast<float>(p.gain);
  dry_ = db_gain(p.dry_db);
}

void RoomReverb::reset() {
  for (auto& f : input_filter_) f.reset();
  early_.reset();
  if (fdn_) fdn_->reset();
  if (schroeder_) schroeder_->reset();
  std::fill(predelay_ring_.begin(), predelay_ring_.end(), 0.0f);
}

void RoomReverb::process(std::span<const float> in, std::span<float> out_left, std::span<float> out_right) {
  const std::size_t n = std::min({in.size(), block_, out_left.size(), out_right.size()});
  auto x = std::span(filtered_).first(n);
  std::copy_n(in.begin(), n, x.begin());
  for (auto& f : input_filter_) f.process(x);
  auto late_in = std::span(late_in_).first(n);
  for (std::size_t i = 0; i < n; ++i) {
    predelay_ring_[write_] = x[i];
    late_in[i] = predelay_ring_[(write_ - predelay_) & predelay_mask_];
    write_ = (write_ + 1) & predelay_mask_;
  }
  auto ll = std::span(late_l_).first(n), lr = std::span(late_r_).first(n);
  if (fdn_)
    fdn_->process(late_in, ll, lr);
  else
    schroeder_->process(late_in, ll, lr);
  early_.process(x, ll, lr);
  for (std::size_t i = 0; i < n; ++i) {
    out_left[i] = wet_ * ll[i] + dry_ * in[i];
    out_right[i] = wet_ * lr[i] + dry_ * in[i];
  }
}

}  // namespace earshot::audio
