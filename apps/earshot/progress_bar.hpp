// The one-line progress bar of offline renders (`earshot render`, the demo's
// WAV fallback), drawn on stderr; callers draw it only on a terminal.
#pragma once

#include <cstdio>

namespace earshot::app {

/// `f`: the fraction done, 0 to 1; a newline at 1.
inline void progress_bar(double f) {
  const int width = 40, filled = static_cast<int>(f * width);
  std::fprintf(stderr, "\rrendering [%.*s%*s] %3d%%", filled, "########################################",
               width - filled, "", static_cast<int>(f * 100));
  if (f >= 1.0) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace earshot::app
