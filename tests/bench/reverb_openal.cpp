#include "reverb_openal.hpp"

#define AL_ALEXT_PROTOTYPES
#include <AL/al.h>
#include <AL/alc.h>
#include <AL/alext.h>
#include <AL/efx.h>

#include <stdexcept>
#include <string>

namespace earshot::bench {
namespace {
ALCdevice* dev(void* d) { return static_cast<ALCdevice*>(d); }
void check(const char* what) {
  if (const ALenum e = alGetError(); e != AL_NO_ERROR)
    throw std::runtime_error(std::string("OpenAL: ") + what + " failed: " + alGetString(e));
}
}  // namespace

void OpenAlReverb::DeviceCloser::operator()(void* d) const { alcCloseDevice(dev(d)); }
void OpenAlReverb::ContextDestroyer::operator()(void* c) const {
  auto* ctx = static_cast<ALCcontext*>(c);
  if (alcGetCurrentContext() == ctx) alcMakeContextCurrent(nullptr);
  alcDestroyContext(ctx);
}

OpenAlReverb::OpenAlReverb(int sample_rate) : rate_(sample_rate) {
  if (alcIsExtensionPresent(nullptr, "ALC_SOFT_loopback") == ALC_FALSE)
    throw std::runtime_error("OpenAL: ALC_SOFT_loopback missing (is this OpenAL Soft?)");
  device_.reset(alcLoopbackOpenDeviceSOFT(nullptr));
  if (!device_) throw std::runtime_error("OpenAL: cannot open a loopback device");
  if (alcIsExtensionPresent(dev(device_.get()), "ALC_EXT_EFX") == ALC_FALSE)
    throw std::runtime_error("OpenAL: ALC_EXT_EFX missing");
  const ALCint attrs[] = {ALC_FORMAT_CHANNELS_SOFT, ALC_STEREO_SOFT, ALC_FORMAT_TYPE_SOFT, ALC_FLOAT_SOFT,
                          ALC_FREQUENCY, rate_, ALC_HRTF_SOFT, ALC_FALSE,
#ifdef ALC_OUTPUT_LIMITER_SOFT
                          ALC_OUTPUT_LIMITER_SOFT, ALC_FALSE,
#endif
                          ALC_MAX_AUXILIARY_SENDS, 1, 0};
  context_.reset(alcCreateContext(dev(device_.get()), attrs));
  if (!context_) throw std::runtime_error("OpenAL: cannot create a context on the loopback device");
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_.get()));
  alDistanceModel(AL_NONE);
  check("context setup");
}

OpenAlReverb::~OpenAlReverb() = default;

