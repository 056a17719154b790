#include "alloc_counter.hpp"

#include <cstdlib>
#include <new>

namespace {
thread_local bool armed = false;
thread_local std::size_t allocations = 0;

void* counted(std::size_t n) {
  if (armed) ++allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return counted(n); }
void* operator new[](std::size_t n) { return counted(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace earshot::testing {
AllocationProbe::AllocationProbe() {
  allocations = 0;
  armed = true;
}
AllocationProbe::~AllocationProbe() { armed = false; }
std::size_t AllocationProbe::count() const { return allocations; }
}  // namespace earshot::testing
