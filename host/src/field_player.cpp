#include "earshot/host/field_player.hpp"

#include <algorithm>

namespace earshot::host {

FieldPlayer::FieldPlayer(const scenes::SceneBed& bed, double sample_rate, std::size_t ahead_frames)
    : stream_(bed, sample_rate), capacity_(std::max<std::size_t>(ahead_frames, 256) + 1) {
  ring_.assign(capacity_ * stream_.channels(), 0.0f);
  chunk_.assign(1024 * stream_.channels(), 0.0f);
  pump();
}

void FieldPlayer::pump() {
  const std::size_t C = stream_.channels();
  while (!ended_.load(std::memory_order_relaxed)) {
    const std::size_t w = write_.load(std::memory_order_relaxed), r = read_.load(std::memory_order_acquire);
    const std::size_t used = (w + capacity_ - r) % capacity_;
    const std::size_t room = capacity_ - 1 - used;
    if (room == 0) return;
    const std::size_t want = std::min(room, chunk_.size() / C);
    const std::size_t got = stream_.read(chunk_, want);
    for (std::size_t i = 0; i < got; ++i)
      std::copy_n(chunk_.begin() + static_cast<std::ptrdiff_t>(i * C), C,
                  ring_.begin() + static_cast<std::ptrdiff_t>(((w + i) % capacity_) * C));
    write_.store((w + got) % capacity_, std::memory_order_release);
    if (got < want) ended_.store(true, std::memory_order_release);  // a bed that does not loop has ended
  }
}

void FieldPlayer::take(float* planar, std::size_t channels, std::size_t frames) {
  const std::size_t C = stream_.channels();
  const std::size_t r = read_.load(std::memory_order_relaxed), w = write_.load(std::memory_order_acquire);
  const std::size_t avail = (w + capacity_ - r) % capacity_;
  const std::size_t n = std::min(avail, frames);
  const std::size_t copy_channels = std::min(channels, C);
  for (std::size_t i = 0; i < n; ++i) {
    const float* frame = ring_.data() + ((r + i) % capacity_) * C;
    for (std::size_t c = 0; c < copy_channels; ++c) planar[c * frames + i] = frame[c];
  }
  for (std::size_t c = 0; c < channels; ++c)
    std::fill(planar + c * frames + (c < copy_channels ? n : 0), planar + (c + 1) * frames, 0.0f);
  read_.store((r + n) % capacity_, std::memory_order_release);
  if (n < frames && !ended_.load(std::memory_order_acquire)) underruns_.fetch_add(1, std::memory_order_relaxed);
}

void FieldPlayer::pull(void* user, float* out, ESuint channels, ESuint frames) {
  static_cast<FieldPlayer*>(user)->take(out, channels, frames);
}

}  // namespace earshot::host
