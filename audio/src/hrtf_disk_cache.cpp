#include "earshot/audio/hrtf_disk_cache.hpp"

#include "earshot/audio/cache_files.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#define XXH_INLINE_ALL  // header only: no library to link into the plugin
#include <xxhash.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>

namespace earshot::audio {
namespace fs = std::filesystem;
namespace {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big);

// ---- sections ----

/// Every section in file order (the shell sections repeat once per shell).
/// An element type that changes size fails the static_assert in put/get
/// until its entry here changes, and the entries are part of the format id.
enum Section : std::size_t { kSetScalars, kSetSizes, kDirs, kFilters, kHrirs, kDelays, kEnergies,
                             kShell, kTriVertices, kTriInverses, kCellStart, kCellTriangles, kGram,
                             kSpectraBlock, kSpectraHead, kSpectraTail, kSpectraScale, kSectionCount };
struct SectionDef {
  char tag[5];
  std::uint32_t size;
};
constexpr std::array<SectionDef, kSectionCount> kSections{{
    {"SETD", 8},   // double: rate, removed delay
    {"SETN", 8},   // uint64: filter length, response length, shells
    {"DIRS", 16},  // Direction
    {"FILT", 4},   // float: the onset-free filters
    {"HRIR", 4},   // float: the resampled responses
    {"DELY", 16},  // Delays
    {"ENRG", 16},  // double[2]: the filters' energies
    {"SHEL", 24},  // StoredShellInfo
    {"TVTX", 12},  // uint32[3]: triangle vertices
    {"TINV", 72},  // double[9]: triangle inverses
    {"CSTA", 4},   // uint32: grid cell starts
    {"CTRI", 4},   // uint32: grid candidates
    {"GRAM", 96},  // double[2][6]: Gram tables
    {"SPEB", 8},   // uint64: block
    {"SPEH", 4},   // float: head partitions
    {"SPET", 2},   // int16: tail partitions
    {"SPES", 4},   // float: tail scales
}};

struct StoredShellInfo {
  std::uint64_t first, count;
  double radius_m;
};

constexpr std::array<std::uint8_t, 8> kMagic{'E', 'S', 'H', 'R', 'T', 'F', '\r', '\n'};
constexpr std::uint32_t kByteOrderMark = 0x01020304u;

std::uint32_t tag_of(Section s) {
  std::uint32_t t = 0;
  std::memcpy(&t, kSections[s].tag, 4);
  return t;
}

/// A file's payload as pieces: section headers and small sections owned
/// here, large arrays referenced where they are (they must outlive the
/// Writer), so an 11 MB payload is never copied into one buffer to be
/// written.
class Writer {
 public:
  template <Section S, class T>
  void put(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    static_assert(sizeof(T) == kSections[S].size, "a section's element changed size: change kSections");
    const std::uint32_t tag = tag_of(S), size = sizeof(T);
    const std::uint64_t count = values.size();
    std::vector<std::uint8_t>& head = owned_.emplace_back(16);
    std::memcpy(head.data(), &tag, 4);
    std::memcpy(head.data() + 4, &size, 4);
    std::memcpy(head.data() + 8, &count, 8);
    const auto* data = reinterpret_cast<const std::uint8_t*>(values.data());
    if (values.size_bytes() <= 256) {
      head.insert(head.end(), data, data + values.size_bytes());
      add(head);
    } else {
      add(head);
      pieces_.emplace_back(data, values.size_bytes());
      bytes_ += values.size_bytes();
    }
    if (const std::size_t pad = (8 - bytes_ % 8) % 8) {
      pieces_.emplace_back(kZeros.data(), pad);
      bytes_ += pad;
    }
  }
  template <Section S, class T, class A>
  void put(const std::vector<T, A>& v) {
    put<S, T>(std::span<const T>(v));
  }
  [[nodiscard]] const std::vector<std::span<const std::uint8_t>>& pieces() const { return pieces_; }
  [[nodiscard]] std::size_t bytes() const { return bytes_; }

