// OpenAL Soft as the reference renderer of the benchmarks: a loopback device
// (no sound card; we pull stereo float blocks ourselves) with HRTF on, N mono
// sources playing looping buffers, and the listener's pose set per block.
//
// OpenAL keeps one current context per process, so the constructor makes this
// instance's context current and only one instance should be alive at a time.
// Frames: OpenAL's world frame (+x right, +y up, -z ahead), metres, seconds.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace earshot::bench {

class OpenAlReference {
 public:
  using Vec3 = std::array<double, 3>;
  using Quat = std::array<double, 4>;  ///< w, x, y, z: head rotation in the world

  struct Config {
    int sample_rate = 48000;
    int sources = 1;
  };

  /// Opens the loopback device and creates `sources` sources. Throws
  /// std::runtime_error when OpenAL Soft cannot render HRTF at that rate.
  explicit OpenAlReference(Config cfg);
  ~OpenAlReference();
  OpenAlReference(const OpenAlReference&) = delete;
  OpenAlReference& operator=(const OpenAlReference&) = delete;

  /// Uploads a mono signal as a buffer that sources can loop; returns its id.
  int add_buffer(std::span<const float> mono);
  /// Starts source `i` looping buffer `buffer` from sample `offset`.
  void play_loop(int i, int buffer, std::size_t offset = 0);

  void set_source_position(int i, const Vec3& p);
  void set_source_velocity(int i, const Vec3& v);
  void set_source_gain(int i, double gain);
  void set_listener_position(const Vec3& p);
  /// OpenAL's at/up pair: the head's -z and +y axes rotated by q.
  void set_listener_orientation(const Quat& q);

  /// Renders left.size() frames (right must match) and de-interleaves them.
  void render(std::span<float> left, std::span<float> right);

  /// The HRTF data set OpenAL Soft chose (e.g. "default-48000").
  [[nodiscard]] std::string hrtf_name() const;
  /// Every HRTF data set OpenAL Soft found for this device.
  [[nodiscard]] std::vector<std::string> available_hrtfs() const;
  [[nodiscard]] int sample_rate() const { return rate_; }
  [[nodiscard]] int source_count() const { return static_cast<int>(sources_.size()); }

 private:
  struct DeviceCloser {
    void operator()(void* d) const;
  };
  struct ContextDestroyer {
    void operator()(void* c) const;
  };
  std::unique_ptr<void, DeviceCloser> device_;
  std::unique_ptr<void, ContextDestroyer> context_;
  int rate_ = 0;
  std::vector<unsigned> sources_, buffers_;
  std::vector<float> interleaved_;
};

}  // namespace earshot::bench
