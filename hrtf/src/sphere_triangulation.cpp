#include "earshot/hrtf/sphere_triangulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

namespace earshot::hrtf {
namespace {

using V = std::array<double, 3>;
V sub(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V cross(const V& a, const V& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct Face {
  std::array<std::uint32_t, 3> v;
  V n;       // outward normal
  double d;  // plane offset: dot(n, x) = d on the face
  bool alive = true;
};

Face make_face(const std::vector<V>& p, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  Face f{{a, b, c}, cross(sub(p[b], p[a]), sub(p[c], p[a])), 0.0};
  const double len = std::sqrt(dot(f.n, f.n));
  for (auto& x : f.n) x /= len;
  f.d = dot(f.n, p[a]);
  return f;
}

/// The index of each direction's first occurrence, in order: a direction
/// measured twice (within ~1e-6 rad) is triangulated once.
std::vector<std::uint32_t> distinct_directions(std::span<const Vec3> dirs) {
  std::vector<std::uint32_t> keep;
  for (std::uint32_t i = 0; i < dirs.size(); ++i) {
    const bool repeat = std::any_of(keep.begin(), keep.end(), [&](std::uint32_t k) {
      const V d = sub(dirs[i], dirs[k]);
      return dot(d, d) < 1e-12;
    });
    if (!repeat) keep.push_back(i);
  }
  return keep;
}

/// Four points far from coplanar, and the fourth's distance from the plane
/// of the first three (times twice their triangle's area).
std::pair<std::array<std::uint32_t, 4>, double> initial_tetrahedron(const std::vector<V>& p) {
  const auto n = static_cast<std::uint32_t>(p.size());
  std::uint32_t i0 = 0, i1 = 1;
  double best = 0;
  for (std::uint32_t i = 1; i < n; ++i)
    if (double d = dot(sub(p[i], p[0]), sub(p[i], p[0])); d > best) best = d, i1 = i;
  std::uint32_t i2 = 0;
  best = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const V c = cross(sub(p[i1], p[i0]), sub(p[i], p[i0]));
    if (double d = dot(c, c); d > best) best = d, i2 = i;
  }
  const V n012 = cross(sub(p[i1], p[i0]), sub(p[i2], p[i0]));
  std::uint32_t i3 = 0;
  best = 0;
  for (std::uint32_t i = 0; i < n; ++i)
    if (double d = std::abs(dot(n012, sub(p[i], p[i0]))); d > best) best = d, i3 = i;
  return {{i0, i1, i2, i3}, best};
}

/// Incremental convex hull of dirs[ids[*]], in indices into dirs. The points
/// are jittered by a tiny amount first so that coplanar measurement rings are
/// in general position; every point on the sphere is then a hull vertex.
std::vector<std::array<std::uint32_t, 3>> convex_hull(std::span<const Vec3> dirs, std::span<const std::uint32_t> ids) {
  const std::size_t n = ids.size();
  std::vector<V> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = dirs[ids[i]];

  // A flat set is refused before the jitter, which would make it look solid.
  if (initial_tetrahedron(p).second < 1e-9) throw std::invalid_argument("the measured directions lie in one plane");
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1e-7, 1e-7);
  for (auto& x : p) x = {x[0] + u(rng), x[1] + u(rng), x[2] + u(rng)};
  const auto [i0, i1, i2, i3] = initial_tetrahedron(p).first;

  std::vector<Face> faces;
  auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, const V& inside) {
    Face f = make_face(p, a, b, c);
    if (dot(f.n, inside) > f.d) {  // orient outward
      std::swap(f.v[1], f.v[2]);
      f = make_face(p, f.v[0], f.v[1], f.v[2]);
    }
    faces.push_back(f);
  };
  const V centre{(p[i0][0] + p[i1][0] + p[i2][0] + p[i3][0]) / 4, (p[i0][1] + p[i1][1] + p[i2][1] + p[i3][1]) / 4,
                 (p[i0][2] + p[i1][2] + p[i2][2] + p[i3][2]) / 4};
  add(i0, i1, i2, centre);
  add(i0, i1, i3, centre);
  add(i0, i2, i3, centre);
  add(i1, i2, i3, centre);

