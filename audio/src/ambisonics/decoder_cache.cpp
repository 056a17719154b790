#include "earshot/audio/ambisonics/decoder_cache.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#define XXH_INLINE_ALL  // header only: no library to link into the plugin
#include <xxhash.h>

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

std::array<std::uint8_t, 16> cache_hash128(std::span<const std::uint8_t> b) {
  XXH128_canonical_t c;
  XXH128_canonicalFromHash(&c, XXH3_128bits(b.data(), b.size()));
  std::array<std::uint8_t, 16> out{};
  std::memcpy(out.data(), c.digest, 16);
  return out;
}

std::string cache_hex(std::span<const std::uint8_t> b) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (const std::uint8_t x : b) s += {kDigits[x >> 4], kDigits[x & 15]};
  return s;
}

/// A file this cache wrote: `<32 hex>.ambi` or its `<32 hex>.ambi.<pid>.<n>.tmp`.
bool cache_file_ours(const fs::path& p) {
  const std::string name = p.filename().string();
  if (name.size() < 37 || name.compare(32, 5, ".ambi") != 0) return false;
  if (!std::all_of(name.begin(), name.begin() + 32, [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); }))
    return false;
  return name.size() == 37 || (name.size() > 41 && name.compare(name.size() - 4, 4, ".tmp") == 0);
}

std::string cache_errno_text(int e) { return std::error_code(e, std::generic_category()).message(); }

[[noreturn]] void cache_corrupt(const std::string& what) { throw std::runtime_error(what); }

}  // namespace

std::array<std::uint8_t, 16> DecoderCache::Key::digest() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "decoder-cache v%u rate=%.17g order=%d radius=%.17g sofa=", unsigned(kFormatVersion), rate,
                order, radius);
  const std::string text = std::string(buf) + cache_hex(sofa_hash) + " design=" + design;
  return cache_hash128(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
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

fs::path DecoderCache::file_for(const Key& key) const { return dir_.value() / (cache_hex(key.digest()) + ".ambi"); }

std::vector<std::uint8_t> DecoderCache::serialize(const Key& key, const DecoderFilters& filters) {
  const std::vector<std::uint8_t> payload = filters.serialise();
  CacheHeader h;
  h.key = key.digest();
  h.payload_bytes = payload.size();
  h.checksum = cache_hash128(payload);
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
  if (verify_checksum && cache_hash128(payload) != h.checksum) cache_corrupt("checksum does not match (corrupt)");
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
      note("cannot read the decoder cache file " + file.string() + " (" + cache_errno_text(errno) + "): designing it again");
    return std::nullopt;
  }
  std::string problem;
  std::vector<std::uint8_t> bytes;
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    problem = cache_errno_text(errno);
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
  static std::atomic<unsigned> serial{0};
  std::string problem;
  fs::path tmp;
  try {
    const std::vector<std::uint8_t> bytes = serialize(key, filters);
    std::error_code ec;
    fs::create_directories(*dir_, ec);
    const fs::path file = file_for(key);
    tmp = file;
    // Appended piece by piece: g++ 12 warns of an overlapping copy in the
    // inlined '"." + std::to_string(...)' (GCC bug 105651).
    tmp += ".";
    tmp += std::to_string(::getpid());
    tmp += ".";
    tmp += std::to_string(serial++);
    tmp += ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
      problem = cache_errno_text(errno);
    } else {
      const std::uint8_t* p = bytes.data();
      std::size_t n = bytes.size();
      while (n > 0 && problem.empty()) {
        const ssize_t k = ::write(fd, p, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) problem = cache_errno_text(k < 0 ? errno : ENOSPC);
        if (k > 0) p += k, n -= static_cast<std::size_t>(k);
      }
      if (::close(fd) != 0 && problem.empty()) problem = cache_errno_text(errno);
      if (problem.empty() && ::rename(tmp.c_str(), file.c_str()) != 0) problem = cache_errno_text(errno);
    }
  } catch (const std::exception& e) {
    problem = e.what();
  }
  if (problem.empty()) {
    prune();
    return;
  }
  if (!tmp.empty()) {
    std::error_code ec;
    fs::remove(tmp, ec);
  }
  if (!write_failed_.exchange(true))
    note("cannot write the decoder cache in " + dir_->string() + " (" + problem +
         "): decoders are designed in every process (EARSHOT_CACHE_DIR names another directory, =off turns the cache "
         "off)");
}

void DecoderCache::prune() const {
  std::error_code ec;
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  const auto stale_tmp = fs::file_time_type::clock::now() - std::chrono::hours(1);
  for (fs::directory_iterator it(*dir_, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    if (!cache_file_ours(p)) continue;
    std::error_code e2;
    const auto t = fs::last_write_time(p, e2);
    if (e2) continue;
    if (p.extension() == ".ambi") files.emplace_back(t, p);
    if (p.extension() == ".tmp" && t < stale_tmp) fs::remove(p, e2);  // left by a process that died mid-write
  }
  if (files.size() <= kMaxFiles) return;
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = kMaxFiles; i < files.size(); ++i) fs::remove(files[i].second, ec);
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
