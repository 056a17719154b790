#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

VoiceSynth::VoiceSynth(const VoiceParams& p, double rate) : p_(p), rate_(rate) {
  tilt_.cutoff(1800.0, rate);  // the glottal pulse's falling spectrum
  if (p_.melody.empty()) p_.melody = {0};
  if (p_.vowels.empty()) p_.vowels.push_back('a');
  f0_ = p_.pitch_hz * std::exp2(p_.melody[0] / 12.0);
  const auto f = synth::vowel_formants(p_.vowels[0]);
  formants_.jump({f.f1 * p_.formant_shift, f.f2 * p_.formant_shift, f.f3 * p_.formant_shift});
}

void VoiceSynth::generate(std::span<float> out) {
  const auto note_len = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(p_.note_s * rate_));
  const double glide = 1.0 - std::exp(-1.0 / (0.03 * rate_));  // 30 ms portamento
  for (float& y : out) {
    const std::uint64_t note = n_ / note_len;
    const double in_note = static_cast<double>(n_ % note_len) / rate_;
    const double target = p_.pitch_hz * std::exp2(p_.melody[note % p_.melody.size()] / 12.0);
    f0_ += glide * (target - f0_);
    // Vibrato grows in over the first 0.2 s of a note, as singers do.
    const double depth = p_.vibrato_cents / 1200.0 * std::min(1.0, in_note / 0.2);
    const double f = f0_ * std::exp2(depth * vib_.next(p_.vibrato_hz, rate_));
    const auto v = synth::vowel_formants(p_.vowels[note % p_.vowels.size()]);
    formants_.target({v.f1 * p_.formant_shift, v.f2 * p_.formant_shift, v.f3 * p_.formant_shift});
    // Legato: a short dip between notes, so they are heard as notes.
    const double edge = std::min(in_note, p_.note_s - in_note);
    const double env = 0.55 + 0.45 * std::min(1.0, edge / 0.04);
    const double s = formants_.process(tilt_.process(saw_.next(f, rate_)), rate_);
    y = static_cast<float>(std::clamp(0.35 * env * s, -1.0, 1.0));
    ++n_;
  }
}

}  // namespace earshot::scenes
