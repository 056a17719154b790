#include "earshot/audio/ambisonics/ambisonic_bus.hpp"

#include <algorithm>
#include <stdexcept>

namespace earshot::ambisonics {

AmbisonicBus::AmbisonicBus(const DecoderFilters& filters, std::size_t block, std::size_t voices)
    : block_(block), decoder_(filters, block), bus_(filters.channels() * block, 0.0f), left_(block), right_(block) {
  if (voices == 0) throw std::invalid_argument("AmbisonicBus: no voices");
  encoders_.reserve(voices);
  for (std::size_t i = 0; i < voices; ++i) encoders_.emplace_back(filters.order, block);
}

void AmbisonicBus::reset_voice(std::size_t voice) {
  if (voice < encoders_.size()) encoders_[voice].reset();
}

void AmbisonicBus::begin_block() { std::fill(bus_.begin(), bus_.end(), 0.0f); }

void AmbisonicBus::add(std::size_t voice, const Vec3& direction, float gain, std::span<const float> signal) {
  if (voice >= encoders_.size() || signal.size() < block_) return;
  Encoder& e = encoders_[voice];
  e.update(direction, gain);
  e.process(signal, bus_);
}

void AmbisonicBus::mix_into(std::span<float> left, std::span<float> right) {
  decoder_.process(bus_, left_, right_);
  const std::size_t n = std::min({left.size(), right.size(), block_});
  for (std::size_t i = 0; i < n; ++i) {
    left[i] += left_[i];
    right[i] += right_[i];
  }
}

}  // namespace earshot::ambisonics
