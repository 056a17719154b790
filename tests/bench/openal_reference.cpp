#include "openal_reference.hpp"

#define AL_ALEXT_PROTOTYPES
#include <AL/al.h>
#include <AL/alc.h>
#include <AL/alext.h>

#include <stdexcept>

namespace earshot::bench {

namespace {

ALCdevice* dev(void* d) { return static_cast<ALCdevice*>(d); }

void check_al(const char* what) {
  if (const ALenum e = alGetError(); e != AL_NO_ERROR)
    throw std::runtime_error(std::string("OpenAL: ") + what + " failed: " + alGetString(e));
}

const char* hrtf_status_text(ALCint s) {
  switch (s) {
    case ALC_HRTF_DISABLED_SOFT: return "disabled";
    case ALC_HRTF_ENABLED_SOFT: return "enabled";
    case ALC_HRTF_DENIED_SOFT: return "denied by the configuration";
    case ALC_HRTF_REQUIRED_SOFT: return "required";
    case ALC_HRTF_HEADPHONES_DETECTED_SOFT: return "headphones detected";
    case ALC_HRTF_UNSUPPORTED_FORMAT_SOFT: return "unsupported format (no data set for this rate?)";
    default: return "unknown";
  }
}

/// v rotated by the unit quaternion q (w, x, y, z).
OpenAlReference::Vec3 rotate(const OpenAlReference::Quat& q, const OpenAlReference::Vec3& v) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  // t = 2 (q.xyz x v); v' = v + w t + q.xyz x t
  const double tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  return {v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)};
}

}  // namespace

void OpenAlReference::DeviceCloser::operator()(void* d) const { alcCloseDevice(dev(d)); }

void OpenAlReference::ContextDestroyer::operator()(void* c) const {
  auto* ctx = static_cast<ALCcontext*>(c);
  if (alcGetCurrentContext() == ctx) alcMakeContextCurrent(nullptr);
  alcDestroyContext(ctx);
}

OpenAlReference::OpenAlReference(Config cfg) : rate_(cfg.sample_rate) {
  if (cfg.sources < 1) throw std::invalid_argument("OpenAlReference: need at least one source");
  if (alcIsExtensionPresent(nullptr, "ALC_SOFT_loopback") == ALC_FALSE)
    throw std::runtime_error("OpenAL: ALC_SOFT_loopback missing (is this OpenAL Soft?)");
  device_.reset(alcLoopbackOpenDeviceSOFT(nullptr));
  if (!device_) throw std::runtime_error("OpenAL: cannot open a loopback device");
  if (alcIsRenderFormatSupportedSOFT(dev(device_.get()), rate_, ALC_STEREO_SOFT, ALC_FLOAT_SOFT) == ALC_FALSE)
    throw std::runtime_error("OpenAL: loopback stereo float at " + std::to_string(rate_) + " Hz unsupported");

  const ALCint attrs[] = {ALC_FORMAT_CHANNELS_SOFT,
                          ALC_STEREO_SOFT,
                          ALC_FORMAT_TYPE_SOFT,
                          ALC_FLOAT_SOFT,
                          ALC_FREQUENCY,
                          rate_,
                          ALC_HRTF_SOFT,
                          ALC_TRUE,
                          ALC_MONO_SOURCES,
                          cfg.sources,
                          ALC_STEREO_SOURCES,
                          0,
                          0};
  context_.reset(alcCreateContext(dev(device_.get()), attrs));
  if (!context_) throw std::runtime_error("OpenAL: cannot create a context on the loopback device");
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_.get()));

  // OpenAL Soft falls back to plain stereo panning silently: insist on HRTF.
  ALCint status = ALC_HRTF_DISABLED_SOFT, hrtf = ALC_FALSE;
  alcGetIntegerv(dev(device_.get()), ALC_HRTF_SOFT, 1, &hrtf);
  alcGetIntegerv(dev(device_.get()), ALC_HRTF_STATUS_SOFT, 1, &status);
  if (hrtf != ALC_TRUE || status != ALC_HRTF_ENABLED_SOFT)
    throw std::runtime_error(std::string("OpenAL: HRTF could not be enabled at ") + std::to_string(rate_) +
                             " Hz (status: " + hrtf_status_text(status) +
                             "); install libopenal-data, which ships /usr/share/openal/hrtf/default-48000.mhr");

  sources_.resize(static_cast<std::size_t>(cfg.sources));
  alGenSources(cfg.sources, sources_.data());
  check_al("alGenSources (raise ALC_MONO_SOURCES?)");
  interleaved_.reserve(2 * 4096);
}

