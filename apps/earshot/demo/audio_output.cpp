#include "audio_output.hpp"

#include <portaudio.h>
#include <time.h>

#include <algorithm>
#include <stdexcept>

#include "earshot/errors.hpp"

namespace earshot::demo {
namespace {

void check(PaError e, const char* what) {
  if (e != paNoError) throw std::runtime_error(std::string(what) + ": " + Pa_GetErrorText(e));
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);  // vDSO: no lock, no allocation
  return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
}

int pa_callback(const void*, void* out, unsigned long frames, const PaStreamCallbackTimeInfo*,
                PaStreamCallbackFlags flags, void* self) {
  auto** ch = static_cast<float**>(out);
  static_cast<AudioOutput*>(self)->on_block(ch[0], ch[1], frames,
                                            (flags & (paOutputUnderflow | paOutputOverflow)) != 0);
  return paContinue;
}

}  // namespace

AudioOutput::AudioOutput() { check(Pa_Initialize(), "PortAudio"); }

AudioOutput::~AudioOutput() {
  stop();
  Pa_Terminate();
}

std::vector<DeviceInfo> AudioOutput::devices() const {
  std::vector<DeviceInfo> out;
  const PaDeviceIndex def = Pa_GetDefaultOutputDevice();
  for (PaDeviceIndex i = 0; i < Pa_GetDeviceCount(); ++i) {
    const PaDeviceInfo* d = Pa_GetDeviceInfo(i);
    if (!d || d->maxOutputChannels < 2) continue;
    const PaHostApiInfo* h = Pa_GetHostApiInfo(d->hostApi);
    out.push_back({i, d->name, h ? h->name : "?", d->maxOutputChannels, d->defaultSampleRate, i == def});
  }
  return out;
}

std::string describe_devices(const std::vector<DeviceInfo>& devs) {
  if (devs.empty()) return "  (no output devices)\n";
  std::string s;
  for (const auto& d : devs)
    s += std::string(d.is_default ? "* " : "  ") + d.name + " (" + d.host_api + ", " +
         std::to_string(d.max_output_channels) + " ch)\n";
  return s;
}

DeviceInfo AudioOutput::choose(const std::string& name) const {
  const auto devs = devices();
  if (devs.empty())
    throw NoDevice(name.empty() ? "no audio output device" : "no audio output device (asked for '" + name + "')");
  if (name.empty()) {
    const auto it = std::find_if(devs.begin(), devs.end(), [](const DeviceInfo& d) { return d.is_default; });
    return it != devs.end() ? *it : devs.front();
  }
  for (const auto& d : devs)
    if (d.name == name) return d;
  for (const auto& d : devs)
    if (d.name.find(name) != std::string::npos) return d;
  throw InputError::at("--device", 0, "", "no output device named '" + name + "'; the devices are:\n" +
                                               describe_devices(devs));
}

void AudioOutput::start(const DeviceInfo& dev, double rate, unsigned long frames, RenderFn fn, void* user) {
  stop();
  prepare(fn, user, frames, rate);
  PaStreamParameters p{};
  p.device = dev.index;
  p.channelCount = 2;
  p.sampleFormat = paFloat32 | paNonInterleaved;
  p.suggestedLatency = block_s_;
  PaStream* s = nullptr;
  check(Pa_OpenStream(&s, nullptr, &p, rate, frames, paClipOff, &pa_callback, this), "open stream");
  stream_ = s;
  if (const PaStreamInfo* i = Pa_GetStreamInfo(s)) latency_ = i->outputLatency;
  check(Pa_StartStream(s), "start stream");
}

void AudioOutput::stop() {
  if (!stream_) return;
  Pa_StopStream(stream_);
  Pa_CloseStream(stream_);
  stream_ = nullptr;
}

void AudioOutput::on_block(float* left, float* right, unsigned long frames, bool xrun) noexcept {
  const double t0 = thread_cpu_s();
  fn_(user_, left, right, frames);
  if (xrun) {
    const std::uint64_t b = stats_.blocks.load(std::memory_order_relaxed) + 1;
    if (stats_.xruns.fetch_add(1, std::memory_order_relaxed) == 0)
      stats_.first_xrun_block.store(b, std::memory_order_relaxed);
    stats_.last_xrun_block.store(b, std::memory_order_relaxed);
  }
  const double load = (thread_cpu_s() - t0) / block_s_;
  stats_.load_last.store(load, std::memory_order_relaxed);
  if (load > stats_.load_max.load(std::memory_order_relaxed)) stats_.load_max.store(load, std::memory_order_relaxed);
  stats_.load_sum.store(stats_.load_sum.load(std::memory_order_relaxed) + load, std::memory_order_relaxed);
  stats_.blocks.fetch_add(1, std::memory_order_release);
}

}  // namespace earshot::demo