 private:
  void add(const std::vector<std::uint8_t>& b) {
    pieces_.emplace_back(b.data(), b.size());
    bytes_ += b.size();
  }
  static constexpr std::array<std::uint8_t, 8> kZeros{};
  std::deque<std::vector<std::uint8_t>> owned_;  // a deque: what pieces_ points at never moves
  std::vector<std::span<const std::uint8_t>> pieces_;
  std::size_t bytes_ = 0;
};

[[noreturn]] void corrupt(const std::string& what) { throw std::runtime_error(what); }

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> b) : b_(b) {}

  /// The next section, which must be S, into a new container of T.
  template <Section S, class T, class Container = std::vector<T>>
  Container get() {
    static_assert(std::is_trivially_copyable_v<T>);
    static_assert(sizeof(T) == kSections[S].size, "a section's element changed size: change kSections");
    const std::string name(kSections[S].tag);
    std::uint32_t tag = 0, size = 0;
    std::uint64_t count = 0;
    if (left() < 16) corrupt("truncated before section " + name);
    raw(&tag, 4);
    raw(&size, 4);
    raw(&count, 8);
    if (tag != tag_of(S)) corrupt("section " + name + " expected at byte " + std::to_string(at_ - 16));
    if (size != sizeof(T)) corrupt("section " + name + " has elements of " + std::to_string(size) + " bytes");
    if (count > left() / sizeof(T))
      corrupt("section " + name + " claims " + std::to_string(count) + " elements, more than the file holds");
    const std::uint8_t* from = b_.data() + at_;
    Container out;
    if (reinterpret_cast<std::uintptr_t>(from) % alignof(T) == 0) {
      // Copied straight from the file's bytes (sections start 8-aligned):
      // no zero-filling of what is overwritten at once.
      const T* first = reinterpret_cast<const T*>(from);
      out.assign(first, first + count);
    } else {
      out.resize(static_cast<std::size_t>(count));
      std::memcpy(out.data(), from, out.size() * sizeof(T));
    }
    at_ += static_cast<std::size_t>(count) * sizeof(T);
    const std::size_t pad = (8 - at_ % 8) % 8;
    if (left() < pad) corrupt("truncated in section " + name);
    at_ += pad;
    return out;
  }
  template <Section S, class T>
  std::vector<T> get_exactly(std::size_t n) {
    std::vector<T> v = get<S, T>();
    if (v.size() != n)
      corrupt("section " + std::string(kSections[S].tag) + " has " + std::to_string(v.size()) + " elements, not " +
              std::to_string(n));
    return v;
  }
  [[nodiscard]] std::size_t left() const { return b_.size() - at_; }

 private:
  void raw(void* p, std::size_t n) {
    if (n) std::memcpy(p, b_.data() + at_, n);
    at_ += n;
  }
  std::span<const std::uint8_t> b_;
  std::size_t at_ = 0;
};

using cache_files::errno_text;
using cache_files::hash128;
using cache_files::hex;

struct Header {
  std::array<std::uint8_t, 8> magic = kMagic;
  std::uint32_t version = HrtfDiskCache::kFormatVersion;
  std::uint32_t byte_order = kByteOrderMark;
  std::uint64_t format_id = 0;
  std::array<std::uint8_t, 16> sofa_hash{};
  double rate = 0.0;
  std::uint64_t block = 0;
  std::uint64_t payload_bytes = 0;
  std::array<std::uint8_t, 16> checksum{};
};
static_assert(sizeof(Header) == HrtfDiskCache::kHeaderBytes && std::is_trivially_copyable_v<Header>);


}  // namespace

// ---- format ----

std::string HrtfDiskCache::layout() {
  std::string s;
  for (const SectionDef& d : kSections) s += std::string(d.tag) + ":" + std::to_string(d.size) + ";";
  return s;
}

std::uint64_t HrtfDiskCache::format_id(std::uint32_t file_version, std::uint32_t set_version,
                                       std::uint32_t spectra_version, std::string_view layout) {
  std::string text = std::to_string(file_version) + "/" + std::to_string(set_version) + "/" +
                     std::to_string(spectra_version) + "/" + std::string(layout);
  return XXH3_64bits(text.data(), text.size());
}

