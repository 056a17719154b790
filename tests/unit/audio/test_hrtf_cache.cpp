// HrtfCache: one preparation per file, rate, block and ITD model; shared
// read-only; a bad file is an error every time and is never remembered; a
// file replaced on disk is read again; callers racing for the same set
// prepare it once (these run under TSan too).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "earshot/audio/hrtf_cache.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/errors.hpp"
#include "../scratch_path.hpp"

using earshot::audio::HrtfCache;
using earshot::audio::PreparedHrtf;
using earshot::hrtf::HrtfSet;
namespace fs = std::filesystem;

namespace {

/// A private copy of the default set in a fresh directory.
fs::path copy_of_default(const std::string& name) {
  const fs::path dir = earshot::test::scratch_path("hrtf_cache_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path p = dir / "set.sofa";
  fs::copy_file(HrtfSet::kDefaultPath, p);
  return p;
}

}  // namespace

TEST(HrtfCache, SameFileRateAndBlockArePreparedOnceAndShared) {
  HrtfCache cache;
  const PreparedHrtf a = cache.get(HrtfSet::kDefaultPath, 48000.0, 128);
  const PreparedHrtf b = cache.get(HrtfSet::kDefaultPath, 48000.0, 128);
  EXPECT_EQ(cache.preparations(), 1u);
  EXPECT_EQ(a.set, b.set);
  EXPECT_EQ(a.spectra, b.spectra);
  EXPECT_EQ(a.spectra->block(), 128u);
  EXPECT_DOUBLE_EQ(a.set->sample_rate(), 48000.0);

  // Another block, rate or ITD model is another preparation.
  const PreparedHrtf c = cache.get(HrtfSet::kDefaultPath, 48000.0, 256);
  EXPECT_EQ(c.spectra->block(), 256u);
  const PreparedHrtf d = cache.get(HrtfSet::kDefaultPath, 44100.0, 128);
  EXPECT_DOUBLE_EQ(d.set->sample_rate(), 44100.0);
  const PreparedHrtf e = cache.get(HrtfSet::kDefaultPath, 48000.0, 128, 0.09);
  EXPECT_NE(e.set, a.set);
  EXPECT_EQ(cache.preparations(), 4u);
}

TEST(HrtfCache, RecentSetsOutliveTheirUsers) {
  HrtfCache cache;
  { const PreparedHrtf a = cache.get(HrtfSet::kDefaultPath, 48000.0, 64); }
  const PreparedHrtf again = cache.get(HrtfSet::kDefaultPath, 48000.0, 64);
  EXPECT_EQ(cache.preparations(), 1u) << "a host that closes its last world and opens another pays again";
}

TEST(HrtfCache, UnusedSetsBeyondTheKeptOnesAreFreed) {
  HrtfCache cache;
  std::weak_ptr<const HrtfSet> first;
  { first = cache.get(HrtfSet::kDefaultPath, 48000.0, 32).set; }
  for (std::size_t i = 0; i < HrtfCache::kKeep; ++i)
    (void)cache.get(HrtfSet::kDefaultPath, 48000.0, 64u << i);
  EXPECT_TRUE(first.expired()) << "the cache keeps only the sets used last";
  (void)cache.get(HrtfSet::kDefaultPath, 48000.0, 32);
  EXPECT_EQ(cache.preparations(), HrtfCache::kKeep + 2);
}

TEST(HrtfCache, ABadFileIsAnErrorEveryTimeAndNotRemembered) {
  HrtfCache cache;
  const fs::path dir = earshot::test::scratch_path("hrtf_cache_bad");
  fs::create_directories(dir);
  const fs::path bad = dir / "not_sofa.sofa";
  std::ofstream(bad) << "this is not a SOFA file\n";
  for (int i = 0; i < 2; ++i) {
    try {
      (void)cache.get(bad, 48000.0, 128);
      FAIL() << "a bad file loaded";
    } catch (const earshot::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("not_sofa.sofa"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW((void)cache.get(dir / "missing.sofa", 48000.0, 128), earshot::InputError);
  EXPECT_EQ(cache.preparations(), 0u);
  // Fixed on disk, it loads.
  fs::copy_file(HrtfSet::kDefaultPath, bad, fs::copy_options::overwrite_existing);
  EXPECT_NO_THROW((void)cache.get(bad, 48000.0, 128));
  EXPECT_EQ(cache.preparations(), 1u);
}

TEST(HrtfCache, AFileReplacedOnDiskIsReadAgain) {
  HrtfCache cache;
  const fs::path p = copy_of_default("replaced");
  const PreparedHrtf a = cache.get(p, 48000.0, 128);
  fs::last_write_time(p, fs::last_write_time(p) + std::chrono::seconds(5));
  const PreparedHrtf b = cache.get(p, 48000.0, 128);
  EXPECT_NE(a.set, b.set);
  EXPECT_EQ(cache.preparations(), 2u);
  // The same file by another path is the same file.
  const PreparedHrtf c = cache.get(p.parent_path() / "." / p.filename(), 48000.0, 128);
  EXPECT_EQ(c.set, b.set);
}

TEST(HrtfCache, ThreadsAskingAtOnceShareOnePreparation) {
  HrtfCache cache;
  constexpr int kThreads = 8;
  std::vector<PreparedHrtf> got(kThreads);
  std::vector<std::thread> threads;
  for (int i = 0; i < kThreads; ++i)
    threads.emplace_back([&, i] { got[static_cast<std::size_t>(i)] = cache.get(HrtfSet::kDefaultPath, 48000.0, 128); });
  for (auto& t : threads) t.join();
  EXPECT_EQ(cache.preparations(), 1u);
  for (const auto& g : got) {
    EXPECT_EQ(g.set, got[0].set);
    EXPECT_EQ(g.spectra, got[0].spectra);
  }
}

TEST(HrtfCache, ARendererRefusesSpectraForAnotherBlock) {
  HrtfCache cache;
  earshot::audio::RendererConfig cfg;
  cfg.block = 256;
  EXPECT_THROW(earshot::audio::Renderer(cache.get(HrtfSet::kDefaultPath, 48000.0, 128), cfg), std::invalid_argument);
  cfg.block = 128;
  EXPECT_NO_THROW(earshot::audio::Renderer(cache.get(HrtfSet::kDefaultPath, 48000.0, 128), cfg));
}
