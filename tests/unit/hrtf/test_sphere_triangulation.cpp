// The sphere triangulation on synthetic direction sets (a Fibonacci sphere,
// a latitude-longitude grid with single poles, a KEMAR-like grid with its
// bottom cap missing, the octahedron, the icosahedron), every expectation
// computed here from the directions themselves:
//  - the hull is a closed surface: every direction a vertex, every edge in
//    two triangles with opposite orientation, V - E + F = 2;
//  - it is the spherical Delaunay triangulation: no direction inside any
//    triangle's circumcircle;
//  - every direction lies in exactly one triangle's cone, and locate() finds
//    it, with weights >= 0 summing to 1 that point back along the direction;
//  - bad sets (too few, all in one plane, all in one hemisphere) are clear
//    errors, and a repeated direction is left out (the first one is used).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "earshot/hrtf/sphere_triangulation.hpp"

using earshot::hrtf::Blend;
using Dir = earshot::Vec3;
using earshot::hrtf::SphereTriangulation;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Dir sub(const Dir& a, const Dir& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Dir cross(const Dir& a, const Dir& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Dir& a, const Dir& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Dir normalized(Dir a) {
  const double n = std::sqrt(dot(a, a));
  for (auto& x : a) x /= n;
  return a;
}
Dir from_deg(double az, double el) {
  return {std::cos(el * kDeg) * std::cos(az * kDeg), std::cos(el * kDeg) * std::sin(az * kDeg), std::sin(el * kDeg)};
}

std::vector<Dir> fibonacci(int n) {
  std::vector<Dir> d;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(1.0 - z * z);
    d.push_back({r * std::cos(golden * i), r * std::sin(golden * i), z});
  }
  return d;
}

/// Rings every 15 deg of elevation, 24 azimuths each, and the two poles once.
std::vector<Dir> lat_long() {
  std::vector<Dir> d{{0, 0, 1}, {0, 0, -1}};
  for (int el = -75; el <= 75; el += 15)
    for (int az = 0; az < 360; az += 15) d.push_back(from_deg(az, el));
  return d;
}

/// The MIT KEMAR layout: rings from -40 to +90 deg; nothing below -40.
std::vector<Dir> kemar_like() {
  const int counts[] = {56, 60, 72, 72, 72, 72, 72, 60, 56, 45, 36, 24, 12, 1};
  std::vector<Dir> d;
  for (int r = 0; r < 14; ++r)
    for (int k = 0; k < counts[r]; ++k) d.push_back(from_deg(360.0 * k / counts[r], -40.0 + 10.0 * r));
  return d;
}

std::vector<Dir> octahedron() { return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}; }

std::vector<Dir> icosahedron() {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Dir> d;
  for (double a : {-1.0, 1.0})
    for (double b : {-g, g}) {
      d.push_back(normalized({0, a, b}));
      d.push_back(normalized({a, b, 0}));
      d.push_back(normalized({b, 0, a}));
    }
  return d;
}

const SphereTriangulation& kemar_triangulation() {
  static const SphereTriangulation tri(kemar_like());
  return tri;
}

struct NamedSet {
  const char* name;
  std::vector<Dir> dirs;
};
std::vector<NamedSet> all_sets() {
  return {{"fibonacci-300", fibonacci(300)}, {"lat-long", lat_long()}, {"kemar-like", kemar_like()},
          {"octahedron", octahedron()},      {"icosahedron", icosahedron()}};
}

std::vector<Dir> random_directions(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Dir> d;
  for (int i = 0; i < n; ++i) d.push_back(normalized({g(rng), g(rng), g(rng)}));
  return d;
}

/// Solves d = w0 a + w1 b + w2 c by Cramer's rule (independent of the code under test).
std::array<double, 3> cone_weights(const Dir& a, const Dir& b, const Dir& c, const Dir& d) {
  const double det = dot(a, cross(b, c));
  return {dot(d, cross(b, c)) / det, dot(a, cross(d, c)) / det, dot(a, cross(b, d)) / det};
}

