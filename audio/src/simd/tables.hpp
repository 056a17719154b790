// Each instruction set's table of kernels, defined in its own file and
// constant-initialised (no code runs to build them); dispatch.cpp picks one.
#pragma once

#include "earshot/audio/simd_kernels.hpp"

namespace earshot::audio::simd {

extern const Kernels portable_kernels;  // portable.cpp
#ifdef EARSHOT_SIMD_AVX2
extern const Kernels avx2_kernels;  // avx2.cpp, built with -mavx2 -mfma
#endif

}  // namespace earshot::audio::simd
