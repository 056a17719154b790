// A tag's printed pattern cell by cell, read from libapriltag's family
// tables (the code word, the bit positions and the border layout), for
// rendering tags in synthetic video and for printing.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace earshot::webcam {

struct TagPattern {
  std::string family;
  int id = 0;
  int total_width = 0;      ///< cells per side, the white quiet border included
  int width_at_border = 0;  ///< cells per side of the square whose corners the detector finds
  int border_start = 0;     ///< row and column of that square's first cell
  /// total_width * total_width cells, row by row from the top-left of the
  /// printed tag: 1 white, 0 black.
  std::vector<std::uint8_t> cells;

  [[nodiscard]] bool white(int column, int row) const {
    return cells[static_cast<size_t>(row * total_width + column)] != 0;
  }
};

/// The pattern of tag `id` of `family` (tag36h11, tag25h9, tag16h5,
/// tag36h10, tagStandard41h12, tagStandard52h13, tagCircle21h7,
/// tagCircle49h12, tagCustom48h12). Throws std::invalid_argument naming the
/// family when it is unknown, or the id when the family has no such code.
[[nodiscard]] TagPattern tag_pattern(std::string_view family, int id);

/// The family names libapriltag provides, for messages.
[[nodiscard]] std::string tag_family_names();

}  // namespace earshot::webcam