OpenAlReference::~OpenAlReference() {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_.get()));
  for (ALuint s : sources_) alSourceStop(s);
  alDeleteSources(static_cast<ALsizei>(sources_.size()), sources_.data());
  alDeleteBuffers(static_cast<ALsizei>(buffers_.size()), buffers_.data());
}

int OpenAlReference::add_buffer(std::span<const float> mono) {
  if (alIsExtensionPresent("AL_EXT_FLOAT32") == AL_FALSE) throw std::runtime_error("OpenAL: AL_EXT_FLOAT32 missing");
  ALuint b = 0;
  alGenBuffers(1, &b);
  check_al("alGenBuffers");
  alBufferData(b, AL_FORMAT_MONO_FLOAT32, mono.data(), static_cast<ALsizei>(mono.size_bytes()), rate_);
  check_al("alBufferData");
  buffers_.push_back(b);
  return static_cast<int>(buffers_.size() - 1);
}

void OpenAlReference::play_loop(int i, int buffer, std::size_t offset) {
  const ALuint s = sources_.at(static_cast<std::size_t>(i));
  alSourcei(s, AL_BUFFER, static_cast<ALint>(buffers_.at(static_cast<std::size_t>(buffer))));
  alSourcei(s, AL_LOOPING, AL_TRUE);
  alSourcei(s, AL_SAMPLE_OFFSET, static_cast<ALint>(offset));
  alSourcePlay(s);
  check_al("starting a looping source");
}

void OpenAlReference::set_source_position(int i, const Vec3& p) {
  alSource3f(sources_[static_cast<std::size_t>(i)], AL_POSITION, float(p[0]), float(p[1]), float(p[2]));
}

void OpenAlReference::set_source_velocity(int i, const Vec3& v) {
  alSource3f(sources_[static_cast<std::size_t>(i)], AL_VELOCITY, float(v[0]), float(v[1]), float(v[2]));
}

void OpenAlReference::set_source_gain(int i, double gain) {
  alSourcef(sources_[static_cast<std::size_t>(i)], AL_GAIN, float(gain));
}

void OpenAlReference::set_listener_position(const Vec3& p) {
  alListener3f(AL_POSITION, float(p[0]), float(p[1]), float(p[2]));
}

void OpenAlReference::set_listener_orientation(const Quat& q) {
  const Vec3 at = rotate(q, {0, 0, -1}), up = rotate(q, {0, 1, 0});
  const ALfloat v[6] = {float(at[0]), float(at[1]), float(at[2]), float(up[0]), float(up[1]), float(up[2])};
  alListenerfv(AL_ORIENTATION, v);
}

void OpenAlReference::render(std::span<float> left, std::span<float> right) {
  if (left.size() != right.size()) throw std::invalid_argument("OpenAlReference::render: left and right differ in size");
  interleaved_.resize(2 * left.size());  // no reallocation after the first block of this size
  alcRenderSamplesSOFT(dev(device_.get()), interleaved_.data(), static_cast<ALCsizei>(left.size()));
  for (std::size_t n = 0; n < left.size(); ++n) {
    left[n] = interleaved_[2 * n];
    right[n] = interleaved_[2 * n + 1];
  }
}

std::string OpenAlReference::hrtf_name() const {
  const ALCchar* s = alcGetString(dev(device_.get()), ALC_HRTF_SPECIFIER_SOFT);
  return s ? std::string(s) : std::string();
}

std::vector<std::string> OpenAlReference::available_hrtfs() const {
  ALCint n = 0;
  alcGetIntegerv(dev(device_.get()), ALC_NUM_HRTF_SPECIFIERS_SOFT, 1, &n);
  std::vector<std::string> names;
  for (ALCint i = 0; i < n; ++i)
    if (const ALCchar* s = alcGetStringiSOFT(dev(device_.get()), ALC_HRTF_SPECIFIER_SOFT, i)) names.emplace_back(s);
  return names;
}

}  // namespace earshot::bench
