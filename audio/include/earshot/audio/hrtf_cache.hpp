// HrtfCache: a measured HRTF set's prepared data, built once per process,
// file, rate and block size, and shared read-only by every renderer that
// uses it (every world, every plugin instance).
//
// Preparing a set (reading the SOFA file, resampling, the onset split, the
// triangulation, the filter spectra) costs hundreds of milliseconds; a world
// made after the first with the same file takes the prepared data from here
// and starts in milliseconds. What is shared is immutable once published, so
// any number of threads may render with it.
//
// Identity of a file: its canonical path, size and modification time, so a
// file replaced on disk is read again. The cache keeps the `kKeep` sets used
// last alive even while no world holds them (a host that closes its last
// world and opens a new one pays nothing), and forgets the others when their
// last user lets go.
//
// Threads: every call may come from any thread. Two callers asking for the
// same data at once prepare it once: the second waits for the first. A file
// that fails to load is not remembered: the next call reads it again (and
// throws the same InputError while it is still bad).
//
// Behind the memory, a disk cache (hrtf_disk_cache.hpp): a set not in memory
// is read from there when a valid file holds it, else prepared from the SOFA
// file and written there for the next process.
//
// The process-wide instance (`shared()`) is the one piece of global state in
// the libraries, and only a cache: results are the same with or without it.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>

#include "earshot/audio/hrtf_disk_cache.hpp"
#include "earshot/audio/hrtf_spectra.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::audio {

/// A set and its spectra for one block size: what a Renderer needs.
struct PreparedHrtf {
  std::shared_ptr<const hrtf::HrtfSet> set;
  std::shared_ptr<const HrtfSpectra> spectra;
};

class HrtfCache {
 public:
  /// How many of the most recently used sets stay alive with no user.
  static constexpr std::size_t kKeep = 4;

  /// With the disk cache the environment names
  /// (HrtfDiskCache::directory_from_environment()).
  HrtfCache();
  /// With the disk cache in `disk_dir` (nullopt: none); `notes` as
  /// HrtfDiskCache's.
  explicit HrtfCache(std::optional<std::filesystem::path> disk_dir, HrtfDiskCache::Notes notes = {});
  HrtfCache(const HrtfCache&) = delete;
  HrtfCache& operator=(const HrtfCache&) = delete;

  /// The set in `sofa` at `sample_rate` (with Woodworth delays for
  /// `parametric_radius_m` when given) and its spectra for `block`.
  /// Throws earshot::InputError as HrtfSet::load does.
  [[nodiscard]] PreparedHrtf get(const std::filesystem::path& sofa, double sample_rate, std::size_t block,
                                 std::optional<double> parametric_radius_m = std::nullopt);

  /// Sets built for callers so far (not found in memory): prepared from
  /// their files or read from the disk cache. For tests and benchmarks.
  [[nodiscard]] std::uint64_t preparations() const;
  /// Of those, the ones read from the disk cache.
  [[nodiscard]] std::uint64_t disk_loads() const;
  [[nodiscard]] const HrtfDiskCache& disk() const { return disk_; }

  /// Forgets everything (users keep what they hold).
  void clear();

  /// The process-wide cache.
  [[nodiscard]] static HrtfCache& shared();

 private:
  struct Key {
    std::string path;  // canonical
    std::uintmax_t size = 0;
    std::int64_t mtime = 0;
    double rate = 0.0;
    std::size_t block = 0;
    double radius = -1.0;  // -1: measured delays
    auto operator<=>(const Key&) const = default;
  };
  struct Entry {
    std::shared_future<PreparedHrtf> ready;  // while it is being prepared
    std::weak_ptr<const hrtf::HrtfSet> set;
    std::weak_ptr<const HrtfSpectra> spectra;
  };

  [[nodiscard]] static Key key_of(const std::filesystem::path& sofa, double rate, std::size_t block,
                                  std::optional<double> radius);
  void keep(const PreparedHrtf& p);
  /// From the disk cache, else prepared (and written there); `from_disk`
  /// says which.
  PreparedHrtf build(const std::filesystem::path& sofa, double rate, std::size_t block, std::optional<double> radius,
                     bool& from_disk);

  mutable std::mutex mutex_;
  std::map<Key, Entry> entries_;
  std::deque<PreparedHrtf> kept_;  // the last kKeep used, newest first
  std::uint64_t preparations_ = 0;
  std::uint64_t disk_loads_ = 0;
  HrtfDiskCache disk_;  // its calls are made outside mutex_: it takes care of itself
};

}  // namespace earshot::audio
