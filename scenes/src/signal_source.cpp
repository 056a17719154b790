#include "earshot/scenes/signal_source.hpp"

#include <sndfile.h>

#include <cmath>
#include <numbers>

#include "earshot/errors.hpp"

namespace earshot::scenes {

SignalSource::SignalSource(const Signal& s, double rate) : sig_(s), rate_(rate), rng_(s.seed) {
  if (s.type != Signal::Type::file) return;
  SF_INFO info{};
  SNDFILE* f = sf_open(s.path.c_str(), SFM_READ, &info);
  if (!f) throw InputError::at(s.path.string(), 0, "", std::string("cannot read audio file: ") + sf_strerror(nullptr));
  if (std::abs(info.samplerate - rate) > 0.5) {
    sf_close(f);
    throw InputError::at(s.path.string(), 0, "", "sample rate " + std::to_string(info.samplerate) +
                                                     " Hz differs from the scene's " +
                                                     std::to_string(static_cast<int>(rate)) + " Hz");
  }
  std::vector<float> inter(static_cast<std::size_t>(info.frames) * static_cast<std::size_t>(info.channels));
  const sf_count_t got = sf_readf_float(f, inter.data(), info.frames);
  sf_close(f);
  file_.resize(static_cast<std::size_t>(got));
  for (std::size_t i = 0; i < file_.size(); ++i) file_[i] = inter[i * static_cast<std::size_t>(info.channels)];  // first channel
}

void SignalSource::generate(std::span<float> out) {
  switch (sig_.type) {
    case Signal::Type::noise: {
      // White noise, uniform in [-1, 1): our own mapping of the 64-bit
      // generator, so every platform gives the same samples.
      for (float& x : out) x = static_cast<float>(static_cast<double>(rng_() >> 11) * 0x1.0p-52 - 1.0);
      break;
    }
    case Signal::Type::sine: {
      const double w = 2.0 * std::numbers::pi * sig_.frequency_hz / rate_;
      for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = static_cast<float>(std::sin(w * static_cast<double>(n_ + i)));
      break;
    }
    case Signal::Type::impulse:
      for (std::size_t i = 0; i < out.size(); ++i) out[i] = (n_ + i == 0) ? 1.0f : 0.0f;
      break;
    case Signal::Type::file:
      for (std::size_t i = 0; i < out.size(); ++i) out[i] = n_ + i < file_.size() ? file_[n_ + i] : 0.0f;
      break;
  }
  n_ += out.size();
}

}  // namespace earshot::scenes
