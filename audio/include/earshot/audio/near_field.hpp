// The near field: what changes when a source is nearer than the distance an
// HRTF set was measured at (a whisper at the ear, a table of talkers), done
// the way 3D Tune-In does it, with the rigid-sphere model
// (earshot/hrtf/rigid_sphere.hpp) for the level:
//
// Acoustic parallax. Each ear hears the source from its own direction: its
// HRTF is read where the line from that ear through the source meets the
// measurement sphere (centred on the head), not from the head-centre
// direction. At the measurement distance the two agree, so nothing jumps as
// a source crosses it. The ears are on the interaural axis at the head
// radius (+-y). Each ear's delay is the measured one at its direction plus
// the sphere's correction: the path (hrtf::sphere_path_delay: straight when
// lit, tangent and arc when shadowed) from the source to that ear, less the
// path from the point its HRTF was read at. At the shell it is zero; for a
// set that is a sphere the ITD is then the sphere's near-field ITD (at 90
// degrees and 20 cm about 55 us more than Woodworth's far-field value, which
// parallax alone would not change on the interaural axis).
//
// Level. Per ear, a minimum-phase FIR of kTaps taps with the magnitude of
// H(r, theta) / H(R, theta_p): the sphere's response at the source's
// distance r and that ear's angle theta (from the head centre), over its
// response at the measurement distance R and the parallax angle theta_p the
// HRTF was read at. For a set that is a sphere, the product is the sphere's
// own near-field response. At r = R the ratio is 1 (the FIR is a unit
// impulse), so it is continuous across the shell; beyond the farthest shell
// nothing is applied. Sources nearer than min_distance_m() (1.15 head radii,
// about 10 cm) are treated as at it (the model diverges at the surface).
//
// The table: one FIR per shell, distance (32 steps even in 1/r from
// min_distance_m() to the farthest shell) and ear angle (5-degree steps),
// designed once per (rate, shells) and shared by every renderer of the
// process (shared()); a source's FIR is the bilinear blend of its four grid
// neighbours. Sets measured at several distances get one table per shell:
// the shell nearest the source supplies the HRTF and its own table only
// corrects from that shell's distance to the source's.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "earshot/audio/aligned_vector.hpp"
#include "earshot/geometry.hpp"
#include "earshot/hrtf/rigid_sphere.hpp"

namespace earshot::audio {

/// The unit vector (SOFA's frame: x ahead, y left, z up) from the head
/// centre to where the ray from the ear at (0, ear_y_m, 0) through `source`
/// (metres, same frame) meets the sphere of radius `shell_m` (> |ear_y_m|).
/// A source at the ear gives the ear's own axis.
[[nodiscard]] Vec3 parallax_direction(const Vec3& source, double ear_y_m, double shell_m);

class NearFieldTable {
 public:
  static constexpr std::size_t kTaps = 64;
  static constexpr std::size_t kDistances = 32;
  static constexpr std::size_t kAngles = 37;  ///< 0..180 degrees in 5-degree steps

  /// Designs every FIR (about 25 ms of CPU per shell at 48 kHz). `shells_m`:
  /// the set's measurement distances, farthest first.
  NearFieldTable(double sample_rate, std::span<const double> shells_m, hrtf::SphereHead head = {});

  /// The table for these parameters, built by the first caller and kept for
  /// the process (locks; not for the audio thread).
  [[nodiscard]] static std::shared_ptr<const NearFieldTable> shared(double sample_rate,
                                                                    std::span<const double> shells_m,
                                                                    hrtf::SphereHead head = {});

  [[nodiscard]] double sample_rate() const { return rate_; }
  [[nodiscard]] const hrtf::SphereHead& head() const { return head_; }
  [[nodiscard]] double min_distance_m() const { return r_min_; }
  [[nodiscard]] std::size_t shells() const { return shells_.size(); }
  [[nodiscard]] double shell_m(std::size_t s) const { return shells_[s]; }
  /// True when the table has no FIRs (the farthest shell is within
  /// min_distance_m(): nothing is near).
  [[nodiscard]] bool empty() const { return taps_.empty(); }

  /// The FIR for a source at `distance_m` and ear angle `theta` (radians,
  /// 0 = the ear faces it) when `shell`'s HRTFs are used, into `out` (kTaps).
  /// Returns false, writing nothing, when it is a unit impulse (shell 0 at or
  /// beyond its distance, or an empty table). No allocation.
  bool taps(std::size_t shell, double distance_m, double theta, std::span<float> out) const;

  /// Where a source falls in the table: its fractional grid coordinates.
  /// `on` is false where the FIR is a unit impulse (as taps() returns).
  struct GridPoint {
    std::size_t shell = 0;
    double distance = -1.0, angle = -1.0;
    bool on = false;
  };
  [[nodiscard]] GridPoint locate(std::size_t shell, double distance_m, double theta) const;
  /// The FIR at a point locate() gave with `on` (kTaps values into out).
  void taps_at(const GridPoint& g, std::span<float> out) const;
  /// How far (in grid cells) a source may move before its taps are
  /// recomputed (moved_enough()): its level then lags by at most this
  /// fraction of the change across one cell, and a slow source runs one FIR
  /// a block instead of gliding between two every block. At 48 kHz and
  /// 1.4 m the largest change across a cell (100 Hz-16 kHz) has a median
  /// of 0.93 dB over the grid and a 90th percentile of 7.7 dB (near the
  /// head, behind the ear, where the sphere's response turns fastest): a
  /// lag of 0.06 and 0.5 dB.
  static constexpr double kHoldCells = 0.0625;
  [[nodiscard]] static bool moved_enough(const GridPoint& from, const GridPoint& to) {
    return from.on != to.on || from.shell != to.shell || std::abs(from.distance - to.distance) > kHoldCells ||
           std::abs(from.angle - to.angle) > kHoldCells;
  }

 private:
  [[nodiscard]] const float* fir(std::size_t shell, std::size_t d, std::size_t a) const {
    return taps_.data() + ((shell * kDistances + d) * kAngles + a) * kTaps;
  }
  double rate_;
  hrtf::SphereHead head_;
  double r_min_;
  std::vector<double> shells_;
  double inv_near_ = 0.0, inv_far_ = 0.0;  // 1 / r at grid ends
  std::vector<float> taps_;                // [shell][distance][angle][tap]
};

/// One ear's near-field FIR on a stream of blocks: the taps glide from one
/// block's to the next across the block (a per-sample blend, so a moving
/// source does not click), and a unit impulse on both sides costs only the
/// copy that keeps the history. Allocates at construction only.
class NearFieldFilter {
 public:
  explicit NearFieldFilter(std::size_t block);
  /// Filters `x` in place towards `taps` (kTaps values, or empty for a unit
  /// impulse).
  void process(std::span<float> x, std::span<const float> taps);
  /// Filters `x` in place with the taps it has (the source moved too little
  /// for new ones: NearFieldTable::moved_enough).
  void hold(std::span<float> x) { process(x, from_unity_ ? std::span<const float>{} : std::span<const float>(from_)); }
  void reset();
  /// False while the taps are a unit impulse (the renderer then skips the
  /// filter, and its history goes stale: a source entering the near field
  /// does so at the shell, where the taps are a unit impulse too).
  [[nodiscard]] bool active() const { return !from_unity_; }

 private:
  std::size_t block_;
  std::array<float, NearFieldTable::kTaps> from_{}, to_{};
  bool from_unity_ = true;
  AlignedVector<float> line_;  // kTaps - 1 past inputs, then the block
};

}  // namespace earshot::audio
