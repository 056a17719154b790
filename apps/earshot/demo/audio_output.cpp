#include "audio_output.hpp"

#include <portaudio.h>
#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <thread>
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
  if (!audio_thread_known_.load(std::memory_order_relaxed)) {  // once: who the audio thread is (no syscall)
    audio_thread_.store(pthread_self(), std::memory_order_relaxed);
    audio_thread_known_.store(true, std::memory_order_release);
  }
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

namespace earshot::demo {

std::string AudioOutput::make_audio_thread_realtime(int priority) {
  for (int i = 0; i < 200 && !audio_thread_known_.load(std::memory_order_acquire); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  if (!audio_thread_known_.load(std::memory_order_acquire)) return "the audio callback has not run yet";
  const pthread_t t = audio_thread_.load(std::memory_order_relaxed);
  int policy = 0;
  sched_param sp{};
  if (pthread_getschedparam(t, &policy, &sp) == 0 && (policy == SCHED_FIFO || policy == SCHED_RR))
    return "";  // the audio server made it real-time already
  sp.sched_priority = std::clamp(priority, sched_get_priority_min(SCHED_FIFO), sched_get_priority_max(SCHED_FIFO));
  if (const int e = pthread_setschedparam(t, SCHED_FIFO, &sp); e != 0)
    return std::string("cannot make the audio thread real-time (") + std::strerror(e) +
           "; see /etc/security/limits.d for rtprio)";
  return "";
}

bool AudioOutput::audio_thread_realtime() const {
  if (!audio_thread_known_.load(std::memory_order_acquire)) return false;
  int policy = 0;
  sched_param sp{};
  return pthread_getschedparam(audio_thread_.load(std::memory_order_relaxed), &policy, &sp) == 0 &&
         (policy == SCHED_FIFO || policy == SCHED_RR);
}

}  // namespace earshot::demo
