// Which table of kernels runs: asked once, by ordinary code on first use.
// (An ifunc resolver would run while the library is relocated, before a
// sanitizer's runtime is up: TSan crashed there.)
#include <cstdlib>
#include <initializer_list>
#include <stdexcept>
#include <string>

#include "tables.hpp"

#ifdef EARSHOT_SIMD_AVX2
#include <cpuid.h>
#endif

namespace earshot::audio::simd {
namespace {

#ifdef EARSHOT_SIMD_AVX2
/// Everything avx2.cpp is built for (-march=x86-64-v3: AVX2, FMA, BMI1/2,
/// F16C, LZCNT, MOVBE and the x86-64-v2 set), and the OS saving the YMM
/// registers across context switches (OSXSAVE, then XCR0's SSE and AVX bits).
/// Bits by number: GCC's and clang's cpuid.h name some of them differently.
bool cpu_runs_avx2() {
  unsigned a = 0, b = 0, c = 0, d = 0;
  const auto all = [](unsigned reg, std::initializer_list<int> bits) {
    for (const int i : bits)
      if ((reg & (1u << i)) == 0) return false;
    return true;
  };
  // Leaf 1, ECX: SSE3 0, SSSE3 9, FMA 12, CMPXCHG16B 13, SSE4.1 19, SSE4.2 20,
  // MOVBE 22, POPCNT 23, OSXSAVE 27, AVX 28, F16C 29.
  if (__get_cpuid(1, &a, &b, &c, &d) == 0 || !all(c, {0, 9, 12, 13, 19, 20, 22, 23, 27, 28, 29})) return false;
  unsigned xcr0 = 0, xcr0_high = 0;
  __asm__("xgetbv" : "=a"(xcr0), "=d"(xcr0_high) : "c"(0));
  if ((xcr0 & 0x6u) != 0x6u) return false;
  // Leaf 7, EBX: BMI1 3, AVX2 5, BMI2 8.
  if (__get_cpuid_count(7, 0, &a, &b, &c, &d) == 0 || !all(b, {3, 5, 8})) return false;
  // Leaf 0x80000001, ECX: LAHF/SAHF 0, LZCNT 5.
  return __get_cpuid(0x80000001u, &a, &b, &c, &d) != 0 && all(c, {0, 5});
}
#endif

}  // namespace

std::string_view name(Isa isa) {
  switch (isa) {
    case Isa::portable: return "portable";
    case Isa::avx2: return "avx2";
  }
  return "unknown";
}

bool supported(Isa isa) {
  switch (isa) {
    case Isa::portable: return true;
    case Isa::avx2: {
#ifdef EARSHOT_SIMD_AVX2
      static const bool runs = cpu_runs_avx2();
      return runs;
#else
      return false;
#endif
    }
  }
  return false;
}

Isa choose(const char* request) {
  const std::string_view asked = request != nullptr ? request : "";
  if (asked.empty()) return supported(Isa::avx2) ? Isa::avx2 : Isa::portable;
  for (const Isa isa : {Isa::portable, Isa::avx2}) {
    if (asked != name(isa)) continue;
    if (!supported(isa))
      throw std::runtime_error("EARSHOT_SIMD=" + std::string(asked) + ": this CPU or build cannot run it" +
                               " (AVX2 and FMA, on x86-64)");
    return isa;
  }
  throw std::runtime_error("EARSHOT_SIMD=" + std::string(asked) +
                           ": expected portable or avx2 (unset: the best this CPU runs)");
}

const Kernels& kernels(Isa isa) {
  if (!supported(isa))
    throw std::runtime_error("SIMD kernels '" + std::string(name(isa)) + "': this CPU or build cannot run them");
#ifdef EARSHOT_SIMD_AVX2
  if (isa == Isa::avx2) return avx2_kernels;
#endif
  return portable_kernels;
}

const Kernels& kernels_for_this_process() { return kernels(choose(std::getenv("EARSHOT_SIMD"))); }

}  // namespace earshot::audio::simd
