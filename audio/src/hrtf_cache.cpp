#include "earshot/audio/hrtf_cache.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <system_error>

namespace earshot::audio {
namespace {

PreparedHrtf share(hrtf::HrtfSet set, HrtfSpectra spectra, std::optional<double> radius) {
  if (radius) set.set_parametric_itd(*radius);
  return {std::make_shared<const hrtf::HrtfSet>(std::move(set)), std::make_shared<const HrtfSpectra>(std::move(spectra))};
}

}  // namespace

HrtfCache::HrtfCache() : disk_(HrtfDiskCache::directory_from_environment()) {}

HrtfCache::HrtfCache(std::optional<std::filesystem::path> disk_dir, HrtfDiskCache::Notes notes)
    : disk_(std::move(disk_dir), std::move(notes)) {}

PreparedHrtf HrtfCache::build(const std::filesystem::path& sofa, double rate, std::size_t block,
                              std::optional<double> radius, bool& from_disk) {
  from_disk = false;
  std::optional<HrtfDiskCache::Key> key;
  if (disk_.directory()) key = HrtfDiskCache::key_of(sofa, rate, block);
  if (key)
    if (std::optional<HrtfDiskCache::Loaded> l = disk_.load(*key)) {
      from_disk = true;
      return share(std::move(l->set), std::move(l->spectra), radius);
    }
  hrtf::HrtfSet set = hrtf::HrtfSet::load(sofa, rate);
  HrtfSpectra spectra(set, block);
  // Written only if the file is still what was hashed (not replaced while
  // it was being read).
  if (key && HrtfDiskCache::key_of(sofa, rate, block) == key) disk_.store(*key, set, spectra);
  return share(std::move(set), std::move(spectra), radius);
}

HrtfCache& HrtfCache::shared() {
  static HrtfCache cache;
  return cache;
}

HrtfCache::Key HrtfCache::key_of(const std::filesystem::path& sofa, double rate, std::size_t block,
                                 std::optional<double> radius) {
  Key k;
  k.path = std::filesystem::canonical(sofa).string();
  k.size = std::filesystem::file_size(k.path);
  k.mtime = std::chrono::duration_cast<std::chrono::nanoseconds>(
                std::filesystem::last_write_time(k.path).time_since_epoch())
                .count();
  k.rate = rate;
  k.block = block;
  k.radius = radius ? *radius : -1.0;
  return k;
}

PreparedHrtf HrtfCache::get(const std::filesystem::path& sofa, double sample_rate, std::size_t block,
                            std::optional<double> parametric_radius_m) {
  Key key;
  try {
    key = key_of(sofa, sample_rate, block, parametric_radius_m);
  } catch (const std::filesystem::filesystem_error&) {
    // Missing or unreadable: HrtfSet::load says so, naming the file.
    bool from_disk = false;
    return build(sofa, sample_rate, block, parametric_radius_m, from_disk);
  }

  std::promise<PreparedHrtf> promise;
  {
    std::unique_lock lock(mutex_);
    std::erase_if(entries_, [](const auto& e) {
      return !e.second.ready.valid() && (e.second.set.expired() || e.second.spectra.expired());
    });
    if (auto it = entries_.find(key); it != entries_.end()) {
      if (it->second.ready.valid()) {  // another thread is preparing it
        const std::shared_future<PreparedHrtf> ready = it->second.ready;
        lock.unlock();
        PreparedHrtf p = ready.get();  // rethrows its InputError
        std::lock_guard again(mutex_);
        keep(p);
        return p;
      }
      PreparedHrtf p{it->second.set.lock(), it->second.spectra.lock()};
      if (p.set && p.spectra) {
        keep(p);
        return p;
      }
    }
    entries_[key] = Entry{promise.get_future().share(), {}, {}};
  }

  PreparedHrtf p;
  bool from_disk = false;
  try {
    p = build(sofa, sample_rate, block, parametric_radius_m, from_disk);
  } catch (...) {
    {
      std::lock_guard lock(mutex_);
      entries_.erase(key);  // a bad file is read again next time
    }
    promise.set_exception(std::current_exception());
    throw;
  }
  {
    std::lock_guard lock(mutex_);
    Entry& e = entries_[key];
    e.ready = {};
    e.set = p.set;
    e.spectra = p.spectra;
    ++preparations_;
    if (from_disk) ++disk_loads_;
    keep(p);
  }
  promise.set_value(p);
  return p;
}

void HrtfCache::keep(const PreparedHrtf& p) {
  std::erase_if(kept_, [&](const PreparedHrtf& k) { return k.set == p.set && k.spectra == p.spectra; });
  kept_.push_front(p);
  if (kept_.size() > kKeep) kept_.pop_back();
}

std::uint64_t HrtfCache::preparations() const {
  std::lock_guard lock(mutex_);
  return preparations_;
}

std::uint64_t HrtfCache::disk_loads() const {
  std::lock_guard lock(mutex_);
  return disk_loads_;
}

void HrtfCache::clear() {
  std::lock_guard lock(mutex_);
  std::erase_if(entries_, [](const auto& e) { return !e.second.ready.valid(); });
  kept_.clear();
}

}  // namespace earshot::audio