OpenAlReverb::Stereo OpenAlReverb::impulse_response(const audio::RoomParams& p, std::size_t frames) {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_.get()));
  ALuint effect = 0, slot = 0, filter = 0, source = 0, buffer = 0;
  alGenEffects(1, &effect);
  alEffecti(effect, AL_EFFECT_TYPE, AL_EFFECT_EAXREVERB);
  check("EAX reverb effect");
  alEffectf(effect, AL_EAXREVERB_DENSITY, float(p.density));
  alEffectf(effect, AL_EAXREVERB_DIFFUSION, float(p.diffusion));
  alEffectf(effect, AL_EAXREVERB_GAIN, float(p.gain));
  alEffectf(effect, AL_EAXREVERB_GAINHF, float(p.gain_hf));
  alEffectf(effect, AL_EAXREVERB_GAINLF, float(p.gain_lf));
  alEffectf(effect, AL_EAXREVERB_DECAY_TIME, float(p.decay_time_s));
  alEffectf(effect, AL_EAXREVERB_DECAY_HFRATIO, float(p.decay_hf_ratio));
  alEffectf(effect, AL_EAXREVERB_DECAY_LFRATIO, float(p.decay_lf_ratio));
  alEffectf(effect, AL_EAXREVERB_REFLECTIONS_GAIN, float(p.reflections_gain));
  alEffectf(effect, AL_EAXREVERB_REFLECTIONS_DELAY, float(p.reflections_delay_s));
  alEffectf(effect, AL_EAXREVERB_LATE_REVERB_GAIN, float(p.late_reverb_gain));
  alEffectf(effect, AL_EAXREVERB_LATE_REVERB_DELAY, float(p.late_reverb_delay_s));
  alEffectf(effect, AL_EAXREVERB_ECHO_TIME, float(p.echo_time_s));
  alEffectf(effect, AL_EAXREVERB_ECHO_DEPTH, float(p.echo_depth));
  alEffectf(effect, AL_EAXREVERB_MODULATION_TIME, float(p.modulation_time_s));
  alEffectf(effect, AL_EAXREVERB_MODULATION_DEPTH, float(p.modulation_depth));
  alEffectf(effect, AL_EAXREVERB_AIR_ABSORPTION_GAINHF, float(p.air_absorption_gain_hf));
  alEffectf(effect, AL_EAXREVERB_HFREFERENCE, float(p.hf_reference_hz));
  alEffectf(effect, AL_EAXREVERB_LFREFERENCE, float(p.lf_reference_hz));
  alEffectf(effect, AL_EAXREVERB_ROOM_ROLLOFF_FACTOR, float(p.room_rolloff_factor));
  alEffecti(effect, AL_EAXREVERB_DECAY_HFLIMIT, p.decay_hf_limit ? AL_TRUE : AL_FALSE);
  check("EAX reverb parameters");
  alGenAuxiliaryEffectSlots(1, &slot);
  alAuxiliaryEffectSloti(slot, AL_EFFECTSLOT_EFFECT, static_cast<ALint>(effect));
  check("effect slot");
  // Mute the direct path: only the reverb is measured.
  alGenFilters(1, &filter);
  alFilteri(filter, AL_FILTER_TYPE, AL_FILTER_LOWPASS);
  alFilterf(filter, AL_LOWPASS_GAIN, 0.0f);
  check("direct filter");
  const std::vector<float> impulse = [] {
    std::vector<float> v(256, 0.0f);
    v[0] = 1.0f;
    return v;
  }();
  alGenBuffers(1, &buffer);
  alBufferData(buffer, AL_FORMAT_MONO_FLOAT32, impulse.data(), static_cast<ALsizei>(impulse.size() * sizeof(float)),
               rate_);
  alGenSources(1, &source);
  alSourcei(source, AL_SOURCE_RELATIVE, AL_TRUE);
  alSource3f(source, AL_POSITION, 0.0f, 0.0f, -1.0f);
  alSourcei(source, AL_DIRECT_FILTER, static_cast<ALint>(filter));
  alSource3i(source, AL_AUXILIARY_SEND_FILTER, static_cast<ALint>(slot), 0, AL_FILTER_NULL);
  alSourcei(source, AL_BUFFER, static_cast<ALint>(buffer));
  check("source setup");
  alSourcePlay(source);
  check("play");
  Stereo out;
  out.left.resize(frames);
  out.right.resize(frames);
  std::vector<float> inter(2 * 1024);
  for (std::size_t done = 0; done < frames;) {
    const std::size_t n = std::min<std::size_t>(1024, frames - done);
    alcRenderSamplesSOFT(dev(device_.get()), inter.data(), static_cast<ALCsizei>(n));
    for (std::size_t i = 0; i < n; ++i) {
      out.left[done + i] = inter[2 * i];
      out.right[done + i] = inter[2 * i + 1];
    }
    done += n;
  }
  alSourceStop(source);
  alDeleteSources(1, &source);
  alDeleteBuffers(1, &buffer);
  alAuxiliaryEffectSloti(slot, AL_EFFECTSLOT_EFFECT, AL_EFFECT_NULL);
  alDeleteAuxiliaryEffectSlots(1, &slot);
  alDeleteEffects(1, &effect);
  alDeleteFilters(1, &filter);
  check("cleanup");
  return out;
}

}  // namespace earshot::bench