std::uint64_t HrtfDiskCache::format_id() {
  static const std::uint64_t id =
      format_id(kFormatVersion, hrtf::HrtfSet::kPreparationVersion, HrtfSpectra::kPreparationVersion, layout());
  return id;
}

namespace {

/// The arrays of a set and its spectra as a file's payload (referencing
/// `s` and `sp`, which must outlive it).
Writer payload_of(const hrtf::HrtfSet::Stored& s, const HrtfSpectra::Stored& sp) {
  Writer w;
  w.put<kSetScalars>(std::vector<double>{s.rate, s.removed_delay_s});
  w.put<kSetSizes>(std::vector<std::uint64_t>{s.filter_length, s.hrir_length, s.shells.size()});
  w.put<kDirs>(s.directions);
  w.put<kFilters>(s.filters);
  w.put<kHrirs>(s.hrirs);
  w.put<kDelays>(s.delays);
  w.put<kEnergies>(s.energies);
  for (const auto& sh : s.shells) {
    w.put<kShell>(std::vector<StoredShellInfo>{{sh.info.first, sh.info.count, sh.info.radius_m}});
    w.put<kTriVertices>(sh.triangulation.vertices);
    w.put<kTriInverses>(sh.triangulation.inverses);
    w.put<kCellStart>(sh.triangulation.cell_start);
    w.put<kCellTriangles>(sh.triangulation.cell_triangles);
    w.put<kGram>(sh.gram);
  }
  w.put<kSpectraBlock>(std::vector<std::uint64_t>{sp.block});
  w.put<kSpectraHead>(sp.head);
  w.put<kSpectraTail>(sp.tail);
  w.put<kSpectraScale>(sp.scale);
  return w;
}

Header header_of(const HrtfDiskCache::Key& key, const Writer& w) {
  Header h;
  h.format_id = HrtfDiskCache::format_id();
  h.sofa_hash = key.sofa_hash;
  h.rate = key.rate;
  h.block = key.block;
  h.payload_bytes = w.bytes();
  XXH3_state_t state;
  XXH3_128bits_reset(&state);
  for (const auto& piece : w.pieces()) XXH3_128bits_update(&state, piece.data(), piece.size());
  XXH128_canonical_t c;
  XXH128_canonicalFromHash(&c, XXH3_128bits_digest(&state));
  std::memcpy(h.checksum.data(), c.digest, 16);
  return h;
}

}  // namespace

std::vector<std::uint8_t> HrtfDiskCache::serialize(const Key& key, const hrtf::HrtfSet& set,
                                                   const HrtfSpectra& spectra) {
  const hrtf::HrtfSet::Stored s = set.stored();
  const HrtfSpectra::Stored sp = spectra.stored();
  const Writer w = payload_of(s, sp);
  const Header h = header_of(key, w);
  std::vector<std::uint8_t> out(kHeaderBytes);
  out.reserve(kHeaderBytes + w.bytes());
  std::memcpy(out.data(), &h, sizeof h);
  for (const auto& piece : w.pieces()) out.insert(out.end(), piece.begin(), piece.end());
  return out;
}

