#include "earshot/audio/spectral_kernels.hpp"

// Not in sanitizer builds: the clones are chosen by an ifunc resolver that
// runs while the library is relocated, before a sanitizer's runtime is up
// (TSan crashes there); those builds test the baseline code.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(EARSHOT_SANITIZED)
#define EARSHOT_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define EARSHOT_CLONES
#endif

namespace earshot::audio::kernels {

EARSHOT_CLONES void multiply_add(const float* __restrict x, const float* __restrict h, float* __restrict acc,
                                 std::size_t S) {
  const float *xr = x, *xi = x + S, *hr = h, *hi = h + S;
  float *ar = acc, *ai = acc + S;
  for (std::size_t k = 0; k < S; ++k) {
    ar[k] += xr[k] * hr[k] - xi[k] * hi[k];
    ai[k] += xr[k] * hi[k] + xi[k] * hr[k];
  }
}

EARSHOT_CLONES void add_ramped(const float* __restrict x, float g0, float dg, const float* __restrict ramp,
                               float* __restrict out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] += (g0 + dg * ramp[i]) * x[i];
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