std::string what_of(const std::vector<Dir>& dirs) {
  try {
    const SphereTriangulation t(dirs);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(SphereTriangulation, IsAClosedSurfaceWithEulerCharacteristicTwo) {
  for (const auto& [name, dirs] : all_sets()) {
    SCOPED_TRACE(name);
    const SphereTriangulation tri(dirs);
    std::set<std::uint32_t> used;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;  // each directed edge once
    for (std::size_t t = 0; t < tri.triangle_count(); ++t) {
      const auto v = tri.vertices(t);
      for (int k = 0; k < 3; ++k) {
        used.insert(v[k]);
        ++directed[{v[k], v[(k + 1) % 3]}];
      }
      // Counter-clockwise seen from outside: the normal points away from the centre.
      EXPECT_GT(dot(cross(sub(dirs[v[1]], dirs[v[0]]), sub(dirs[v[2]], dirs[v[0]])), dirs[v[0]]), 0.0) << t;
    }
    EXPECT_EQ(used.size(), dirs.size()) << "every direction is a vertex";
    for (const auto& [e, count] : directed) {
      EXPECT_EQ(count, 1) << e.first << "->" << e.second;
      EXPECT_EQ(directed.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second << " is open";
    }
    const auto V = static_cast<long>(used.size()), E = static_cast<long>(directed.size() / 2),
               F = static_cast<long>(tri.triangle_count());
    EXPECT_EQ(V - E + F, 2);
    EXPECT_EQ(2 * E, 3 * F);
  }
  EXPECT_EQ(SphereTriangulation(octahedron()).triangle_count(), 8u);
  EXPECT_EQ(SphereTriangulation(icosahedron()).triangle_count(), 20u);
}

TEST(SphereTriangulation, NoDirectionLiesInsideATrianglesCircumcircle) {
  for (const auto& [name, dirs] : all_sets()) {
    SCOPED_TRACE(name);
    const SphereTriangulation tri(dirs);
    for (std::size_t t = 0; t < tri.triangle_count(); ++t) {
      const auto v = tri.vertices(t);
      // The circumcircle on the sphere is the plane through the three
      // directions: its pole c, its angular radius acos(dot(c, a)).
      const Dir c = normalized(cross(sub(dirs[v[1]], dirs[v[0]]), sub(dirs[v[2]], dirs[v[0]])));
      const double rim = dot(c, dirs[v[0]]);
      for (std::size_t i = 0; i < dirs.size(); ++i) {
        if (i == v[0] || i == v[1] || i == v[2]) continue;
        // Rings of a grid put four directions on one circle: on it is allowed.
        ASSERT_LE(dot(c, dirs[i]), rim + 1e-9) << "direction " << i << " inside the circumcircle of triangle " << t;
      }
    }
  }
}

TEST(SphereTriangulation, EveryDirectionIsInExactlyOneTriangleAndLocateFindsIt) {
  for (const auto& [name, dirs] : all_sets()) {
    SCOPED_TRACE(name);
    const SphereTriangulation tri(dirs);
    auto probes = random_directions(2000, 5);
    probes.push_back({0, 0, 1});
    probes.push_back({0, 0, -1});  // below the KEMAR-like grid's lowest ring
    std::uint32_t hint = SphereTriangulation::kNoHint;
    for (const Dir& d : probes) {
      // Independently: the triangles whose cone holds d.
      int inside = 0, strictly = 0;
      std::size_t found = 0;
      for (std::size_t t = 0; t < tri.triangle_count(); ++t) {
        const auto v = tri.vertices(t);
        const auto w = cone_weights(dirs[v[0]], dirs[v[1]], dirs[v[2]], d);
        const double lo = std::min({w[0], w[1], w[2]});
        if (lo >= -1e-9) ++inside, found = t;
        if (lo > 1e-6) ++strictly;
      }
      ASSERT_GE(inside, 1) << "a direction in no triangle";
      ASSERT_LE(strictly, 1) << "a direction inside two triangles";

      const Blend b = tri.locate(d, hint);
      ASSERT_LT(b.triangle, tri.triangle_count());
      EXPECT_EQ(b.index, tri.vertices(b.triangle));
      Dir back{0, 0, 0};
      double sum = 0;
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(b.weight[k], 0.0);
        sum += b.weight[k];
        for (int i = 0; i < 3; ++i) back[i] += b.weight[k] * dirs[b.index[k]][i];
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      const Dir n = normalized(back);
      EXPECT_NEAR(dot(n, d), 1.0, 1e-9) << "the weights do not point back along the direction";
      // The hint is only a hint: a wrong one gives the same triangle (or, on
      // an edge or a vertex, one of the triangles that share it).
      const Blend again = tri.locate(d, static_cast<std::uint32_t>((b.triangle + 1) % tri.triangle_count()));
      if (strictly == 1) {
        EXPECT_EQ(b.triangle, found);
        EXPECT_EQ(again.triangle, found);
      }
      Dir back2{0, 0, 0};
      for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) back2[i] += again.weight[k] * dirs[again.index[k]][i];
      EXPECT_NEAR(dot(normalized(back2), d), 1.0, 1e-9);
      hint = b.triangle;
    }
  }
}

TEST(SphereTriangulation, AMeasuredDirectionGetsAllTheWeight) {
  const auto dirs = kemar_like();
  const SphereTriangulation& tri = kemar_triangulation();
  for (std::size_t i = 0; i < dirs.size(); i += 7) {
    const Blend b = tri.locate(dirs[i]);
    double own = 0;
    for (int k = 0; k < 3; ++k)
      if (b.index[k] == i) own += b.weight[k];
    EXPECT_NEAR(own, 1.0, 1e-6) << "direction " << i;
  }
}

TEST(SphereTriangulation, OctahedronWeightsAreTheExactBarycentricOnes) {
  const SphereTriangulation tri(octahedron());
  const Blend centre = tri.locate(normalized({1, 1, 1}));
  std::set<std::uint32_t> idx(centre.index.begin(), centre.index.end());
  EXPECT_EQ(idx, (std::set<std::uint32_t>{0, 2, 4}));  // +x, +y, +z
  for (double w : centre.weight) EXPECT_NEAR(w, 1.0 / 3.0, 1e-9);
  // Between +x and -y, on an edge: half each (whichever triangle it picks).
  const Blend edge = tri.locate(normalized({1, -1, 0}));
  double wx = 0, wy = 0;
  for (int k = 0; k < 3; ++k) {
    if (edge.index[k] == 0) wx += edge.weight[k];
    if (edge.index[k] == 3) wy += edge.weight[k];
  }
  EXPECT_NEAR(wx, 0.5, 1e-9);
  EXPECT_NEAR(wy, 0.5, 1e-9);
  // (2, 1, 1)/|.|: the ray meets the face x + y + z = 1 at (1/2, 1/4, 1/4).
  const Blend off = tri.locate(normalized({2, 1, 1}));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(off.weight[k], off.index[k] == 0 ? 0.5 : 0.25, 1e-9);
}

TEST(SphereTriangulation, BelowTheLowestRingBlendsThatRingOnly) {
  // KEMAR has nothing below -40 deg: straight down falls in a face spanning
  // the gap, made of -40 deg directions, each weighted >= 0.
  const Blend b = kemar_triangulation().locate({0, 0, -1});
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(b.index[k], 56u) << "not a -40 deg direction";
    EXPECT_GE(b.weight[k], 0.0);
  }
}

TEST(SphereTriangulation, TooFewOrFlatSetsAreClearErrors) {
  EXPECT_NE(what_of({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}).find("at least four"), std::string::npos);
  // A horizontal ring only: nothing above or below to blend.
  std::vector<Dir> ring;
  for (int az = 0; az < 360; az += 5) ring.push_back(from_deg(az, 0));
  EXPECT_NE(what_of(ring).find("one plane"), std::string::npos) << what_of(ring);
  // A tilted great circle is no better.
  std::vector<Dir> tilted;
  for (int k = 0; k < 36; ++k) tilted.push_back(normalized({std::cos(k * 10 * kDeg), std::sin(k * 10 * kDeg), std::sin(k * 10 * kDeg)}));
  EXPECT_NE(what_of(tilted).find("one plane"), std::string::npos) << what_of(tilted);
  // An upper hemisphere (horizon and above): the directions below have no
  // triangle whose weights are >= 0.
  std::vector<Dir> upper;
  for (int el = 0; el <= 60; el += 30)
    for (int az = 0; az < 360; az += 30) upper.push_back(from_deg(az, el));
  upper.push_back({0, 0, 1});
  EXPECT_NE(what_of(upper).find("hemisphere"), std::string::npos) << what_of(upper);
}

TEST(SphereTriangulation, ARepeatedDirectionIsLeftOutAndTheFirstIsUsed) {
  auto dirs = octahedron();
  dirs.push_back({0, 0, 1});  // index 6 repeats +z (index 4)
  dirs.push_back({1, 0, 0});  // index 7 repeats +x (index 0)
  const SphereTriangulation tri(dirs);
  EXPECT_EQ(tri.triangle_count(), 8u);
  for (std::size_t t = 0; t < tri.triangle_count(); ++t)
    for (auto v : tri.vertices(t)) EXPECT_LT(v, 6u) << "a repeated direction is a vertex";
  const Blend up = tri.locate({0, 0, 1});
  double w4 = 0;
  for (int k = 0; k < 3; ++k)
    if (up.index[k] == 4) w4 += up.weight[k];
  EXPECT_NEAR(w4, 1.0, 1e-9);
}
