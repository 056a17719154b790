// The renderer's innermost loops, once per instruction set, and the choice
// between them. Each instruction set has one source file
// (audio/src/simd/portable.cpp, audio/src/simd/avx2.cpp) compiled with its
// own flags, and one table of its kernels. The table is chosen once, on
// first use, from CPUID (or EARSHOT_SIMD): no ifunc resolver and no
// target_clones, so the same choice is made, and the same vector code
// tested, under ASan, UBSan and TSan and with clang.
//
// Callers use the named functions in spectral_kernels.hpp and
// FractionalDelay; tests take a table by instruction set to compare paths.
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace earshot::audio::simd {

enum class Isa {
  portable,  // baseline x86-64 (SSE2) or whatever the target's baseline is; always there
  avx2,      // AVX2 + FMA (x86-64 only; the CPU and the OS must both support it)
};

[[nodiscard]] std::string_view name(Isa isa);

/// A gliding delay read's walk (defined with FractionalDelay's read, in
/// audio/src/simd/glide.hpp).
struct Glide;

/// One instruction set's kernels. Pointers passed to a kernel may not
/// overlap; see spectral_kernels.hpp for each spectral kernel's contract.
struct Kernels {
  Isa isa;
  void (*multiply_add)(const float* x, const float* h, float* acc, std::size_t S);
  void (*multiply_add_scaled)(const float* x, const std::int16_t* h, float scale, float* acc, std::size_t S);
  void (*add_shaped)(const float* x, float c0, float c1, float c2, const float* r, const float* r2, float* out,
                     std::size_t n);
  void (*to_planar)(const std::complex<float>* in, std::size_t n, float* out, std::size_t S);
  void (*to_planar_odd_negated)(const std::complex<float>* in, std::size_t n, float* out, std::size_t S);
  void (*to_interleaved)(const float* in, std::size_t S, std::complex<float>* out, std::size_t n);
  void (*real_spectrum)(const std::complex<float>* z, std::size_t M, const float* c, const float* s,
                        const float* sign, float* out, std::size_t S);
  /// FractionalDelay's read at a moving delay: n samples of the walk g.
  void (*glide)(const Glide& g, float* out, std::size_t n);
  /// y[i] = a[i] + (i + 1) / n (b[i] - a[i]) with a = h0 * x and b = h1 * x,
  /// T-tap FIRs (x[i - k] readable for k < T): the near-field filter
  /// gliding from one block's taps to the next (near_field.hpp).
  void (*fir_glide)(const float* h0, const float* h1, std::size_t T, const float* x, float* y, std::size_t n);
};

/// Whether this build has the instruction set's kernels and this CPU (and
/// OS) can run them. Asks CPUID once.
[[nodiscard]] bool supported(Isa isa);

/// The choice rule. `request` is EARSHOT_SIMD's value: null or empty for
/// the best the CPU has (AVX2 where supported), else "portable" or "avx2".
/// Throws std::runtime_error naming EARSHOT_SIMD for any other value or an
/// instruction set this CPU or build lacks.
[[nodiscard]] Isa choose(const char* request);

/// kernels(isa) for the instruction set choose() picks from EARSHOT_SIMD
/// (read on each call: call kernels() instead).
[[nodiscard]] const Kernels& kernels_for_this_process();

/// The kernels every caller uses: chosen once, by the first call, from
/// EARSHOT_SIMD (read then, never again) and CPUID. The first call comes
/// from a constructor (FractionalDelay, HrtfSpectra), not from the audio
/// thread; a bad EARSHOT_SIMD throws there (and again on each later call).
/// Inline: after the first call, a guard check and a load at each kernel call.
[[nodiscard]] inline const Kernels& kernels() {
  static const Kernels& chosen = kernels_for_this_process();  // initialised once, thread-safely
  return chosen;
}

/// One instruction set's kernels, for tests that compare paths. Throws
/// std::runtime_error if !supported(isa).
[[nodiscard]] const Kernels& kernels(Isa isa);

}  // namespace earshot::audio::simd