  for (std::uint32_t k = 0; k < n; ++k) {
    if (k == i0 || k == i1 || k == i2 || k == i3) continue;
    // Faces that see the new point go; the horizon's edges make new faces.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    bool any = false;
    for (auto& f : faces) {
      if (!f.alive || dot(f.n, p[k]) - f.d <= 1e-12) continue;
      f.alive = false;
      any = true;
      for (int e = 0; e < 3; ++e) ++edges[{f.v[static_cast<std::size_t>(e)], f.v[static_cast<std::size_t>((e + 1) % 3)]}];
    }
    if (!any) continue;  // inside the hull (not expected for points on a sphere)
    for (const auto& [e, count] : edges) {
      if (edges.count({e.second, e.first})) continue;  // shared by two removed faces
      Face f = make_face(p, e.first, e.second, k);
      faces.push_back(f);
    }
    std::erase_if(faces, [](const Face& f) { return !f.alive; });
  }
  std::vector<std::array<std::uint32_t, 3>> out;
  for (const auto& f : faces) out.push_back({ids[f.v[0]], ids[f.v[1]], ids[f.v[2]]});
  return out;
}

}  // namespace

// For each acceleration cell, in increasing order, the triangles whose
// bounding cap (around the normalised centroid, out to the farthest vertex)
// overlaps the cell's azimuth x elevation box, widened by one cell. A point
// of a triangle lies in its cap (a cap narrower than a hemisphere is convex
// on the sphere), so no triangle that holds a point of the cell is left out.
std::vector<std::vector<std::uint32_t>> SphereTriangulation::triangles_near_cells(
    const std::vector<Triangle>& tris, std::span<const Vec3> dirs) {
  std::vector<std::vector<std::uint32_t>> near(kAz * kEl);
  const double cell_az = 2 * std::numbers::pi / kAz, cell_el = std::numbers::pi / kEl;
  for (std::uint32_t t = 0; t < tris.size(); ++t) {
    V c{0.0, 0.0, 0.0};
    for (const std::uint32_t i : tris[t].v)
      for (std::size_t k = 0; k < 3; ++k) c[k] += dirs[i][k];
    const double len = std::sqrt(dot(c, c));
    double r = std::numbers::pi;  // a degenerate centroid: every cell
    if (len > 1e-12) {
      for (auto& x : c) x /= len;
      r = 0.0;
      for (const std::uint32_t i : tris[t].v)
        r = std::max(r, std::acos(std::clamp(dot(c, dirs[i]), -1.0, 1.0)));
    }
    int ie0 = 0, ie1 = kEl - 1, ia0 = 0, ia1 = kAz - 1;
    if (r < 0.45 * std::numbers::pi) {
      const double c_el = std::asin(std::clamp(c[2], -1.0, 1.0));
      const double c_az = std::atan2(c[1], c[0]);
      ie0 = std::max(0, static_cast<int>(std::floor((c_el - r + std::numbers::pi / 2) / cell_el)) - 1);
      ie1 = std::min(kEl - 1, static_cast<int>(std::floor((c_el + r + std::numbers::pi / 2) / cell_el)) + 1);
      if (std::abs(c_el) + r < 0.45 * std::numbers::pi) {  // no pole inside: a bounded azimuth span
        const double half = std::asin(std::min(1.0, std::sin(r) / std::cos(c_el)));
        ia0 = static_cast<int>(std::floor((c_az - half + std::numbers::pi) / cell_az)) - 1;
        ia1 = static_cast<int>(std::floor((c_az + half + std::numbers::pi) / cell_az)) + 1;
        if (ia1 - ia0 >= kAz - 1) ia0 = 0, ia1 = kAz - 1;
      }
    }
    for (int ia = ia0; ia <= ia1; ++ia) {
      const int a = ((ia % kAz) + kAz) % kAz;  // azimuth wraps at +-pi
      for (int ie = ie0; ie <= ie1; ++ie) near[static_cast<std::size_t>(a * kEl + ie)].push_back(t);
    }
  }
  return near;
}

