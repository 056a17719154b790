#pragma once
// PortAudio output for `earshot demo`: lists devices, picks one by name (or
// the default), opens it at a requested buffer size, reports the latency it
// got, and counts xruns and measures the callback's load without allocating
// or locking in the callback.
#include <pthread.h>

#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace earshot::demo {

struct DeviceInfo {
  int index = -1;
  std::string name, host_api;
  int max_output_channels = 0;
  double default_rate = 0;
  bool is_default = false;
};

/// What the audio thread does per block: fill `frames` samples of left and right.
/// Called on the real-time thread; must not allocate, lock, log or do I/O.
using RenderFn = void (*)(void* user, float* left, float* right, unsigned long frames);

/// Live counters, written by the audio thread, read by anyone.
struct OutputStats {
  std::atomic<std::uint64_t> blocks{0}, xruns{0};
  std::atomic<std::uint64_t> first_xrun_block{0}, last_xrun_block{0};  ///< 1-based; 0: none
  std::atomic<double> load_last{0}, load_max{0};  ///< CPU time / block duration
  std::atomic<double> load_sum{0};
};

/// There is no output device at all (the demo then renders to a WAV).
struct NoDevice : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// PortAudio, initialised for the object's lifetime (RAII).
class AudioOutput {
 public:
  AudioOutput();
  ~AudioOutput();
  AudioOutput(const AudioOutput&) = delete;
  AudioOutput& operator=(const AudioOutput&) = delete;

  /// Devices with output channels.
  [[nodiscard]] std::vector<DeviceInfo> devices() const;
  /// The device whose name contains `name` (empty: the default output).
  /// Throws earshot::InputError listing the devices when none matches, and
  /// NoDevice when there are none.
  [[nodiscard]] DeviceInfo choose(const std::string& name) const;

  /// Opens and starts a stereo float stream of `frames` per buffer.
  void start(const DeviceInfo& dev, double rate, unsigned long frames, RenderFn fn, void* user);
  void stop();
  /// Output latency PortAudio reports for the open stream, seconds.
  [[nodiscard]] double latency_s() const { return latency_; }
  [[nodiscard]] const OutputStats& stats() const { return stats_; }

  /// Sets what on_block calls (start() does this; tests call on_block directly).
  void prepare(RenderFn fn, void* user, unsigned long frames, double rate) noexcept {
    fn_ = fn, user_ = user, block_s_ = double(frames) / rate;
  }
  /// The audio thread's block (PortAudio's callback lands here): renders,
  /// counts xruns from the status flags, measures its own CPU time.
  void on_block(float* left, float* right, unsigned long frames, bool xrun) noexcept;

  /// From the control thread, once the stream runs: makes the audio thread
  /// SCHED_FIFO at `priority` unless the audio server made it real-time
  /// already (JACK does, unless run with --no-realtime). Returns "" or why
  /// it could not (no permission: the audio then competes with the window).
  std::string make_audio_thread_realtime(int priority = 70);
  [[nodiscard]] bool audio_thread_realtime() const;

 private:
  void* stream_ = nullptr;
  RenderFn fn_ = nullptr;
  void* user_ = nullptr;
  double block_s_ = 0, latency_ = 0;
  OutputStats stats_;
  std::atomic<bool> audio_thread_known_{false};
  std::atomic<pthread_t> audio_thread_{};
};

/// A readable list of `devs` for messages.
[[nodiscard]] std::string describe_devices(const std::vector<DeviceInfo>& devs);

}  // namespace earshot::demo
