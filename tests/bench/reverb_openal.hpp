// OpenAL Soft's EFX reverb as a reference: a loopback device (stereo float,
// HRTF off, no output limiter), one source whose direct path is muted and
// whose auxiliary send feeds an effect slot holding AL_EFFECT_EAXREVERB with
// a room preset's parameters. impulse_response() plays one unit impulse and
// renders what comes out: the reverb alone.
//
// OpenAL keeps one current context per process: keep one instance alive at a
// time (and none of OpenAlReference beside it).
#pragma once

#include <memory>
#include <vector>

#include "earshot/audio/room_presets.hpp"

namespace earshot::bench {

class OpenAlReverb {
 public:
  /// Throws std::runtime_error if OpenAL Soft lacks loopback or EFX.
  explicit OpenAlReverb(int sample_rate);
  ~OpenAlReverb();
  OpenAlReverb(const OpenAlReverb&) = delete;
  OpenAlReverb& operator=(const OpenAlReverb&) = delete;

  struct Stereo {
    std::vector<float> left, right;
  };
  /// The reverb's response to a unit impulse, `frames` long (impulse at frame 0).
  [[nodiscard]] Stereo impulse_response(const audio::RoomParams& p, std::size_t frames);

 private:
  struct DeviceCloser {
    void operator()(void* d) const;
  };
  struct ContextDestroyer {
    void operator()(void* c) const;
  };
  std::unique_ptr<void, DeviceCloser> device_;
  std::unique_ptr<void, ContextDestroyer> context_;
  int rate_;
};

}  // namespace earshot::bench
