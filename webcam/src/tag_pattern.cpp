#include "earshot/webcam/tag_pattern.hpp"

#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>

#include <array>
#include <cstdint>
#include <stdexcept>

#include "tag_families.hpp"

namespace earshot::webcam {
namespace detail {
namespace {

struct FamilyEntry {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

constexpr std::array<FamilyEntry, 9> kFamilies{{
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tag36h10", tag36h10_create, tag36h10_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
    {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
}};

}  // namespace

std::string family_names() {
  std::string s;
  for (const auto& f : kFamilies) {
    if (!s.empty()) s += ", ";
    s += f.name;
  }
  return s;
}

FamilyPtr create_family(std::string_view name) {
  for (const auto& f : kFamilies)
    if (name == f.name) return FamilyPtr(f.create(), FamilyDeleter{f.destroy});
  throw std::invalid_argument("unknown AprilTag family '" + std::string(name) + "' (known: " + family_names() + ")");
}

}  // namespace detail

std::string tag_family_names() { return detail::family_names(); }

TagPattern tag_pattern(std::string_view family, int id) {
  const detail::FamilyPtr fam = detail::create_family(family);
  if (id < 0 || static_cast<std::uint32_t>(id) >= fam->ncodes)
    throw std::invalid_argument("AprilTag family " + std::string(family) + " has ids 0.." +
                                std::to_string(fam->ncodes - 1) + ", not " + std::to_string(id));
  TagPattern p;
  p.family = std::string(family);
  p.id = id;
  p.total_width = fam->total_width;
  p.width_at_border = fam->width_at_border;
  p.border_start = (fam->total_width - fam->width_at_border) / 2;
  const auto n = static_cast<size_t>(p.total_width);
  p.cells.assign(n * n, 0);
  // The layout libapriltag prints (apriltag_to_image): black paper, a
  // one-cell white ring (just outside the black border of a normal family,
  // inside the data of a reversed-border one), then a white cell for every
  // set bit, bit_x/bit_y counted from the border square's first cell (they
  // may be "negative", stored modulo 2^32, for bits outside the border).
  const int ring = fam->width_at_border + (fam->reversed_border ? 0 : 2);
  const int ring_start = (p.total_width - ring) / 2;
  auto set = [&](int x, int y) {
    if (x >= 0 && y >= 0 && x < p.total_width && y < p.total_width)
      p.cells[static_cast<size_t>(y) * n + static_cast<size_t>(x)] = 1;
  };
  for (int i = 0; i < ring - 1; ++i) {
    set(ring_start + i, ring_start);
    set(ring_start + ring - 1, ring_start + i);
    set(ring_start + ring - 1 - i, ring_start + ring - 1);
    set(ring_start, ring_start + ring - 1 - i);
  }
  const std::uint64_t code = fam->codes[id];
  for (std::uint32_t i = 0; i < fam->nbits; ++i) {
    if ((code >> (fam->nbits - 1 - i)) & 1u)
      set(static_cast<int>(static_cast<std::int32_t>(fam->bit_x[i])) + p.border_start,
          static_cast<int>(static_cast<std::int32_t>(fam->bit_y[i])) + p.border_start);
  }
  return p;
}

}  // namespace earshot::webcam