SphereTriangulation::SphereTriangulation(std::span<const Vec3> dirs) {
  const auto ids = distinct_directions(dirs);
  if (ids.size() < 4) throw std::invalid_argument("need at least four different measured directions");
  for (const auto& t : convex_hull(dirs, ids)) {
    Triangle tri{t, {}};
    // Inverse of the 3x3 matrix whose columns are the three directions.
    const V& a = dirs[t[0]];
    const V& b = dirs[t[1]];
    const V& c = dirs[t[2]];
    const V r0 = cross(b, c), r1 = cross(c, a), r2 = cross(a, b);
    const double det = dot(a, r0);
    // det is twice the face's area times its distance from the centre: a face
    // through the centre (or beyond) leaves the directions behind it with no
    // triangle of non-negative weights.
    const V n = cross(sub(b, a), sub(c, a));
    if (det <= 1e-6 * std::sqrt(dot(n, n)))
      throw std::invalid_argument(
          "the measured directions all lie within one hemisphere: the other side has no measurements around it");
    if (std::abs(det) < 1e-15) continue;  // degenerate sliver
    for (int k = 0; k < 3; ++k) {
      tri.inv[static_cast<std::size_t>(k)] = r0[static_cast<std::size_t>(k)] / det;
      tri.inv[static_cast<std::size_t>(3 + k)] = r1[static_cast<std::size_t>(k)] / det;
      tri.inv[static_cast<std::size_t>(6 + k)] = r2[static_cast<std::size_t>(k)] / det;
    }
    tris_.push_back(tri);
  }
  // Candidate triangles per grid cell, found by sampling each cell densely.
  // Only triangles whose bounding cap reaches the cell are tried (testing
  // every triangle at every sample was a third of a world's start-up); the
  // order they are tried and listed in is the same as for all triangles.
  const std::vector<std::vector<std::uint32_t>> near = triangles_near_cells(tris_, dirs);
  std::vector<std::vector<std::uint32_t>> cells(kAz * kEl);
  constexpr int kSub = 3;
  std::array<double, 3> w{};
  for (int ia = 0; ia < kAz; ++ia)
    for (int ie = 0; ie < kEl; ++ie) {
      const auto cell = static_cast<std::size_t>(ia * kEl + ie);
      auto& list = cells[cell];
      for (int sa = 0; sa <= kSub; ++sa)
        for (int se = 0; se <= kSub; ++se) {
          const double az = (ia + static_cast<double>(sa) / kSub) * 2 * std::numbers::pi / kAz - std::numbers::pi;
          const double el = (ie + static_cast<double>(se) / kSub) * std::numbers::pi / kEl - std::numbers::pi / 2;
          const Vec3 d{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
          for (const std::uint32_t t : near[cell])
            if (weights(tris_[t], d, w) && std::find(list.begin(), list.end(), t) == list.end()) list.push_back(t);
        }
    }
  cell_start_.push_back(0);
  for (const auto& l : cells) {
    cell_tris_.insert(cell_tris_.end(), l.begin(), l.end());
    cell_start_.push_back(static_cast<std::uint32_t>(cell_tris_.size()));
  }
}

SphereTriangulation::Stored SphereTriangulation::stored() const {
  Stored s;
  s.vertices.reserve(tris_.size());
  s.inverses.reserve(tris_.size());
  for (const Triangle& t : tris_) {
    s.vertices.push_back(t.v);
    s.inverses.push_back(t.inv);
  }
  s.cell_start = cell_start_;
  s.cell_triangles = cell_tris_;
  return s;
}

SphereTriangulation SphereTriangulation::from_stored(Stored s, std::size_t points) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("stored triangulation: " + what); };
  if (s.vertices.empty() || s.vertices.size() != s.inverses.size())
    fail("the triangles' vertices and inverses differ in number (or there are none)");
  if (s.vertices.size() > std::numeric_limits<std::uint32_t>::max()) fail("too many triangles");
  for (const auto& v : s.vertices)
    for (const std::uint32_t i : v)
      if (i >= points) fail("a triangle names direction " + std::to_string(i) + " of " + std::to_string(points));
  for (const auto& inv : s.inverses)
    for (const double x : inv)
      if (!std::isfinite(x)) fail("a triangle's inverse is not finite");
  if (s.cell_start.size() != kCells + 1 || s.cell_start.front() != 0 || s.cell_start.back() != s.cell_triangles.size())
    fail("the grid's cell starts do not span its candidate list");
  for (std::size_t c = 0; c < kCells; ++c)
    if (s.cell_start[c] > s.cell_start[c + 1]) fail("the grid's cell starts decrease");
  for (const std::uint32_t t : s.cell_triangles)
    if (t >= s.vertices.size()) fail("a grid cell names triangle " + std::to_string(t));
  SphereTriangulation out;
  out.tris_.reserve(s.vertices.size());
  for (std::size_t t = 0; t < s.vertices.size(); ++t) out.tris_.push_back({s.vertices[t], s.inverses[t]});
  out.cell_start_ = std::move(s.cell_start);
  out.cell_tris_ = std::move(s.cell_triangles);
  return out;
}

