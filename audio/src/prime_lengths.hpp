// Delay line lengths for the reverbs: the first prime at or above a length,
// so that no two lines share a factor and their echoes do not pile up on a
// common period (internal to audio/).
#pragma once

#include <cstddef>

namespace earshot::audio::detail {

[[nodiscard]] inline bool is_prime(std::size_t n) {
  if (n < 2) return false;
  for (std::size_t d = 2; d * d <= n; ++d)
    if (n % d == 0) return false;
  return true;
}

[[nodiscard]] inline std::size_t prime_at_least(std::size_t n) {
  while (!is_prime(n)) ++n;
  return n;
}

}  // namespace earshot::audio::detail
