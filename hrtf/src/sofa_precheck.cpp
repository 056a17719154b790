#include "sofa_precheck.hpp"

#include <algorithm>
#include <cstring>
#include <optional>
#include <set>
#include <string_view>
#include <vector>

namespace earshot::hrtf::detail {
namespace {

// Layout facts from the HDF5 file format specification (superblock v2/3,
// object header v2, dataspace v1/v2, datatype, attribute v1/v3 messages),
// read the way libmysofa reads them.

/// Little-endian reads from a position; a read past the end gives nullopt
/// (where libmysofa would read all ones).
struct Cursor {
  std::span<const std::uint8_t> f;
  std::uint64_t pos = 0;
  std::optional<std::uint64_t> value(unsigned bytes) {
    if (bytes > 8 || pos > f.size() || f.size() - pos < bytes) {
      pos = f.size() + 1;  // at the end: every later read fails too
      return std::nullopt;
    }
    std::uint64_t v = 0;
    for (unsigned i = 0; i < bytes; ++i) v |= std::uint64_t{f[pos + i]} << (8 * i);
    pos += bytes;
    return v;
  }
  int byte() {
    const auto v = value(1);
    return v ? static_cast<int>(*v) : -1;
  }
};

struct Limits {
  unsigned size_of_offsets = 8, size_of_lengths = 8;
  std::uint64_t max_dataset = 0;
};

std::string hex(std::uint64_t v) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  do s.insert(s.begin(), kDigits[v & 15]), v >>= 4;
  while (v);
  return "0x" + s;
}

/// Reads a dataspace message at c; the problem with its element count, if
/// any. nullopt: not a dataspace libmysofa would accept (it stops there).
std::optional<std::string> dataspace(Cursor& c, const Limits& lim, std::uint64_t max_elements, std::string_view what) {
  const std::uint64_t at = c.pos;
  const int version = c.byte();
  if (version != 1 && version != 2) return std::nullopt;
  const int rank = c.byte();
  if (rank < 0 || rank > 4) return std::nullopt;
  const int flags = c.byte();
  c.value(version == 1 ? 5 : 1);  // v1: reserved bytes; v2: the type
  // libmysofa loops over the dimensions nested, outermost first: each
  // leading product counts passes (a huge first dimension loops even when a
  // later one is 0).
  std::string dims;
  std::uint64_t passes = 1;
  bool too_many = false;
  for (int i = 0; i < rank; ++i) {
    const auto d = c.value(lim.size_of_lengths);
    if (!d) return std::string(what) + " at " + hex(at) + " runs past the end of the file";
    dims += (i ? " x " : "") + std::to_string(*d);
    if (passes != 0 && *d > max_elements / passes) too_many = true;
    if (!too_many) passes *= *d;
  }
  if (flags >= 0 && (flags & 1))  // maximum sizes follow; libmysofa reads and ignores them
    for (int i = 0; i < rank; ++i)
      if (!c.value(lim.size_of_lengths)) return std::string(what) + " at " + hex(at) + " runs past the end of the file";
  if (too_many)
    return std::string(what) + " at " + hex(at) + " declares " + dims + " elements, more than " +
           std::to_string(max_elements);
  return std::string();
}

/// Skips a datatype message as libmysofa parses it; false where libmysofa
/// would stop (an unsupported type) or the types nest absurdly deep.
bool datatype(Cursor& c, int depth = 0) {
  if (depth > 16) return false;
  const int cv = c.byte();
  if (cv < 0 || ((cv & 0xf0) != 0x10 && (cv & 0xf0) != 0x30)) return false;
  const auto bits = c.value(3);
  const auto size = c.value(4);
  if (!bits || !size) return false;
  switch (cv & 0xf) {
    case 0: return c.value(4).has_value();   // fixed point: offset, precision
    case 1: return c.value(12).has_value();  // floating point properties
    case 3:
    case 7: return true;  // string, reference
    case 6: {  // compound: named members, each with an offset and a type
      const std::uint64_t members = *bits & 0xffff;
      if ((cv & 0xf0) == 0x30) {
        for (std::uint64_t i = 0; i < members; ++i) {
          int ch = 0;
          do ch = c.byte();
          while (ch > 0);
          for (unsigned j = 0; j < 4 && (*size >> (8 * j)) > 0; ++j) c.byte();
          if (ch < 0 || !datatype(c, depth + 1)) return false;
        }
        return true;
      }
      // Version 1 (libmysofa reads it too; fuzz_sofa found a header this
      // check stopped at while libmysofa went on to a dataspace it read for
      // minutes): each name padded to 8 bytes, a 4-byte offset, a
      // dimensionality that must be 0, 27 bytes libmysofa skips, the type.
      for (std::uint64_t i = 0; i < members; ++i) {
        unsigned length = 0;
        for (int ch = c.byte(); ch != 0; ch = c.byte(), ++length)
          if (ch < 0 || length + 1 >= 256) return false;
        c.pos += (7 - length) & 7;
        c.value(4);
        if (c.byte() != 0) return false;
        c.pos += 27;
        if (!datatype(c, depth + 1)) return false;
      }
      return true;
    }
    case 9: return datatype(c, depth + 1);  // variable-length list of a base type
    default: return false;
  }
}

struct Block {
  std::uint64_t start;  // first message
  std::uint64_t end;    // libmysofa reads messages while pos < end - 4
  int flags;            // the object header's
};

/// Walks one block of header messages; continuations go to `more`.
std::string messages(std::span<const std::uint8_t> f, const Block& b, const Limits& lim, std::vector<Block>& more) {
  Cursor c{f, b.start};
  const std::uint64_t stop = std::min<std::uint64_t>(b.end - 4, f.size());  // wraps like libmysofa's when end < 4
  while (c.pos < stop) {
    const int type = c.byte();
    const auto size = c.value(2);
    const int mflags = c.byte();
    if (type < 0 || !size || mflags < 0 || (mflags & ~5) != 0) break;
    if (b.flags & 4) c.pos += 2;  // creation order
    const std::uint64_t at = c.pos, end = c.pos + *size;
    if (type == 1) {
      if (auto p = dataspace(c, lim, lim.max_dataset, "a dataset's dataspace"); p && !p->empty()) return *p;
    } else if (type == 12) {
      // Attribute: version, flags, the sizes of name, datatype and dataspace,
      // (v3) the encoding, then the three; version 1 pads each to 8 bytes
      // (fuzz_sofa found a v1 attribute libmysofa read for minutes, which
      // this check had passed over when it knew only v3).
      const int version = c.byte();
      if (version != 1 && version != 3) break;
      const int aflags = c.byte();
      const auto name_size = c.value(2), datatype_size = c.value(2);
      c.value(2);
      if (version == 3) c.byte();
      if (!name_size || !datatype_size || aflags < 0 || (version == 3 && (aflags & 3))) break;
      c.pos += *name_size;
      if (version == 1) c.pos += (8 - *name_size) & 7;
      if (!datatype(c)) break;
      if (version == 1) c.pos += (8 - *datatype_size) & 7;
      if (auto p = dataspace(c, lim, kMaxAttributeElements, "an attribute's dataspace"); p && !p->empty()) return *p;
    } else if (type == 16) {  // continuation: the next block's address and length
      const auto offset = c.value(lim.size_of_offsets), length = c.value(lim.size_of_lengths);
      if (offset && length && *offset < f.size()) more.push_back({*offset + 4, *offset + *length - 4, b.flags});
    } else if (type != 0 && type != 2 && type != 3 && type != 5 && type != 8 && type != 10 && type != 11 &&
               type != 21) {
      break;  // libmysofa refuses the header here
    }
    c.pos = at <= end ? end : f.size();
  }
  return {};
}

}  // namespace