HrtfDiskCache::Loaded HrtfDiskCache::parse(std::span<const std::uint8_t> bytes, const Key& expected,
                                           bool verify_checksum) {
  if (bytes.size() < kHeaderBytes) corrupt("shorter than its header (" + std::to_string(bytes.size()) + " bytes)");
  Header h;
  std::memcpy(&h, bytes.data(), sizeof h);
  if (h.magic != kMagic) corrupt("not an Earshot HRTF cache file (magic)");
  if (h.byte_order != kByteOrderMark) corrupt("written on a machine of another byte order");
  if (h.version != kFormatVersion || h.format_id != format_id())
    corrupt("written by another version of Earshot (format " + std::to_string(h.version) + ")");
  if (h.sofa_hash != expected.sofa_hash || !(h.rate == expected.rate) || h.block != expected.block)
    corrupt("holds another set, rate or block than its name says");
  const std::span<const std::uint8_t> payload = bytes.subspan(kHeaderBytes);
  if (h.payload_bytes != payload.size())
    corrupt("payload of " + std::to_string(payload.size()) + " bytes, header says " + std::to_string(h.payload_bytes));
  if (verify_checksum && hash128(payload) != h.checksum) corrupt("checksum does not match (corrupt)");

  Reader r(payload);
  hrtf::HrtfSet::Stored s;
  const auto scalars = r.get_exactly<kSetScalars, double>(2);
  const auto sizes = r.get_exactly<kSetSizes, std::uint64_t>(3);
  s.rate = scalars[0];
  s.removed_delay_s = scalars[1];
  s.filter_length = static_cast<std::size_t>(sizes[0]);
  s.hrir_length = static_cast<std::size_t>(sizes[1]);
  s.directions = r.get<kDirs, hrtf::Direction>();
  s.filters = r.get<kFilters, float>();
  s.hrirs = r.get<kHrirs, float>();
  s.delays = r.get<kDelays, hrtf::Delays>();
  s.energies = r.get<kEnergies, std::array<double, 2>>();
  // Each shell takes at least six section headers: a count beyond what the
  // bytes left could hold fails here, before any loop or allocation.
  if (sizes[2] == 0 || sizes[2] > r.left() / (6 * 16)) corrupt(std::to_string(sizes[2]) + " shells");
  for (std::uint64_t i = 0; i < sizes[2]; ++i) {
    hrtf::HrtfSet::StoredShell sh;
    const StoredShellInfo info = r.get_exactly<kShell, StoredShellInfo>(1)[0];
    sh.info = {info.radius_m, static_cast<std::size_t>(info.first), static_cast<std::size_t>(info.count)};
    sh.triangulation.vertices = r.get<kTriVertices, std::array<std::uint32_t, 3>>();
    sh.triangulation.inverses = r.get<kTriInverses, std::array<double, 9>>();
    sh.triangulation.cell_start = r.get<kCellStart, std::uint32_t>();
    sh.triangulation.cell_triangles = r.get<kCellTriangles, std::uint32_t>();
    sh.gram = r.get<kGram, std::array<std::array<double, 6>, 2>>();
    s.shells.push_back(std::move(sh));
  }
  HrtfSpectra::Stored sp;
  sp.block = static_cast<std::size_t>(r.get_exactly<kSpectraBlock, std::uint64_t>(1)[0]);
  sp.head = r.get<kSpectraHead, float, AlignedVector<float>>();
  sp.tail = r.get<kSpectraTail, std::int16_t, AlignedVector<std::int16_t>>();
  sp.scale = r.get<kSpectraScale, float>();
  if (r.left() != 0) corrupt(std::to_string(r.left()) + " bytes after the last section");
  if (!(s.rate == expected.rate) || sp.block != expected.block) corrupt("holds another rate or block than its header");

  hrtf::HrtfSet set = hrtf::HrtfSet::from_stored(std::move(s));
  HrtfSpectra spectra(set, std::move(sp));
  return {std::move(set), std::move(spectra)};
}

// ---- the cache ----

std::optional<HrtfDiskCache::Key> HrtfDiskCache::key_of(const fs::path& sofa, double rate, std::size_t block) {
  const int fd = ::open(sofa.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  struct stat st {};
  std::optional<Key> key;
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0 &&
      static_cast<std::uintmax_t>(st.st_size) <= hrtf::HrtfSet::kMaxFileBytes) {
    // Hashed where the page cache holds it: nothing copied or zeroed.
    const auto size = static_cast<std::size_t>(st.st_size);
    void* map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
    if (map != MAP_FAILED) {
      key = Key{hash128(std::span(static_cast<const std::uint8_t*>(map), size)), rate, block};
      ::munmap(map, size);
    }
  }
  ::close(fd);
  return key;
}

std::optional<fs::path> HrtfDiskCache::directory_from_environment() {
  const auto env = [](const char* name) -> std::string {
    const char* v = std::getenv(name);
    return v ? v : "";
  };
  if (const std::string dir = env("EARSHOT_CACHE_DIR"); !dir.empty()) {
    if (dir == "off") return std::nullopt;
    return fs::path(dir);
  }
  // XDG: a relative XDG_CACHE_HOME is invalid and ignored.
  if (const std::string xdg = env("XDG_CACHE_HOME"); !xdg.empty() && fs::path(xdg).is_absolute())
    return fs::path(xdg) / "earshot";
  if (const std::string home = env("HOME"); !home.empty()) return fs::path(home) / ".cache" / "earshot";
  return std::nullopt;
}

