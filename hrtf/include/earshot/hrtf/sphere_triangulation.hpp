// Triangulation of measured directions on the unit sphere, and barycentric
// lookup of any direction in it: the convex hull of the direction vectors.
// Directions that no measurement surrounds (a missing bottom cap) fall in a
// hull face that spans the gap, so they blend the nearest ring's measurements.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "earshot/geometry.hpp"

namespace earshot::hrtf {


/// Three measurement indices and their weights (non-negative, sum 1).
struct Blend {
  std::array<std::uint32_t, 3> index{};
  std::array<double, 3> weight{};
  std::uint32_t triangle = 0;  ///< which hull triangle; a hint for the next locate()
};

class SphereTriangulation {
 public:
  /// Builds the hull of `dirs` (unit vectors). A direction given twice is
  /// triangulated once: locate() names the first. Throws
  /// std::invalid_argument when fewer than four differ, when they lie in one
  /// plane (a ring), or within one hemisphere (the hull must surround the
  /// centre, or the far side would have no triangle to blend).
  explicit SphereTriangulation(std::span<const Vec3> dirs);

  /// Weights of the triangle the ray through `d` crosses. No allocation.
  /// `hint`: a triangle to try first (a moving source is usually still in
  /// the one it was in last block).
  [[nodiscard]] Blend locate(const Vec3& d, std::uint32_t hint = kNoHint) const;
  static constexpr std::uint32_t kNoHint = 0xffffffffu;

  [[nodiscard]] std::size_t triangle_count() const { return tris_.size(); }
  /// The measurement indices of triangle t, in the order locate() gives them.
  [[nodiscard]] std::array<std::uint32_t, 3> vertices(std::size_t t) const { return tris_[t].v; }

  /// What the constructor computes, as plain arrays (for a disk cache of
  /// prepared sets): each triangle's vertices and inverse matrix, and the
  /// acceleration grid (cell c's candidates are cell_triangles[cell_start[c]
  /// .. cell_start[c + 1]]).
  struct Stored {
    std::vector<std::array<std::uint32_t, 3>> vertices;
    std::vector<std::array<double, 9>> inverses;
    std::vector<std::uint32_t> cell_start, cell_triangles;
  };
  [[nodiscard]] Stored stored() const;
  /// The triangulation `stored()` gave, taken back without recomputing.
  /// Checks what locate() relies on and throws std::invalid_argument naming
  /// the array that does not fit: vertex indices below `points`, finite
  /// inverses, one grid cell per kCells, candidate lists in range.
  [[nodiscard]] static SphereTriangulation from_stored(Stored s, std::size_t points);
  /// Cells of the acceleration grid.
  static constexpr std::size_t kCells = 60 * 30;

 private:
  SphereTriangulation() = default;
  struct Triangle {
    std::array<std::uint32_t, 3> v;
    std::array<double, 9> inv;  // inverse of [a b c] (columns), row-major
  };
  [[nodiscard]] bool weights(const Triangle& t, const Vec3& d, std::array<double, 3>& w) const;
  [[nodiscard]] std::size_t cell_of(const Vec3& d) const;
  [[nodiscard]] static std::vector<std::vector<std::uint32_t>> triangles_near_cells(
      const std::vector<Triangle>& tris, std::span<const Vec3> dirs);

  std::vector<Triangle> tris_;
  // Acceleration grid over azimuth x elevation: candidate triangles per cell.
  static constexpr int kAz = 60, kEl = 30;
  static_assert(kCells == std::size_t{kAz} * kEl);
  std::vector<std::uint32_t> cell_start_, cell_tris_;
};

}  // namespace earshot::hrtf