bool SphereTriangulation::weights(const Triangle& t, const Vec3& d, std::array<double, 3>& w) const {
  for (int k = 0; k < 3; ++k) {
    const auto r = static_cast<std::size_t>(3 * k);
    w[static_cast<std::size_t>(k)] = t.inv[r] * d[0] + t.inv[r + 1] * d[1] + t.inv[r + 2] * d[2];
  }
  const double eps = -1e-9;
  return w[0] >= eps && w[1] >= eps && w[2] >= eps && (w[0] + w[1] + w[2]) > 0.0;
}

std::size_t SphereTriangulation::cell_of(const Vec3& d) const {
  const double az = std::atan2(d[1], d[0]);
  const double el = std::asin(std::clamp(d[2], -1.0, 1.0));
  const int ia = std::clamp(static_cast<int>((az + std::numbers::pi) / (2 * std::numbers::pi) * kAz), 0, kAz - 1);
  const int ie = std::clamp(static_cast<int>((el + std::numbers::pi / 2) / std::numbers::pi * kEl), 0, kEl - 1);
  return static_cast<std::size_t>(ia * kEl + ie);
}

Blend SphereTriangulation::locate(const Vec3& d, std::uint32_t hint) const {
  std::array<double, 3> w{};
  const Triangle* hit = nullptr;
  if (hint < tris_.size() && weights(tris_[hint], d, w)) hit = &tris_[hint];
  const std::size_t c = hit ? 0 : cell_of(d);
  for (std::uint32_t i = hit ? cell_start_[c + 1] : cell_start_[c]; i < cell_start_[c + 1] && !hit; ++i)
    if (weights(tris_[cell_tris_[i]], d, w)) hit = &tris_[cell_tris_[i]];
  for (std::size_t i = 0; i < tris_.size() && !hit; ++i)  // a sliver the grid missed
    if (weights(tris_[i], d, w)) hit = &tris_[i];
  Blend b;
  if (!hit) {  // cannot happen for a closed hull; keep the output defined
    b.index = tris_.front().v;
    b.weight = {1.0, 0.0, 0.0};
    return b;
  }
  const double s = std::max(0.0, w[0]) + std::max(0.0, w[1]) + std::max(0.0, w[2]);
  b.index = hit->v;
  b.triangle = static_cast<std::uint32_t>(hit - tris_.data());
  for (int k = 0; k < 3; ++k) b.weight[static_cast<std::size_t>(k)] = std::max(0.0, w[static_cast<std::size_t>(k)]) / s;
  return b;
}

}  // namespace earshot::hrtf
