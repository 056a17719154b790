#include "earshot/audio/ambisonics/decoder_cache.hpp"

#include "earshot/audio/cache_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace earshot::ambisonics {
namespace fs = std::filesystem;
namespace {

constexpr std::array<std::uint8_t, 8> kCacheMagic{'E', 'S', 'A', 'M', 'B', 'D', '\r', '\n'};
constexpr std::uint32_t kCacheByteOrder = 0x01020304u;

struct CacheHeader {
  std::array<std::uint8_t, 8> magic = kCacheMagic;
  std::uint32_t version = DecoderCache::kFormatVersion;
  std::uint32_t byte_order = kCacheByteOrder;
  std::array<std::uint8_t, 16> key{};
  std::uint64_t payload_bytes = 0;
  std::array<std::uint8_t, 16> checksum{};
};
static_assert(sizeof(CacheHeader) == DecoderCache::kHeaderBytes - 8 && std::is_trivially_copyable_v<CacheHeader>);
// (8 bytes of the 64 reserved, zero.)

using audio::cache_files::errno_text;
using audio::cache_files::hash128;
using audio::cache_files::hex;

[[noreturn]] void cache_corrupt(const std::string& what) { throw std::runtime_error(what); }

}  // namespace

std::array<std::uint8_t, 16> DecoderCache::Key::digest() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "decoder-cache v%u rate=%.17g order=%d radius=%.17g sofa=", unsigned(kFormatVersion), rate,
                order, radius);
  const std::string text = std::string(buf) + hex(sofa_hash) + " design=" + design;
  return hash128(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

DecoderCache::DecoderCache() : DecoderCache(audio::HrtfDiskCache::directory_from_environment()) {}

DecoderCache::DecoderCache(std::optional<fs::path> disk_dir, audio::HrtfDiskCache::Notes notes)
    : dir_(std::move(disk_dir)), notes_(std::move(notes)) {
  if (!notes_) notes_ = [](const std::string& line) { std::fprintf(stderr, "earshot: %s\n", line.c_str()); };
}

DecoderCache& DecoderCache::shared() {
  static DecoderCache cache;
  return cache;
}

void DecoderCache::note(const std::string& line) const { notes_(line); }

// ---- the file ----

fs::path DecoderCache::file_for(const Key& key) const { return dir_.value() / (hex(key.digest()) + ".ambi"); }

std::vector<std::uint8_t> DecoderCache::serialize(const Key& key, const DecoderFilters& filters) {
  const std::vector<std::uint8_t> payload = filters.serialise();
  CacheHeader h;
  h.key = key.digest();
  h.payload_bytes = payload.size();
  h.checksum = hash128(payload);
  std::vector<std::uint8_t> out(kHeaderBytes + payload.size(), 0);
  std::memcpy(out.data(), &h, sizeof h);
  std::memcpy(out.data() + kHeaderBytes, payload.data(), payload.size());
  return out;
}

DecoderFilters DecoderCache::parse(std::span<const std::uint8_t> bytes, const Key& expected, bool verify_checksum) {
  if (bytes.size() < kHeaderBytes) cache_corrupt("shorter than its header (" + std::to_string(bytes.size()) + " bytes)");
  CacheHeader h;
  std::memcpy(&h, bytes.data(), sizeof h);
  if (h.magic != kCacheMagic) cache_corrupt("not an Earshot decoder cache file (magic)");
  if (h.byte_order != kCacheByteOrder) cache_corrupt("written on a machine of another byte order");
  if (h.version != kFormatVersion) cache_corrupt("written by another version of Earshot (format " + std::to_string(h.version) + ")");
  if (h.key != expected.digest()) cache_corrupt("holds another set, rate, order or design than its name says");
  const std::span<const std::uint8_t> payload = bytes.subspan(kHeaderBytes);
  if (h.payload_bytes != payload.size())
    cache_corrupt("payload of " + std::to_string(payload.size()) + " bytes, header says " + std::to_string(h.payload_bytes));
  if (verify_checksum && hash128(payload) != h.checksum) cache_corrupt("checksum does not match (corrupt)");
  DecoderFilters f = DecoderFilters::deserialise(payload);  // checks every size and tap
  if (f.order != expected.order || !(f.sample_rate == expected.rate))
    cache_corrupt("holds order " + std::to_string(f.order) + " at " + std::to_string(f.sample_rate) + " Hz, not its key's");
  return f;
}

std::optional<DecoderFilters> DecoderCache::load(const Key& key) const {
  if (!dir_) return std::nullopt;
  const fs::path file = file_for(key);
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno != ENOENT && errno != ENOTDIR)
      note("cannot read the decoder cache file " + file.string() + " (" + errno_text(errno) + "): designing it again");
    return std::nullopt;
  }
  std::string problem;
  std::vector<std::uint8_t> bytes;
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    problem = errno_text(errno);
  } else if (!S_ISREG(st.st_mode)) {
    problem = "not a regular file";
  } else if (static_cast<std::uintmax_t>(st.st_size) > kMaxFileBytes) {
    problem = "larger than " + std::to_string(kMaxFileBytes) + " bytes";
  } else {
    bytes.resize(static_cast<std::size_t>(st.st_size));
    std::size_t got = 0;
    while (got < bytes.size()) {
      const ssize_t k = ::read(fd, bytes.data() + got, bytes.size() - got);
      if (k < 0 && errno == EINTR) continue;
      if (k <= 0) break;
      got += static_cast<std::size_t>(k);
    }
    bytes.resize(got);
  }
  ::close(fd);
  if (problem.empty()) {
    try {
      DecoderFilters f = parse(bytes, key);
      std::error_code ec;
      fs::last_write_time(file, fs::file_time_type::clock::now(), ec);  // used: kept longest by prune()
      return f;
    } catch (const std::exception& e) {
      problem = e.what();
    }
  }
  note("ignored the decoder cache file " + file.string() + ": " + problem + "; designing it again");
  return std::nullopt;
}

