#include "earshot/audio/spectral_kernels.hpp"

// Not in sanitizer builds: the clones are chosen by an ifunc resolver that
// runs while the library is relocated, before a sanitizer's runtime is up
// (TSan crashes there); those builds test the baseline code.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(EARSHOT_SANITIZED)
#define EARSHOT_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define EARSHOT_CLONES
#endif

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#include <immintrin.h>
#define EARSHOT_HAVE_F16C_PATH 1
#endif

#include "earshot/audio/half_float.hpp"

namespace earshot::audio::kernels {
namespace {

#ifdef EARSHOT_HAVE_F16C_PATH
bool cpu_has_f16c() {
  __builtin_cpu_init();  // this runs as a static initialiser, maybe before the CPU model is read
  // Clang's __builtin_cpu_supports does not know "f16c": ask CPUID (leaf 1, ECX).
  unsigned a = 0, b = 0, c = 0, d = 0;
  const bool f16c = __get_cpuid(1, &a, &b, &c, &d) != 0 && (c & bit_F16C) != 0;
  return f16c && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}
// Read-only after load: which multiply_add_half to run.
const bool kF16c = cpu_has_f16c();

__attribute__((target("avx2,fma,f16c"))) void multiply_add_half_f16c(const float* __restrict x,
                                                                     const std::uint16_t* __restrict h,
                                                                     float* __restrict acc, std::size_t S) {
  const float *xr = x, *xi = x + S;
  const std::uint16_t *hr = h, *hi = h + S;
  float *ar = acc, *ai = acc + S;
  for (std::size_t k = 0; k < S; k += 8) {
    const __m256 hre = _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(hr + k)));
    const __m256 him = _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(hi + k)));
    const __m256 xre = _mm256_loadu_ps(xr + k), xim = _mm256_loadu_ps(xi + k);
    _mm256_storeu_ps(ar + k, _mm256_fmadd_ps(xre, hre, _mm256_fnmadd_ps(xim, him, _mm256_loadu_ps(ar + k))));
    _mm256_storeu_ps(ai + k, _mm256_fmadd_ps(xre, him, _mm256_fmadd_ps(xim, hre, _mm256_loadu_ps(ai + k))));
  }
}
#endif

}  // namespace

EARSHOT_CLONES void multiply_add(const float* __restrict x, const float* __restrict h, float* __restrict acc,
                                 std::size_t S) {
  const float *xr = x, *xi = x + S, *hr = h, *hi = h + S;
  float *ar = acc, *ai = acc + S;
  for (std::size_t k = 0; k < S; ++k) {
    ar[k] += xr[k] * hr[k] - xi[k] * hi[k];
    ai[k] += xr[k] * hi[k] + xi[k] * hr[k];
  }
}

void multiply_add_half(const float* __restrict x, const std::uint16_t* __restrict h, float* __restrict acc,
                       std::size_t S) {
#ifdef EARSHOT_HAVE_F16C_PATH
  if (kF16c) return multiply_add_half_f16c(x, h, acc, S);
#endif
  const float *xr = x, *xi = x + S;
  const std::uint16_t *hr = h, *hi = h + S;
  float *ar = acc, *ai = acc + S;
  for (std::size_t k = 0; k < S; ++k) {
    const float re = half_to_float(hr[k]), im = half_to_float(hi[k]);
    ar[k] += xr[k] * re - xi[k] * im;
    ai[k] += xr[k] * im + xi[k] * re;
  }
}

EARSHOT_CLONES void add_shaped(const float* __restrict x, float c0, float c1, float c2, const float* __restrict r,
                               const float* __restrict r2, float* __restrict out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] += (c0 + c1 * r[i] + c2 * r2[i]) * x[i];
}

void to_planar(const std::complex<float>* in, std::size_t n, float* __restrict out, std::size_t S) {
  const float* __restrict f = reinterpret_cast<const float*>(in);
  for (std::size_t k = 0; k < n; ++k) {
    out[k] = f[2 * k];
    out[S + k] = f[2 * k + 1];
  }
}

void to_planar_odd_negated(const std::complex<float>* in, std::size_t n, float* __restrict out, std::size_t S) {
  const float* __restrict f = reinterpret_cast<const float*>(in);
  for (std::size_t k = 0; k < n; ++k) {
    const float sign = (k & 1) ? -1.0f : 1.0f;
    out[k] = sign * f[2 * k];
    out[S + k] = sign * f[2 * k + 1];
  }
}

void to_interleaved(const float* __restrict in, std::size_t S, std::complex<float>* out, std::size_t n) {
  float* __restrict f = reinterpret_cast<float*>(out);
  for (std::size_t k = 0; k < n; ++k) {
    f[2 * k] = in[k];
    f[2 * k + 1] = in[S + k];
  }
}

}  // namespace earshot::audio::kernels
