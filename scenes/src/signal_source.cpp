#include "earshot/scenes/signal_source.hpp"

#include <samplerate.h>
#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "earshot/errors.hpp"

namespace earshot::scenes {
namespace {

struct SndfileClose {
  void operator()(SNDFILE* f) const { sf_close(f); }
};

/// The whole file as mono at `rate`.
std::vector<float> read_file(const std::filesystem::path& path, double rate) {
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError::at(name, 0, "", "audio file not found");
  SF_INFO info{};
  std::unique_ptr<SNDFILE, SndfileClose> f(sf_open(path.c_str(), SFM_READ, &info));
  if (!f) throw InputError::at(name, 0, "", std::string("cannot read audio file: ") + sf_strerror(nullptr));
  if (info.frames <= 0 || info.channels <= 0) throw InputError::at(name, 0, "", "audio file holds no samples");
  const auto ch = static_cast<std::size_t>(info.channels);
  std::vector<float> inter(static_cast<std::size_t>(info.frames) * ch);
  const auto got = static_cast<std::size_t>(std::max<sf_count_t>(0, sf_readf_float(f.get(), inter.data(), info.frames)));
  if (got == 0) throw InputError::at(name, 0, "", "audio file holds no readable samples");
  std::vector<float> mono(got);
  for (std::size_t i = 0; i < got; ++i) {
    float sum = 0.0f;
    for (std::size_t c = 0; c < ch; ++c) sum += inter[i * ch + c];
    mono[i] = sum / static_cast<float>(ch);
  }
  if (std::abs(info.samplerate - rate) <= 0.5) return mono;
  // Resample: libsamplerate's sinc converter, in one deterministic pass.
  const double ratio = rate / info.samplerate;
  std::vector<float> out(static_cast<std::size_t>(std::ceil(static_cast<double>(got) * ratio)) + 16);
  SRC_DATA d{};
  d.data_in = mono.data();
  d.input_frames = static_cast<long>(got);
  d.data_out = out.data();
  d.output_frames = static_cast<long>(out.size());
  d.src_ratio = ratio;
  if (const int err = src_simple(&d, SRC_SINC_MEDIUM_QUALITY, 1); err != 0)
    throw InputError::at(name, 0, "",
                         "cannot resample from " + std::to_string(info.samplerate) + " Hz: " + src_strerror(err));
  out.resize(static_cast<std::size_t>(d.output_frames_gen));
  if (out.empty()) throw InputError::at(name, 0, "", "audio file too short to resample");
  return out;
}

}  // namespace

SignalSource::SignalSource(const Signal& s, double rate) : sig_(s), rate_(rate), rng_(s.seed) {
  using T = Signal::Type;
  switch (s.type) {
    case T::noise: case T::sine: case T::impulse: break;
    case T::file: file_ = read_file(s.path, rate); break;
    case T::voice: synth_.emplace<VoiceSynth>(s.voice, rate); break;
    case T::talk: synth_.emplace<TalkSynth>(s.talk, s.seed, rate); break;
    case T::siren: synth_.emplace<SirenSynth>(s.siren, rate); break;
    case T::birds: synth_.emplace<BirdsSynth>(s.birds, s.seed, rate); break;
    case T::engine: synth_.emplace<EngineSynth>(s.engine, s.seed, rate); break;
    case T::horn: synth_.emplace<HornSynth>(s.horn, rate); break;
    case T::footsteps: synth_.emplace<FootstepsSynth>(s.footsteps, s.seed, rate); break;
    case T::ambience: synth_.emplace<AmbienceSynth>(s.ambience, s.seed, rate); break;
    case T::animal: synth_.emplace<AnimalSynth>(s.animal, s.seed, rate); break;
  }
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
    case Signal::Type::file: {
      const std::size_t len = file_.size();
      for (std::size_t i = 0; i < out.size(); ++i) {
        const std::uint64_t k = n_ + i;
        out[i] = sig_.loop ? file_[k % len] : (k < len ? file_[k] : 0.0f);
      }
      break;
    }
    default:
      std::visit(
          [out](auto& g) {
            if constexpr (!std::is_same_v<std::decay_t<decltype(g)>, std::monostate>) g.generate(out);
          },
          synth_);
      break;
  }
  // A last guard: resampled files may overshoot; nothing leaves above full scale or as NaN.
  for (float& x : out) x = std::isfinite(x) ? std::clamp(x, -1.0f, 1.0f) : 0.0f;
  n_ += out.size();
}

}  // namespace earshot::scenes