void DecoderCache::store(const Key& key, const DecoderFilters& filters) {
  if (!dir_) return;
  std::string problem;
  try {
    const std::vector<std::uint8_t> bytes = serialize(key, filters);
    const std::span<const std::uint8_t> pieces[] = {bytes};
    problem = audio::cache_files::write_whole(file_for(key), pieces);
  } catch (const std::exception& e) {
    problem = e.what();
  }
  if (problem.empty()) {
    audio::cache_files::prune(*dir_, ".ambi", kMaxFiles);
    return;
  }
  if (!write_failed_.exchange(true))
    note("cannot write the decoder cache in " + dir_->string() + " (" + problem +
         "): decoders are designed in every process (EARSHOT_CACHE_DIR names another directory, =off turns the cache "
         "off)");
}

// ---- memory ----

std::shared_ptr<const DecoderFilters> DecoderCache::build(const fs::path& sofa, const hrtf::HrtfSet& set,
                                                          std::optional<double> radius, int order,
                                                          const DecoderDesign& design, bool& from_disk) {
  from_disk = false;
  std::optional<Key> key;
  if (dir_)
    if (const auto k = audio::HrtfDiskCache::key_of(sofa, set.sample_rate(), 0))
      key = Key{k->sofa_hash, set.sample_rate(), order, radius.value_or(-1.0), design_key(design, order)};
  if (key)
    if (std::optional<DecoderFilters> f = load(*key)) {
      from_disk = true;
      return std::make_shared<const DecoderFilters>(std::move(*f));
    }
  DecoderFilters f = design_binaural_decoder(set, order, design);
  if (key) store(*key, f);
  return std::make_shared<const DecoderFilters>(std::move(f));
}

std::shared_ptr<const DecoderFilters> DecoderCache::get(const fs::path& sofa, const hrtf::HrtfSet& set,
                                                        std::optional<double> radius, int order,
                                                        const DecoderDesign& design) {
  MemoryKey key;
  try {
    key.path = fs::canonical(sofa).string();
    key.size = fs::file_size(key.path);
    key.mtime = std::chrono::duration_cast<std::chrono::nanoseconds>(fs::last_write_time(key.path).time_since_epoch())
                    .count();
  } catch (const fs::filesystem_error&) {
    // Gone since the set was read: design from the set in hand, keep nothing.
    bool from_disk = false;
    return build(sofa, set, radius, order, design, from_disk);
  }
  key.rate = set.sample_rate();
  key.order = order;
  key.radius = radius.value_or(-1.0);
  key.design = design_key(design, order);

  std::promise<std::shared_ptr<const DecoderFilters>> promise;
  {
    std::unique_lock lock(mutex_);
    std::erase_if(entries_, [](const auto& e) { return !e.second.ready.valid() && e.second.filters.expired(); });
    if (auto it = entries_.find(key); it != entries_.end()) {
      if (it->second.ready.valid()) {  // another thread is making it
        const auto ready = it->second.ready;
        lock.unlock();
        auto f = ready.get();  // rethrows its error
        std::lock_guard again(mutex_);
        keep(f);
        return f;
      }
      if (auto f = it->second.filters.lock()) {
        keep(f);
        return f;
      }
    }
    entries_[key] = Entry{promise.get_future().share(), {}};
  }
  std::shared_ptr<const DecoderFilters> f;
  bool from_disk = false;
  try {
    f = build(sofa, set, radius, order, design, from_disk);
  } catch (...) {
    {
      std::lock_guard lock(mutex_);
      entries_.erase(key);
    }
    promise.set_exception(std::current_exception());
    throw;
  }
  {
    std::lock_guard lock(mutex_);
    Entry& e = entries_[key];
    e.ready = {};
    e.filters = f;
    ++builds_;
    if (from_disk) ++disk_loads_;
    keep(f);
  }
  promise.set_value(f);
  return f;
}

void DecoderCache::keep(const std::shared_ptr<const DecoderFilters>& f) {
  std::erase(kept_, f);
  kept_.push_front(f);
  if (kept_.size() > kKeep) kept_.pop_back();
}

std::uint64_t DecoderCache::builds() const {
  std::lock_guard lock(mutex_);
  return builds_;
}

std::uint64_t DecoderCache::disk_loads() const {
  std::lock_guard lock(mutex_);
  return disk_loads_;
}

void DecoderCache::clear() {
  std::lock_guard lock(mutex_);
  std::erase_if(entries_, [](const auto& e) { return !e.second.ready.valid(); });
  kept_.clear();
}

}  // namespace earshot::ambisonics
