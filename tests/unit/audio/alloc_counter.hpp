// Counts heap allocations and mutex locks made by this thread while a probe
// is armed, by replacing the global operator new and pthread_mutex_lock /
// trylock in the test binary that includes alloc_counter.cpp. Real-time code
// must show zero of both.
#pragma once

#include <cstddef>

namespace earshot::testing {

/// Allocations and locks on this thread while the probe lives.
class AllocationProbe {
 public:
  AllocationProbe();
  ~AllocationProbe();
  [[nodiscard]] std::size_t count() const;       ///< heap allocations
  [[nodiscard]] std::size_t lock_count() const;  ///< mutex locks taken
};

}  // namespace earshot::testing
