// DecoderCache: binaural decoder filters (binaural_decoder_design.hpp)
// designed once per HRTF set, rate, order and design, shared read-only by
// every user in the process and kept on disk between processes, as the
// prepared HRTF data is (hrtf_cache.hpp, hrtf_disk_cache.hpp).
//
// A design costs 0.2-0.34 s of CPU (orders 1-5, KEMAR at 48 kHz), so nothing
// designs one until a bed or the Ambisonic tier needs it: a world with
// neither starts as fast as before. Then: memory first, then the disk, then
// the design (written to the disk for the next process).
//
// Identity in memory: the SOFA file's canonical path, size and mtime, the
// rate, the order, the parametric ITD radius (when the set was prepared with
// one: its delays differ) and design_key(). On disk: a 128-bit hash (XXH3)
// of the SOFA file's bytes with the same rate, order, radius and
// design_key() (which holds kDecoderDesignVersion, so a build that designs
// differently names other files), `<32 hex digits>.ambi` in the HRTF disk
// cache's directory ($EARSHOT_CACHE_DIR, else $XDG_CACHE_HOME/earshot, else
// ~/.cache/earshot; EARSHOT_CACHE_DIR=off turns it off), kMaxFiles kept.
//
// File: a 64-byte header (magic, format version, byte-order mark, the key's
// hash, payload size, XXH3-128 of the payload), then DecoderFilters::
// serialise()'s bytes (33 KB at order 1, 295 KB at order 5, 48 kHz). Written
// to a temporary name and renamed; read back, the header, the checksum and
// every size and tap are checked (DecoderFilters::deserialise), and the
// filters must be of the key's order and rate: a stale, corrupt or hostile
// file is ignored with one note, designed again and rewritten. Filters read
// back are the bytes designed.
//
// Threads: any. Two callers asking for one design at once design it once
// (the second waits). A design that fails (an order the set cannot carry)
// is not remembered.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"
#include "earshot/audio/hrtf_disk_cache.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::ambisonics {

class DecoderCache {
 public:
  /// Designs kept alive with no user (the ones used last).
  static constexpr std::size_t kKeep = 4;
  /// .ambi files the directory keeps (the most recently used).
  static constexpr std::size_t kMaxFiles = 16;
  /// Largest file read (an order-7 design at 192 kHz is well under it).
  static constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 26;
  static constexpr std::uint32_t kFormatVersion = 1;
  static constexpr std::size_t kHeaderBytes = 64;

  /// With the disk directory the environment names.
  DecoderCache();
  /// With the disk cache in `disk_dir` (nullopt: none); notes as HrtfDiskCache's.
  explicit DecoderCache(std::optional<std::filesystem::path> disk_dir, audio::HrtfDiskCache::Notes notes = {});
  DecoderCache(const DecoderCache&) = delete;
  DecoderCache& operator=(const DecoderCache&) = delete;

  /// The filters of `set` (read from the SOFA file `sofa`, at the set's
  /// rate; `parametric_radius_m` as the set was prepared) for `order` and
  /// `design`. Throws std::invalid_argument as design_binaural_decoder does.
  [[nodiscard]] std::shared_ptr<const DecoderFilters> get(const std::filesystem::path& sofa, const hrtf::HrtfSet& set,
                                                          std::optional<double> parametric_radius_m, int order,
                                                          const DecoderDesign& design = {});

  /// Filters made for callers (not found in memory): designed or read from disk.
  [[nodiscard]] std::uint64_t builds() const;
  /// Of those, the ones read from disk.
  [[nodiscard]] std::uint64_t disk_loads() const;
  [[nodiscard]] const std::optional<std::filesystem::path>& directory() const { return dir_; }
  /// Forgets everything in memory (users keep what they hold).
  void clear();

  /// The process-wide cache.
  [[nodiscard]] static DecoderCache& shared();

  // ---- the file (public for the tests and the fuzz target) ----

  /// What a file holds: one design of one set's bytes.
  struct Key {
    std::array<std::uint8_t, 16> sofa_hash{};
    double rate = 0.0;
    int order = 0;
    double radius = -1.0;  ///< -1: the set's measured delays
    std::string design;    ///< design_key()
    [[nodiscard]] std::array<std::uint8_t, 16> digest() const;
  };
  /// The file that holds `key` (needs a directory).
  [[nodiscard]] std::filesystem::path file_for(const Key& key) const;
  [[nodiscard]] static std::vector<std::uint8_t> serialize(const Key& key, const DecoderFilters& filters);
  /// Throws std::runtime_error or std::invalid_argument saying what does
  /// not check out. `verify_checksum` false reads past a wrong checksum (the
  /// fuzz target: a hostile file can carry a right one).
  [[nodiscard]] static DecoderFilters parse(std::span<const std::uint8_t> bytes, const Key& expected,
                                            bool verify_checksum = true);
  /// `key`'s filters from its file, or nullopt (none, or noted and ignored).
  [[nodiscard]] std::optional<DecoderFilters> load(const Key& key) const;
  /// Writes `filters` as `key`'s file (atomically); never throws.
  void store(const Key& key, const DecoderFilters& filters);

 private:
  struct MemoryKey {
    std::string path;
    std::uintmax_t size = 0;
    std::int64_t mtime = 0;
    double rate = 0.0;
    int order = 0;
    double radius = -1.0;
    std::string design;
    auto operator<=>(const MemoryKey&) const = default;
  };
  struct Entry {
    std::shared_future<std::shared_ptr<const DecoderFilters>> ready;  // while it is being made
    std::weak_ptr<const DecoderFilters> filters;
  };

  std::shared_ptr<const DecoderFilters> build(const std::filesystem::path& sofa, const hrtf::HrtfSet& set,
                                              std::optional<double> radius, int order, const DecoderDesign& design,
                                              bool& from_disk);
  void keep(const std::shared_ptr<const DecoderFilters>& f);
  void note(const std::string& line) const;

  mutable std::mutex mutex_;
  std::map<MemoryKey, Entry> entries_;
  std::deque<std::shared_ptr<const DecoderFilters>> kept_;
  std::uint64_t builds_ = 0, disk_loads_ = 0;
  std::optional<std::filesystem::path> dir_;
  audio::HrtfDiskCache::Notes notes_;
  std::atomic<bool> write_failed_{false};
};

}  // namespace earshot::ambisonics
