// Dots CSV: what the camera saw, one frame per line (the contract in
// docs/ARCHITECTURE.md):
//   t_s,x1,y1,x2,y2,x3,y3,x4,y4[,ground truth...]
// Dots come in camera-slot order, unlabelled; an empty pair is an empty slot.
// The simulator appends ground truth: gt_tx_mm,gt_ty_mm,gt_tz_mm,gt_qw,gt_qx,
// gt_qy,gt_qz,gt_led1..gt_led4 (LED number 1-4 seen in each slot, 0 = empty,
// -1 = stray reflection). The solver ignores those columns.
#pragma once

#include <array>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "earshot/tracker/core/geometry.hpp"

namespace earshot::tracker {

inline constexpr int kSlots = 4;

struct GroundTruth {
  Pose pose;
  std::array<int, kSlots> slot_led{0, 0, 0, 0};  ///< 1-4, 0 empty, -1 stray
};

struct DotFrame {
  double t = 0.0;  ///< seconds
  std::array<std::optional<Vec2>, kSlots> slots;
  std::optional<GroundTruth> truth;

  [[nodiscard]] int visible() const;
};

/// Reads Dots CSV line by line. Errors name the origin, line and field.
class DotsCsvReader {
 public:
  DotsCsvReader(std::istream& in, std::string origin);
  /// Next frame, or nullopt at end of input. Throws InputError on a bad line.
  std::optional<DotFrame> next();

 private:
  std::istream& in_;
  std::string origin_;
  long line_ = 0;
  bool has_truth_ = false;
  std::vector<std::string> header_;
  std::string line_buf_;
};

/// Parses one data line (no header) of a Dots CSV. `with_truth` expects the
/// ground-truth columns too. Throws InputError naming origin/line/field.
[[nodiscard]] DotFrame parse_dots_line(std::string_view line, bool with_truth,
                                       std::string_view origin, long line_number);

/// Reads a whole Dots CSV file.
[[nodiscard]] std::vector<DotFrame> read_dots_csv(const std::string& path);

/// Writes the header and frames (with ground truth columns when present).
class DotsCsvWriter {
 public:
  DotsCsvWriter(std::ostream& out, bool with_truth);
  void write(const DotFrame& f);

 private:
  std::ostream& out_;
  bool with_truth_;
};

}  // namespace earshot::tracker