std::string sofa_header_problem(std::span<const std::uint8_t> f, std::uint64_t max_dataset) {
  Limits lim;
  lim.max_dataset = max_dataset;
  {
    // Superblock v2/v3: signature, version, size of offsets, size of lengths.
    Cursor c{f, 8};
    const int version = c.byte();
    if (version != 2 && version != 3) return {};  // libmysofa refuses it
    const int so = c.byte(), sl = c.byte();
    if (so < 1 || so > 8 || sl < 1 || sl > 8) return "the HDF5 superblock's sizes of offsets/lengths are not 1-8 bytes";
    lim.size_of_offsets = static_cast<unsigned>(so);
    lim.size_of_lengths = static_cast<unsigned>(sl);
  }
  // Every object header libmysofa could be sent to starts with "OHDR", and
  // every continuation it follows with "OCHK": look at all of them.
  std::vector<Block> pending;
  static constexpr char kOhdr[] = "OHDR";
  for (auto it = f.begin(); (it = std::search(it, f.end(), kOhdr, kOhdr + 4)) != f.end(); ++it) {
    Cursor c{f, static_cast<std::uint64_t>(it - f.begin()) + 4};
    if (c.byte() != 2) continue;
    const int flags = c.byte();
    if (flags < 0 || (flags & 0x10)) continue;
    if (flags & 0x20) c.pos += 16;  // time stamps
    const auto chunk = c.value(1u << (flags & 3));
    if (!chunk) continue;
    pending.push_back({c.pos, c.pos + *chunk, flags});
  }
  constexpr std::size_t kMaxBlocks = 100000;
  std::set<std::uint64_t> seen;
  for (std::size_t i = 0; i < pending.size(); ++i) {
    if (i >= kMaxBlocks) return "more than " + std::to_string(kMaxBlocks) + " HDF5 object header blocks";
    const Block b = pending[i];
    if (!seen.insert(b.start).second) continue;
    std::vector<Block> more;
    if (std::string p = messages(f, b, lim, more); !p.empty()) return p;
    for (const Block& m : more) {
      // Only a block that starts with "OCHK" is read as one.
      const std::uint64_t sig = m.start - 4;
      if (sig + 4 <= f.size() && std::memcmp(f.data() + sig, "OCHK", 4) == 0) pending.push_back(m);
    }
  }
  return {};
}

}  // namespace earshot::hrtf::detail
