// Air absorption of one source: a high shelf above 5 kHz (a second-order
// Butterworth low-pass plus the rest of the signal at the shelf's gain) whose
// gain falls with distance, OpenAL's model (AL_AIR_ABSORPTION_FACTOR):
// the high band loses a factor 0.994 (-0.05 dB) per metre per unit of
// `factor`. Factor 0 (OpenAL's default) passes the signal untouched.
// A DSP unit the Resonance way: set up at construction, update() takes the
// new distance, process() runs per block (the gain glides across the
// block) and never allocates.
#pragma once

#include <span>

namespace earshot::audio {

class AirAbsorption {
 public:
  static constexpr double kReferenceHz = 5000.0;
  static constexpr double kGainPerMetre = 0.99426;  // OpenAL's AIRABSORBGAINHF

  explicit AirAbsorption(double sample_rate);

  /// The high band's gain for this distance (metres) and factor (0..10).
  void update(double distance_m, double factor);
  /// Filters the block in place.
  void process(std::span<float> block);
  void reset();

  [[nodiscard]] double high_gain() const { return target_; }

 private:
  double b0_, b1_, b2_, a1_, a2_;  // the low-pass biquad at kReferenceHz
  double z1_ = 0.0, z2_ = 0.0;     // its state (transposed direct form II)
  double gain_ = -1.0;    // high-band gain of the previous block (< 0: none yet)
  bool primed_ = false;   // the state follows the signal (false while bypassed)
  double target_ = 1.0;
};

}  // namespace earshot::audio
