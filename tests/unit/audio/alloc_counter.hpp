// Counts heap allocations made by this thread while a probe is armed, by
// replacing the global operator new in the test binary that includes
// alloc_counter.cpp. Real-time code must show zero.
#pragma once

#include <cstddef>

namespace earshot::testing {

/// Allocations on this thread since arm(); arm() resets the count.
class AllocationProbe {
 public:
  AllocationProbe();
  ~AllocationProbe();
  [[nodiscard]] std::size_t count() const;
};

}  // namespace earshot::testing
