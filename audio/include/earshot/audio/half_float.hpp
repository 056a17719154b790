// IEEE 754 half precision (binary16) to and from float, exactly as F16C's
// vcvtps2ph (round to nearest even) and vcvtph2ps do, for CPUs and builds
// without them. The renderer keeps the measured HRTF spectra as halves:
// their rounding (relative 2^-11, about -66 dB per coefficient) is far
// below what the cues need, and it halves the memory the convolution
// streams each block.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace earshot::audio {

[[nodiscard]] inline std::uint16_t float_to_half(float f) {
  const auto x = std::bit_cast<std::uint32_t>(f);
  const auto sign = static_cast<std::uint16_t>((x >> 16) & 0x8000u);
  const std::uint32_t ax = x & 0x7fffffffu;
  if (ax > 0x7f800000u) return static_cast<std::uint16_t>(sign | 0x7e00u | ((ax >> 13) & 0x3ffu));  // NaN stays NaN
  if (ax >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // rounds past 65504: infinity
  if (ax < 0x38800000u) {  // below 2^-14: a subnormal half (or zero), in steps of 2^-24
    const float steps = std::nearbyint(std::bit_cast<float>(ax) * 16777216.0f);  // exact scaling, ties to even
    return static_cast<std::uint16_t>(sign | static_cast<std::uint32_t>(steps));  // 1024 steps is the smallest normal
  }
  std::uint32_t h = (ax - 0x38000000u) >> 13;  // exponent rebiased (127 - 15), mantissa cut to 10 bits
  const std::uint32_t rest = ax & 0x1fffu;
  if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;  // to nearest even; a carry bumps the exponent
  return static_cast<std::uint16_t>(sign | h);
}

[[nodiscard]] inline float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
  if (exponent == 0) {  // zero or subnormal: mantissa x 2^-24
    const float v = static_cast<float>(mantissa) * (1.0f / 16777216.0f);
    return sign ? -v : v;
  }
  if (exponent == 31) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));
  return std::bit_cast<float>(sign | ((exponent + 112u) << 23) | (mantissa << 13));
}

}  // namespace earshot::audio
