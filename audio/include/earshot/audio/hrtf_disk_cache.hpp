// HrtfDiskCache: a measured HRTF set's prepared data (the set and its
// spectra for one block size) kept on disk between processes, so the first
// world of a process reads a file instead of preparing the set from its SOFA
// file (resampling, onset split, triangulation, Gram tables, FFTs).
//
// Key: a 128-bit hash (XXH3) of the SOFA file's bytes, the render rate and
// the block size, and the format id: the file layout's version, both
// preparation versions (HrtfSet::kPreparationVersion,
// HrtfSpectra::kPreparationVersion) and the list of sections with their
// element sizes, hashed together. A changed SOFA file, another rate or block,
// or a build that prepares differently names another file; the parametric
// ITD radius is not part of it (a setting applied after loading).
//
// Where: $EARSHOT_CACHE_DIR, else $XDG_CACHE_HOME/earshot, else
// $HOME/.cache/earshot; EARSHOT_CACHE_DIR=off turns it off. One file per key,
// `<32 hex digits>.hrtf`, 11.4 MB for the default set at 48 kHz and 128-frame
// blocks; the kMaxFiles used last are kept, older ones removed (nothing else
// in the directory is touched).
//
// File: an 80-byte header (magic, format version, byte-order mark, format
// id, the key, payload size, XXH3-128 of the payload), then sections, each a
// tag, element size and count before its data (padded to 8 bytes). Written to
// a temporary file in the same directory and renamed over the name, so a
// reader sees a whole file or none, and two processes writing at once are
// fine. Read back, every size and count is checked against the bytes there
// are and against each other, and the arrays against what the renderer
// relies on (HrtfSet::from_stored): a truncated, corrupt, stale or hostile
// file is ignored with a note, the set is prepared from the SOFA file and the
// file written again. load() and store() never throw: a directory that
// cannot be written means no cache (one note).
//
// A set read back renders sample for sample what the freshly prepared one
// does (tests/unit/hrtf_disk_cache). Cost, default set: hashing the SOFA
// file 0.5 ms, reading the cache file 12 ms of CPU (preparing: 146 ms),
// writing it 23 ms.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "earshot/audio/hrtf_spectra.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::audio {

class HrtfDiskCache {
 public:
  /// What a file holds: the prepared data of these bytes at this rate and block.
  struct Key {
    std::array<std::uint8_t, 16> sofa_hash{};  ///< XXH3-128 of the SOFA file, canonical (big-endian) bytes
    double rate = 0.0;
    std::uint64_t block = 0;
    bool operator==(const Key&) const = default;
  };
  /// Reads and hashes `sofa` (about 0.2 ms for the 1.1 MB default set);
  /// nullopt when it cannot be read (the loader then says why).
  [[nodiscard]] static std::optional<Key> key_of(const std::filesystem::path& sofa, double rate, std::size_t block);

  /// A set and its spectra read back.
  struct Loaded {
    hrtf::HrtfSet set;
    HrtfSpectra spectra;
  };

  /// The directory the environment names (see above); nullopt when it says
  /// "off" or names none.
  [[nodiscard]] static std::optional<std::filesystem::path> directory_from_environment();

  /// Where notes go (a file ignored, a directory that cannot be written):
  /// one line each, for people. The default writes to stderr.
  using Notes = std::function<void(const std::string&)>;

  /// A cache in `dir` (created when first written); nullopt: no cache
  /// (load() finds nothing, store() does nothing).
  explicit HrtfDiskCache(std::optional<std::filesystem::path> dir, Notes notes = {});

  [[nodiscard]] const std::optional<std::filesystem::path>& directory() const { return dir_; }
  /// The file that holds `key`'s data (whether or not it exists); needs a directory.
  [[nodiscard]] std::filesystem::path file_for(const Key& key) const;

  /// `key`'s data from its file, or nullopt: no file, or one that could not
  /// be read or did not check out (noted, naming the file and the problem).
  [[nodiscard]] std::optional<Loaded> load(const Key& key) const;
  /// Writes `set` and `spectra` as `key`'s file (atomically). Never throws;
  /// the first failure is noted, later ones are not.
  void store(const Key& key, const hrtf::HrtfSet& set, const HrtfSpectra& spectra);

  /// How many .hrtf files the directory keeps (the most recently used).
  static constexpr std::size_t kMaxFiles = 8;
  /// Largest file read (the largest set the loader accepts is well under it).
  static constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 30;

  // ---- the file format (public for the tests and the fuzz target) ----

  /// The file layout's version: bump it with any change to the header or
  /// the sections that the section list below does not show.
  static constexpr std::uint32_t kFormatVersion = 1;
  static constexpr std::size_t kHeaderBytes = 80;
  /// The current format id (see the top of this file).
  [[nodiscard]] static std::uint64_t format_id();
  /// The id for these parts: a change to any of them changes it.
  [[nodiscard]] static std::uint64_t format_id(std::uint32_t file_version, std::uint32_t set_version,
                                               std::uint32_t spectra_version, std::string_view layout);
  /// The sections' tags and element sizes in file order, as text.
  [[nodiscard]] static std::string layout();
  /// A whole file's bytes.
  [[nodiscard]] static std::vector<std::uint8_t> serialize(const Key& key, const hrtf::HrtfSet& set,
                                                           const HrtfSpectra& spectra);
  /// Reads a file's bytes back; throws std::runtime_error or
  /// std::invalid_argument saying what does not check out. `verify_checksum`
  /// false reads on past a wrong checksum (the fuzz target: a hostile file
  /// can carry a right one).
  [[nodiscard]] static Loaded parse(std::span<const std::uint8_t> bytes, const Key& expected,
                                    bool verify_checksum = true);

 private:
  void note(const std::string& line) const;

  std::optional<std::filesystem::path> dir_;
  Notes notes_;
  std::atomic<bool> write_failed_{false};
};

}  // namespace earshot::audio
