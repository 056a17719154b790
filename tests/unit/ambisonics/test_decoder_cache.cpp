// DecoderCache: one design per set, rate, order and design in memory; on
// disk between processes (the same bytes back); a damaged, stale or
// hostile file noted, ignored, designed again and rewritten.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "earshot/audio/ambisonics/decoder_cache.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace fs = std::filesystem;
using earshot::ambisonics::DecoderCache;
using earshot::ambisonics::DecoderDesign;
using earshot::ambisonics::DecoderFilters;
using earshot::ambisonics::DecoderMethod;

namespace {

const earshot::hrtf::HrtfSet& cache_test_set() {
  static const earshot::hrtf::HrtfSet set = earshot::hrtf::HrtfSet::load_default(48000.0);
  return set;
}

const fs::path kSofa = earshot::hrtf::HrtfSet::kDefaultPath;

/// A directory of its own, removed at the end.
struct CacheDir {
  fs::path dir = fs::temp_directory_path() / ("earshot-decoder-cache-" + std::to_string(::getpid()) + "-" +
                                              ::testing::UnitTest::GetInstance()->current_test_info()->name());
  CacheDir() { fs::remove_all(dir); }
  ~CacheDir() { fs::remove_all(dir); }
  [[nodiscard]] std::vector<fs::path> files(const std::string& ext) const {
    std::vector<fs::path> out;
    if (fs::exists(dir))
      for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ext) out.push_back(e.path());
    return out;
  }
};

std::vector<std::uint8_t> slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}
void spill(const fs::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

}  // namespace

TEST(DecoderCache, OneDesignPerKeyInMemory) {
  DecoderCache cache(std::nullopt);
  const auto a = cache.get(kSofa, cache_test_set(), std::nullopt, 1);
  const auto b = cache.get(kSofa, cache_test_set(), std::nullopt, 1);
  EXPECT_EQ(a.get(), b.get());
  EXPECT_EQ(cache.builds(), 1u);
  DecoderDesign ls;
  ls.method = DecoderMethod::ls;
  const auto c = cache.get(kSofa, cache_test_set(), std::nullopt, 1, ls);
  EXPECT_NE(a.get(), c.get());
  EXPECT_NE(a->taps, c->taps);
  EXPECT_EQ(cache.builds(), 2u);
  EXPECT_EQ(cache.disk_loads(), 0u);
  EXPECT_THROW((void)cache.get(kSofa, cache_test_set(), std::nullopt, 0), std::invalid_argument);
}

TEST(DecoderCache, TheDiskGivesBackTheBytesDesigned) {
  CacheDir d;
  std::vector<std::string> notes;
  std::shared_ptr<const DecoderFilters> designed;
  {
    DecoderCache first(d.dir, [&](const std::string& n) { notes.push_back(n); });
    designed = first.get(kSofa, cache_test_set(), std::nullopt, 2);
    EXPECT_EQ(first.disk_loads(), 0u);
  }
  ASSERT_EQ(d.files(".ambi").size(), 1u);
  DecoderCache second(d.dir, [&](const std::string& n) { notes.push_back(n); });
  const auto read = second.get(kSofa, cache_test_set(), std::nullopt, 2);
  EXPECT_EQ(second.builds(), 1u);
  EXPECT_EQ(second.disk_loads(), 1u);
  EXPECT_EQ(read->serialise(), designed->serialise());
  EXPECT_TRUE(notes.empty());
  // Another radius (a parametric ITD) is another design, in another file.
  (void)second.get(kSofa, cache_test_set(), 0.0875, 2);
  EXPECT_EQ(d.files(".ambi").size(), 2u);
}

TEST(DecoderCache, ADamagedFileIsNotedIgnoredAndRewritten) {
  CacheDir d;
  std::vector<std::string> notes;
  const auto note = [&](const std::string& n) { notes.push_back(n); };
  const std::vector<std::uint8_t> good = [&] {
    DecoderCache c(d.dir, note);
    (void)c.get(kSofa, cache_test_set(), std::nullopt, 1);
    return slurp(d.files(".ambi").at(0));
  }();
  const fs::path file = d.files(".ambi").at(0);
  const auto damaged = [&](std::vector<std::uint8_t> bytes, const char* what) {
    spill(file, bytes);
    notes.clear();
    DecoderCache c(d.dir, note);
    const auto f = c.get(kSofa, cache_test_set(), std::nullopt, 1);
    EXPECT_EQ(c.disk_loads(), 0u) << what;
    ASSERT_EQ(notes.size(), 1u) << what;
    EXPECT_NE(notes[0].find(file.string()), std::string::npos) << notes[0];
    EXPECT_EQ(slurp(file), good) << what << ": written again";
  };
  auto flipped = good;
  flipped[flipped.size() / 2] ^= 0x40;
  damaged(flipped, "a flipped bit");
  damaged(std::vector<std::uint8_t>(good.begin(), good.begin() + 100), "truncated");
  damaged({}, "empty");
  auto magic = good;
  magic[0] = 'X';
  damaged(magic, "magic");
}

TEST(DecoderCache, ParseRefusesAnotherKeyAndSizesThatDoNotFit) {
  const DecoderFilters f = [] {
    DecoderCache c(std::nullopt);
    return *c.get(kSofa, cache_test_set(), std::nullopt, 1);
  }();
  DecoderCache::Key key{{1, 2, 3}, 48000.0, 1, -1.0, "k"};
  const auto bytes = DecoderCache::serialize(key, f);
  EXPECT_EQ(DecoderCache::parse(bytes, key).taps, f.taps);
  DecoderCache::Key other = key;
  other.order = 2;
  EXPECT_THROW((void)DecoderCache::parse(bytes, other), std::runtime_error);
  other = key;
  other.design = "another";
  EXPECT_THROW((void)DecoderCache::parse(bytes, other), std::runtime_error);
  // A right checksum over a lying payload: the filters' own checks refuse it.
  auto lying = bytes;
  lying[DecoderCache::kHeaderBytes + 12] = 7;  // the order inside the payload
  EXPECT_ANY_THROW((void)DecoderCache::parse(lying, key, false));
  auto longer = bytes;
  longer.push_back(0);
  EXPECT_THROW((void)DecoderCache::parse(longer, key), std::runtime_error);
}
