#include "block_render.hpp"

#include <algorithm>

namespace earshot::demo {

void render_block(void* user, float* left, float* right, unsigned long frames) noexcept {
  auto& a = *static_cast<AudioSide*>(user);
  if (esRender(a.world, left, right, static_cast<ESuint>(frames)) != ES_OK) {
    std::fill(left, left + frames, 0.0f);
    std::fill(right, right + frames, 0.0f);
  }
  const std::size_t at = a.captured.load(std::memory_order_relaxed);
  const std::size_t n = std::min<std::size_t>(frames, (a.capture.size() - at) / 2);
  for (std::size_t i = 0; i < n; ++i) {
    a.capture[at + 2 * i] = left[i];
    a.capture[at + 2 * i + 1] = right[i];
  }
  a.captured.store(at + 2 * n, std::memory_order_release);
}

}  // namespace earshot::demo
