#include "earshot/audio/hrtf_cache.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <system_error>

namespace earshot::audio {
namespace {

PreparedHrtf prepare(const std::filesystem::path& sofa, double rate, std::size_t block,
                     std::optional<double> radius) {
  auto set = hrtf::HrtfSet::load(sofa, rate);
  if (radius) set.set_parametric_itd(*radius);
  PreparedHrtf p;
  p.set = std::make_shared<const hrtf::HrtfSet>(std::move(set));
  p.spectra = std::make_shared<const HrtfSpectra>(*p.set, block);
  return p;
}

}  // namespace

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
    return prepare(sofa, sample_rate, block, parametric_radius_m);
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
  try {
    p = prepare(sofa, sample_rate, block, parametric_radius_m);
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

void HrtfCache::clear() {
  std::lock_guard lock(mutex_);
  std::erase_if(entries_, [](const auto& e) { return !e.second.ready.valid(); });
  kept_.clear();
}

}  // namespace earshot::audio
