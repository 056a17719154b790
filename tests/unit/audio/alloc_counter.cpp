#include "alloc_counter.hpp"

#include <dlfcn.h>
#include <pthread.h>

#include <cstdlib>
#include <new>

namespace {
thread_local bool armed = false;
thread_local std::size_t allocations = 0;
thread_local std::size_t locks = 0;

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

// Every mutex a thread takes goes through pthread_mutex_lock / trylock
// (std::mutex, std::shared_mutex's writer side and glibc's own locks alike):
// these definitions in the test binary come first, count, and forward.
namespace {
template <typename Fn>
Fn next_symbol(const char* name) {
  return reinterpret_cast<Fn>(dlsym(RTLD_NEXT, name));
}
}  // namespace

extern "C" int pthread_mutex_lock(pthread_mutex_t* m) {
  static const auto real = next_symbol<int (*)(pthread_mutex_t*)>("pthread_mutex_lock");
  if (armed) ++locks;
  return real(m);
}
extern "C" int pthread_mutex_trylock(pthread_mutex_t* m) {
  static const auto real = next_symbol<int (*)(pthread_mutex_t*)>("pthread_mutex_trylock");
  if (armed) ++locks;
  return real(m);
}

namespace earshot::testing {
AllocationProbe::AllocationProbe() {
  allocations = 0;
  locks = 0;
  armed = true;
}
AllocationProbe::~AllocationProbe() { armed = false; }
std::size_t AllocationProbe::count() const { return allocations; }
std::size_t AllocationProbe::lock_count() const { return locks; }
}  // namespace earshot::testing