HrtfDiskCache::HrtfDiskCache(std::optional<fs::path> dir, Notes notes) : dir_(std::move(dir)), notes_(std::move(notes)) {
  if (!notes_) notes_ = [](const std::string& line) { std::fprintf(stderr, "earshot: %s\n", line.c_str()); };
}

void HrtfDiskCache::note(const std::string& line) const { notes_(line); }

fs::path HrtfDiskCache::file_for(const Key& key) const {
  std::array<std::uint8_t, 40> name{};
  const std::uint64_t id = format_id();
  std::memcpy(name.data(), key.sofa_hash.data(), 16);
  std::memcpy(name.data() + 16, &key.rate, 8);
  std::memcpy(name.data() + 24, &key.block, 8);
  std::memcpy(name.data() + 32, &id, 8);
  return dir_.value() / (hex(hash128(name)) + ".hrtf");
}

std::optional<HrtfDiskCache::Loaded> HrtfDiskCache::load(const Key& key) const {
  if (!dir_) return std::nullopt;
  const fs::path file = file_for(key);
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno != ENOENT && errno != ENOTDIR) note("cannot read the HRTF cache file " + file.string() + " (" + errno_text(errno) + "): preparing the set again");
    return std::nullopt;
  }
  std::string problem;
  struct stat st {};
  void* map = MAP_FAILED;
  std::size_t size = 0;
  if (::fstat(fd, &st) != 0) {
    problem = errno_text(errno);
  } else if (static_cast<std::uintmax_t>(st.st_size) > kMaxFileBytes) {
    problem = "larger than " + std::to_string(kMaxFileBytes) + " bytes";
  } else if (st.st_size == 0) {
    problem = "empty";
  } else {
    // Mapped, not read: the bytes are copied once, from the page cache
    // straight into the arrays.
    size = static_cast<std::size_t>(st.st_size);
    map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
    if (map == MAP_FAILED) problem = errno_text(errno);
  }
  ::close(fd);
  if (problem.empty()) {
    // A file truncated by someone else while mapped raises SIGBUS on
    // access; the cache's own files are only ever replaced by rename.
    const std::unique_ptr<void, std::function<void(void*)>> unmap(map, [size](void* p) { ::munmap(p, size); });
    try {
      Loaded l = parse(std::span(static_cast<const std::uint8_t*>(map), size), key);
      std::error_code ec;
      fs::last_write_time(file, fs::file_time_type::clock::now(), ec);  // used: kept longest by prune()
      return l;
    } catch (const std::exception& e) {
      problem = e.what();
    }
  }
  note("ignored the HRTF cache file " + file.string() + ": " + problem + "; preparing the set again");
  return std::nullopt;
}

void HrtfDiskCache::store(const Key& key, const hrtf::HrtfSet& set, const HrtfSpectra& spectra) {
  if (!dir_) return;
  std::string problem;
  try {
    const hrtf::HrtfSet::Stored s = set.stored();
    const HrtfSpectra::Stored sp = spectra.stored();
    const Writer w = payload_of(s, sp);
    const Header h = header_of(key, w);
    std::vector<std::span<const std::uint8_t>> pieces{{reinterpret_cast<const std::uint8_t*>(&h), sizeof h}};
    pieces.insert(pieces.end(), w.pieces().begin(), w.pieces().end());
    problem = cache_files::write_whole(file_for(key), pieces);
  } catch (const std::exception& e) {
    problem = e.what();
  }
  if (problem.empty()) {
    cache_files::prune(*dir_, ".hrtf", kMaxFiles);
    return;
  }
  if (!write_failed_.exchange(true))
    note("cannot write the HRTF cache in " + dir_->string() + " (" + problem +
         "): HRTF sets are prepared in every process (EARSHOT_CACHE_DIR names another directory, =off turns "
         "the cache off)");
}

}  // namespace earshot::audio
