#pragma once
// The audio thread's work in `earshot demo`: one esRender block, copied into
// a capture buffer sized before the stream starts. No allocation, lock, log
// or I/O (tests/unit/demo/test_demo_rt.cpp proves it with the probe).
#include <atomic>
#include <cstddef>
#include <vector>

#include "earshot/earshot.h"

namespace earshot::demo {

struct AudioSide {
  ESworld world = 0;
  std::vector<float> capture;  ///< interleaved stereo, sized before start
  std::atomic<std::size_t> captured{0};
};

/// A RenderFn: `user` is an AudioSide. Silence if esRender refuses.
void render_block(void* user, float* left, float* right, unsigned long frames) noexcept;

}  // namespace earshot::demo
