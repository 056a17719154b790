#include "earshot/audio/ambisonics/spherical_harmonics.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace earshot::ambisonics {
namespace {

constexpr std::size_t kMaxChannels = channel_count(kMaxOrder);

/// N_l^|m| (SN3D) per ACN channel, computed once.
const std::array<double, kMaxChannels>& sn3d_norms() {
  static const std::array<double, kMaxChannels> table = [] {
    std::array<double, kMaxChannels> t{};
    for (int l = 0; l <= kMaxOrder; ++l)
      for (int m = -l; m <= l; ++m) {
        const int a = m < 0 ? -m : m;
        double ratio = 1.0;  // (l - a)! / (l + a)!
        for (int k = l - a + 1; k <= l + a; ++k) ratio /= k;
        t[acn(l, m)] = std::sqrt((a == 0 ? 1.0 : 2.0) * ratio);
      }
    return t;
  }();
  return table;
}

void check_order(int order, const char* who) {
  if (order < 0 || order > kMaxOrder)
    throw std::invalid_argument(std::string(who) + ": order " + std::to_string(order) + " outside 0.." +
                                std::to_string(kMaxOrder));
}

template <class T>
void real_sh_impl(int order, const Vec3& d, std::span<T> out) {
  if (order < 0 || order > kMaxOrder || out.size() < channel_count(order)) return;
  const auto& norm = sn3d_norms();
  const double x = d[0], y = d[1], z = d[2];
  // c + i s = (x + i y)^m = cos^m(el) e^{i m az}; pbar = P_l^m(z) / cos^m(el),
  // the Legendre function without the factor that (x + i y)^m carries.
  double c = 1.0, s = 0.0, pmm = 1.0;  // pmm = (2m - 1)!!
  for (int m = 0; m <= order; ++m) {
    if (m > 0) {
      const double c1 = x * c - y * s;
      s = x * s + y * c;
      c = c1;
      pmm *= 2 * m - 1;
    }
    double p2 = 0.0, p1 = pmm;  // pbar_{l-2}, pbar_{l-1}
    for (int l = m; l <= order; ++l) {
      double p;
      if (l == m) {
        p = pmm;
      } else if (l == m + 1) {
        p = (2 * m + 1) * z * pmm;
      } else {
        p = ((2 * l - 1) * z * p1 - (l + m - 1) * p2) / (l - m);
      }
      if (l > m) {
        p2 = p1;
        p1 = p;
      }
      out[acn(l, m)] = static_cast<T>(norm[acn(l, m)] * p * c);
      if (m > 0) out[acn(l, -m)] = static_cast<T>(norm[acn(l, -m)] * p * s);
    }
  }
}

// FuMa: channel letters in FuMa order, each letter's ACN channel, and the
// gain from FuMa's maxN to SN3D (the SN3D function's largest value over the
// sphere; W: sqrt 2, FuMa's -3 dB).
constexpr std::array<std::size_t, 16> kFumaToAcn{0, 3, 1, 2, 6, 7, 5, 8, 4, 12, 13, 11, 14, 10, 15, 9};

double fuma_to_sn3d_gain(std::size_t acn_channel) {
  switch (acn_channel) {
    case 0: return std::sqrt(2.0);               // W
    case 1: case 2: case 3: return 1.0;          // Y Z X
    case 4: case 5: case 7: case 8: return std::sqrt(3.0) / 2.0;  // V T S U
    case 6: return 1.0;                          // R
    case 9: case 15: return std::sqrt(5.0 / 8.0);     // Q P
    case 10: case 14: return std::sqrt(5.0) / 3.0;    // O N
    case 11: case 13: return std::sqrt(32.0 / 45.0);  // M L
    case 12: return 1.0;                         // K
    default: return 1.0;
  }
}

}  // namespace

int degree_of(std::size_t n) {
  int l = 0;
  while (channel_count(l) <= n) ++l;
  return l;
}

int order_from_channels(std::size_t channels) {
  for (int n = 0; n <= kMaxOrder; ++n)
    if (channel_count(n) == channels) return n;
  return -1;
}

Vec3 ambix_from_sofa(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

void real_sh(int order, const Vec3& d, std::span<double> out) { real_sh_impl(order, d, out); }
void real_sh(int order, const Vec3& d, std::span<float> out) { real_sh_impl(order, d, out); }

std::string_view convention_name(Convention c) {
  switch (c) {
    case Convention::ambix: return "ambix";
    case Convention::n3d: return "n3d";
    case Convention::fuma: return "fuma";
  }
  return "?";
}

ChannelMap to_ambix(Convention from, int order) {
  check_order(order, "to_ambix");
  const std::size_t C = channel_count(order);
  ChannelMap map{std::vector<std::size_t>(C), std::vector<double>(C, 1.0)};
  for (std::size_t n = 0; n < C; ++n) map.source[n] = n;
  switch (from) {
    case Convention::ambix: break;
    case Convention::n3d:
      for (std::size_t n = 0; n < C; ++n) map.gain[n] = 1.0 / std::sqrt(2.0 * degree_of(n) + 1.0);
      break;
    case Convention::fuma:
      if (order > kMaxFumaOrder)
        throw std::invalid_argument("FuMa is defined up to order 3, not " + std::to_string(order));
      for (std::size_t f = 0; f < C; ++f) {
        const std::size_t n = kFumaToAcn[f];
        map.source[n] = f;
        map.gain[n] = fuma_to_sn3d_gain(n);
      }
      break;
  }
  return map;
}

ChannelMap from_ambix(Convention to, int order) {
  const ChannelMap in = to_ambix(to, order);  // ambix[n] = g[n] other[s[n]]
  ChannelMap out{std::vector<std::size_t>(in.source.size()), std::vector<double>(in.gain.size())};
  for (std::size_t n = 0; n < in.source.size(); ++n) {
    out.source[in.source[n]] = n;
    out.gain[in.source[n]] = 1.0 / in.gain[n];
  }
  return out;
}

}  // namespace earshot::ambisonics
