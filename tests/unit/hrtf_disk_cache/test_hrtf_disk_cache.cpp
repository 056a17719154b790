// HrtfDiskCache behind HrtfCache: a set prepared once is read back by the
// next process (here: the next HrtfCache) and renders sample for sample the
// same; a changed SOFA file, a corrupt, truncated, foreign or hostile cache
// file is ignored with a note and the set prepared again (and the file
// rewritten); a directory that cannot be written means no cache and one
// note; the key changes with every part of the format.
//
// Every test works in its own temporary directory and points
// EARSHOT_CACHE_DIR there, so nothing is written to the user's home.
#include <gtest/gtest.h>

#include <unistd.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "earshot/audio/hrtf_cache.hpp"
#include "earshot/audio/hrtf_disk_cache.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/errors.hpp"

using earshot::audio::HrtfCache;
using earshot::audio::HrtfDiskCache;
using earshot::audio::HrtfSpectra;
using earshot::audio::PreparedHrtf;
using earshot::hrtf::HrtfSet;
namespace fs = std::filesystem;

namespace {

std::vector<std::uint8_t> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

std::uint64_t read_u64(const std::vector<std::uint8_t>& b, std::size_t at) {
  std::uint64_t v = 0;
  std::memcpy(&v, b.data() + at, 8);
  return v;
}

/// The payload's checksum written back into the header: what a hostile
/// file (not a corrupt one) carries.
void reseal(std::vector<std::uint8_t>& b) {
  const std::size_t h = HrtfDiskCache::kHeaderBytes;
  XXH128_canonical_t c;
  XXH128_canonicalFromHash(&c, XXH3_128bits(b.data() + h, b.size() - h));
  std::memcpy(b.data() + h - 16, c.digest, 16);
}

/// Both sets' arrays and both spectra's arrays are the same, bit for bit.
void expect_same(const PreparedHrtf& a, const PreparedHrtf& b) {
  const HrtfSet::Stored x = a.set->stored(), y = b.set->stored();
  EXPECT_EQ(x.rate, y.rate);
  EXPECT_EQ(x.filter_length, y.filter_length);
  EXPECT_EQ(x.removed_delay_s, y.removed_delay_s);
  EXPECT_EQ(x.filters, y.filters);
  EXPECT_EQ(x.hrirs, y.hrirs);
  ASSERT_EQ(x.delays.size(), y.delays.size());
  EXPECT_EQ(0, std::memcmp(x.delays.data(), y.delays.data(), x.delays.size() * sizeof x.delays[0]));
  EXPECT_EQ(x.energies, y.energies);
  ASSERT_EQ(x.shells.size(), y.shells.size());
  for (std::size_t s = 0; s < x.shells.size(); ++s) {
    EXPECT_EQ(x.shells[s].gram, y.shells[s].gram);
    EXPECT_EQ(x.shells[s].triangulation.vertices, y.shells[s].triangulation.vertices);
    EXPECT_EQ(x.shells[s].triangulation.inverses, y.shells[s].triangulation.inverses);
    EXPECT_EQ(x.shells[s].triangulation.cell_triangles, y.shells[s].triangulation.cell_triangles);
  }
  const HrtfSpectra::Stored p = a.spectra->stored(), q = b.spectra->stored();
  EXPECT_EQ(p.head, q.head);
  EXPECT_EQ(p.tail, q.tail);
  EXPECT_EQ(p.scale, q.scale);
}

/// Four moving noise sources (one near the head) through a renderer on
/// `hrtf`, 200 blocks of both ears.
std::vector<float> render(const PreparedHrtf& hrtf) {
  earshot::audio::RendererConfig cfg;
  cfg.block = hrtf.spectra->block();
  cfg.sample_rate = hrtf.set->sample_rate();
  cfg.max_sources = 4;
  earshot::audio::Renderer r(hrtf, cfg);
  std::vector<int> ids;
  for (int i = 0; i < 4; ++i) ids.push_back(r.add_source({}));
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  std::vector<float> out, left(cfg.block), right(cfg.block);
  for (int b = 0; b < 200; ++b) {
    for (int i = 0; i < 4; ++i) {
      earshot::audio::SourceState s;
      const double a = 0.05 * b + 1.7 * i, d = i == 3 ? 0.3 : 1.0 + i;
      s.position = {d * std::sin(a), 0.3 * std::sin(0.02 * b + i), -d * std::cos(a)};
      r.set_source(ids[static_cast<std::size_t>(i)], s);
      for (float& x : r.source_input(ids[static_cast<std::size_t>(i)])) x = u(rng);
    }
    r.render(left, right);
    out.insert(out.end(), left.begin(), left.end());
    out.insert(out.end(), right.begin(), right.end());
  }
  return out;
}

class HrtfDiskCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("earshot_disk_cache_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    dir_ = root_ / "cache";
    if (const char* old = std::getenv("EARSHOT_CACHE_DIR")) saved_env_ = old;
    ::setenv("EARSHOT_CACHE_DIR", dir_.c_str(), 1);
  }
  void TearDown() override {
    if (saved_env_)
      ::setenv("EARSHOT_CACHE_DIR", saved_env_->c_str(), 1);
    else
      ::unsetenv("EARSHOT_CACHE_DIR");
    std::error_code ec;
    fs::remove_all(root_, ec);
  }

  /// A cache on dir_ whose notes are kept in notes_.
  HrtfCache cache() {
    return HrtfCache(dir_, [this](const std::string& line) {
      std::lock_guard lock(notes_mutex_);
      notes_.push_back(line);
    });
  }
  /// A small synthetic set (make_sofa.py) written to `name` in the test's directory.
  fs::path synthetic(const std::string& name, const std::string& args) const {
    const fs::path file = root_ / name;
    const std::string cmd = std::string("/usr/bin/python3 ") + EARSHOT_MAKE_SOFA + " --out " + file.string() + " " + args;
    if (std::system(cmd.c_str()) != 0) throw std::runtime_error("make_sofa.py failed: " + cmd);
    return file;
  }
  [[nodiscard]] std::vector<fs::path> cache_files() const {
    std::vector<fs::path> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir_, ec)) out.push_back(e.path());
    return out;
  }

  fs::path root_, dir_;
  std::optional<std::string> saved_env_;
  std::mutex notes_mutex_;
  std::vector<std::string> notes_;
};

constexpr const char* kSmall = "--rate 44100 --length 64 --grid fibonacci:40";

}  // namespace

TEST_F(HrtfDiskCacheTest, TheNextProcessReadsWhatTheFirstPrepared) {
  PreparedHrtf first;
  {
    HrtfCache c = cache();
    first = c.get(HrtfSet::kDefaultPath, 48000.0, 128);
    EXPECT_EQ(c.disk_loads(), 0u) << "an empty cache has nothing to read";
  }
  ASSERT_EQ(cache_files().size(), 1u) << "one file written";
  const auto key = HrtfDiskCache::key_of(HrtfSet::kDefaultPath, 48000.0, 128);
  ASSERT_TRUE(key);
  EXPECT_TRUE(fs::exists(HrtfDiskCache(dir_).file_for(*key)));

  HrtfCache c = cache();
  const PreparedHrtf again = c.get(HrtfSet::kDefaultPath, 48000.0, 128);
  EXPECT_EQ(c.disk_loads(), 1u);
  EXPECT_EQ(c.preparations(), 1u);
  expect_same(first, again);
  EXPECT_TRUE(notes_.empty()) << notes_.front();

  // Another block is another file; the default constructor takes the
  // directory from EARSHOT_CACHE_DIR.
  HrtfCache from_env;
  ASSERT_TRUE(from_env.disk().directory());
  EXPECT_EQ(*from_env.disk().directory(), dir_);
  (void)from_env.get(HrtfSet::kDefaultPath, 48000.0, 256);
  EXPECT_EQ(from_env.disk_loads(), 0u);
  EXPECT_EQ(cache_files().size(), 2u);
}

TEST_F(HrtfDiskCacheTest, ASetReadBackRendersSampleForSampleAsAFreshOne) {
  HrtfCache writer = cache();
  const PreparedHrtf fresh = writer.get(HrtfSet::kDefaultPath, 48000.0, 128);  // prepared, and written
  ASSERT_EQ(writer.disk_loads(), 0u);
  HrtfCache c = cache();
  const PreparedHrtf read = c.get(HrtfSet::kDefaultPath, 48000.0, 128);
  ASSERT_EQ(c.disk_loads(), 1u);
  ASSERT_NE(read.set, fresh.set);
  const std::vector<float> a = render(fresh), b = render(read);
  ASSERT_EQ(a.size(), b.size());
  double energy = 0.0;
  for (float x : a) energy += double(x) * x;
  EXPECT_GT(energy, 1.0) << "the render is not silence";
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float))) << "renders differ";

  // The parametric ITD is a setting, not in the file: the same file serves it.
  HrtfSet woodworth = *fresh.set;
  woodworth.set_parametric_itd(0.09);
  const PreparedHrtf fresh_woodworth{std::make_shared<const HrtfSet>(std::move(woodworth)), fresh.spectra};
  HrtfCache c2 = cache();
  const PreparedHrtf read_woodworth = c2.get(HrtfSet::kDefaultPath, 48000.0, 128, 0.09);
  EXPECT_EQ(c2.disk_loads(), 1u);
  const std::vector<float> w1 = render(fresh_woodworth), w2 = render(read_woodworth);
  EXPECT_EQ(0, std::memcmp(w1.data(), w2.data(), w1.size() * sizeof(float)));
  EXPECT_NE(0, std::memcmp(w1.data(), a.data(), a.size() * sizeof(float))) << "the radius was not applied";
}

TEST_F(HrtfDiskCacheTest, AChangedSofaFileIsPreparedAgain) {
  const fs::path sofa = synthetic("set.sofa", kSmall);
  const PreparedHrtf a = cache().get(sofa, 48000.0, 64);
  // Same path, same size class, other contents: a stale cache file must not serve it.
  const fs::path other = synthetic("other.sofa", "--rate 44100 --length 64 --grid fibonacci:41");
  fs::copy_file(other, sofa, fs::copy_options::overwrite_existing);
  HrtfCache c = cache();
  const PreparedHrtf b = c.get(sofa, 48000.0, 64);
  EXPECT_EQ(c.disk_loads(), 0u) << "a changed file was served from the cache";
  EXPECT_EQ(b.set->all_measurement_count(), 41u);
  EXPECT_EQ(a.set->all_measurement_count(), 40u);
  EXPECT_EQ(cache_files().size(), 2u);
  // And the new one is served next time.
  HrtfCache d = cache();
  expect_same(b, d.get(sofa, 48000.0, 64));
  EXPECT_EQ(d.disk_loads(), 1u);
}

TEST_F(HrtfDiskCacheTest, CorruptTruncatedAndForeignFilesArePreparedAgainAndRewritten) {
  const fs::path sofa = synthetic("set.sofa", kSmall);
  const PreparedHrtf fresh = HrtfCache(std::nullopt).get(sofa, 48000.0, 32);
  (void)cache().get(sofa, 48000.0, 32);
  const auto key = HrtfDiskCache::key_of(sofa, 48000.0, 32);
  ASSERT_TRUE(key);
  const fs::path file = HrtfDiskCache(dir_).file_for(*key);
  const std::vector<std::uint8_t> good = read_bytes(file);
  ASSERT_GT(good.size(), HrtfDiskCache::kHeaderBytes + 1000);

  struct Damage {
    std::string what;
    std::vector<std::uint8_t> bytes;
  };
  std::vector<Damage> damages;
  const auto flipped = [&](std::size_t at) {
    auto b = good;
    b[at] ^= 0x5a;
    return b;
  };
  damages.push_back({"empty", {}});
  damages.push_back({"header only", {good.begin(), good.begin() + HrtfDiskCache::kHeaderBytes}});
  damages.push_back({"half", {good.begin(), good.begin() + static_cast<long>(good.size() / 2)}});
  damages.push_back({"one byte short", {good.begin(), good.end() - 1}});
  damages.push_back({"magic", flipped(0)});
  damages.push_back({"format version", flipped(8)});
  damages.push_back({"format id", flipped(16)});
  damages.push_back({"key", flipped(24)});
  damages.push_back({"payload size", flipped(56)});
  damages.push_back({"a payload byte", flipped(good.size() / 3)});
  damages.push_back({"the last byte", flipped(good.size() - 1)});
  {
    auto b = good;
    b.push_back(0);
    damages.push_back({"a byte appended", b});
  }
  {
    std::vector<std::uint8_t> noise(good.size());
    std::mt19937 rng(3);
    for (auto& x : noise) x = static_cast<std::uint8_t>(rng());
    damages.push_back({"noise", noise});
  }
  for (const Damage& d : damages) {
    SCOPED_TRACE(d.what);
    write_bytes(file, d.bytes);
    notes_.clear();
    HrtfCache c = cache();
    PreparedHrtf p;
    ASSERT_NO_THROW(p = c.get(sofa, 48000.0, 32));
    EXPECT_EQ(c.disk_loads(), 0u);
    expect_same(fresh, p);
    ASSERT_EQ(notes_.size(), 1u);
    EXPECT_NE(notes_[0].find(file.filename().string()), std::string::npos) << notes_[0];
    EXPECT_TRUE(read_bytes(file) == good) << "not rewritten";
  }
}

TEST_F(HrtfDiskCacheTest, HostileFilesWithARightChecksumAreRefused) {
  const fs::path sofa = synthetic("set.sofa", kSmall);
  (void)cache().get(sofa, 48000.0, 32);
  const auto key = HrtfDiskCache::key_of(sofa, 48000.0, 32);
  ASSERT_TRUE(key);
  const std::vector<std::uint8_t> good = read_bytes(HrtfDiskCache(dir_).file_for(*key));
  ASSERT_NO_THROW((void)HrtfDiskCache::parse(good, *key));
  const std::size_t h = HrtfDiskCache::kHeaderBytes;

  // Find each section by its tag: [tag][element size][count][data...].
  const auto find = [&](const char* tag) {
    for (std::size_t at = h; at + 16 <= good.size(); at += 8)
      if (std::memcmp(good.data() + at, tag, 4) == 0) return at;
    ADD_FAILURE() << "no section " << tag;
    return std::size_t{0};
  };
  const auto sealed = [&](std::vector<std::uint8_t> b) {
    reseal(b);
    return b;
  };
  const auto with_u64 = [&](std::size_t at, std::uint64_t v) {
    auto b = good;
    std::memcpy(b.data() + at, &v, 8);
    return sealed(b);
  };
  const auto with_u32 = [&](std::size_t at, std::uint32_t v) {
    auto b = good;
    std::memcpy(b.data() + at, &v, 4);
    return sealed(b);
  };
  const auto with_double = [&](std::size_t at, double v) {
    auto b = good;
    std::memcpy(b.data() + at, &v, 8);
    return sealed(b);
  };
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> hostile{
      {"filter count huge", with_u64(find("FILT") + 8, std::uint64_t{1} << 61)},
      {"filter count one less", with_u64(find("FILT") + 8, (read_u64(good, find("FILT") + 8)) - 1)},
      {"filter length", with_u64(find("SETN") + 16, 1u << 20)},
      {"shell count", with_u64(find("SETN") + 16 + 16, 1000)},
      {"element size", with_u32(find("DIRS") + 4, 8)},
      {"tag", with_u32(find("HRIR"), 0x41414141u)},
      {"triangle vertex out of range", with_u32(find("TVTX") + 16, 40)},
      {"grid candidate out of range", with_u32(find("CTRI") + 16, 1u << 30)},
      {"grid start", with_u32(find("CSTA") + 16 + 4, 1u << 30)},
      {"delay not finite", with_double(find("DELY") + 16, std::nan(""))},
      {"delay negative", with_double(find("DELY") + 16, -1.0)},
      {"rate", with_double(find("SETD") + 16, 44100.0)},
      {"spectra block", with_u64(find("SPEB") + 16, 64)},
      {"shell first", with_u64(find("SHEL") + 16, 1)},
  };
  for (const auto& [what, bytes] : hostile) {
    SCOPED_TRACE(what);
    EXPECT_ANY_THROW((void)HrtfDiskCache::parse(bytes, *key));
    EXPECT_ANY_THROW((void)HrtfDiskCache::parse(bytes, *key, false));
  }
}

TEST_F(HrtfDiskCacheTest, AnUnwritableDirectoryMeansNoCacheAndOneNote) {
  const fs::path sofa = synthetic("set.sofa", kSmall);
  // A directory under a regular file cannot be made, not even by root.
  std::ofstream(root_ / "plain_file") << "x";
  dir_ = root_ / "plain_file" / "cache";
  HrtfCache c = cache();
  PreparedHrtf a, b;
  ASSERT_NO_THROW(a = c.get(sofa, 48000.0, 64));
  ASSERT_NO_THROW(b = c.get(sofa, 48000.0, 32));
  EXPECT_EQ(c.preparations(), 2u);
  ASSERT_EQ(notes_.size(), 1u) << "one note, not one per set";
  EXPECT_NE(notes_[0].find("plain_file"), std::string::npos) << notes_[0];
  EXPECT_NE(notes_[0].find("EARSHOT_CACHE_DIR"), std::string::npos) << notes_[0];
}

TEST_F(HrtfDiskCacheTest, TheEnvironmentNamesTheDirectoryOrTurnsItOff) {
  const auto saved = [](const char* name) -> std::optional<std::string> {
    const char* v = std::getenv(name);
    return v ? std::optional<std::string>(v) : std::nullopt;
  };
  const auto xdg = saved("XDG_CACHE_HOME"), home = saved("HOME");
  ::setenv("EARSHOT_CACHE_DIR", "off", 1);
  EXPECT_FALSE(HrtfDiskCache::directory_from_environment());
  EXPECT_FALSE(HrtfCache().disk().directory());
  ::setenv("EARSHOT_CACHE_DIR", "/some/where", 1);
  EXPECT_EQ(HrtfDiskCache::directory_from_environment(), fs::path("/some/where"));
  ::unsetenv("EARSHOT_CACHE_DIR");
  ::setenv("XDG_CACHE_HOME", "/xdg/cache", 1);
  ::setenv("HOME", "/home/someone", 1);
  EXPECT_EQ(HrtfDiskCache::directory_from_environment(), fs::path("/xdg/cache/earshot"));
  ::setenv("XDG_CACHE_HOME", "relative/ignored", 1);
  EXPECT_EQ(HrtfDiskCache::directory_from_environment(), fs::path("/home/someone/.cache/earshot"));
  ::unsetenv("XDG_CACHE_HOME");
  ::unsetenv("HOME");
  EXPECT_FALSE(HrtfDiskCache::directory_from_environment());
  if (xdg) ::setenv("XDG_CACHE_HOME", xdg->c_str(), 1);
  if (home) ::setenv("HOME", home->c_str(), 1);

  // Off: nothing is read or written.
  HrtfCache off(std::nullopt);
  (void)off.get(synthetic("set.sofa", kSmall), 48000.0, 64);
  EXPECT_TRUE(cache_files().empty());
}

TEST_F(HrtfDiskCacheTest, EveryPartOfTheFormatChangesTheKey) {
  const std::uint32_t f = HrtfDiskCache::kFormatVersion, s = HrtfSet::kPreparationVersion,
                      p = HrtfSpectra::kPreparationVersion;
  const std::string layout = HrtfDiskCache::layout();
  const std::uint64_t now = HrtfDiskCache::format_id(f, s, p, layout);
  EXPECT_EQ(now, HrtfDiskCache::format_id()) << "the current id is made of the current parts";
  EXPECT_NE(now, HrtfDiskCache::format_id(f + 1, s, p, layout));
  EXPECT_NE(now, HrtfDiskCache::format_id(f, s + 1, p, layout));
  EXPECT_NE(now, HrtfDiskCache::format_id(f, s, p + 1, layout));
  // A section added, or one whose element changes size.
  EXPECT_NE(now, HrtfDiskCache::format_id(f, s, p, layout + "NEWS:4;"));
  std::string wider = layout;
  wider.replace(wider.find("FILT:4"), 6, "FILT:8");
  EXPECT_NE(now, HrtfDiskCache::format_id(f, s, p, wider));
  EXPECT_NE(layout.find("SPET:2"), std::string::npos) << layout;

  // The file's name: the SOFA bytes, the rate and the block.
  const auto key = HrtfDiskCache::key_of(HrtfSet::kDefaultPath, 48000.0, 128);
  ASSERT_TRUE(key);
  const HrtfDiskCache disk(dir_);
  auto other = *key;
  other.block = 256;
  EXPECT_NE(disk.file_for(*key), disk.file_for(other));
  other = *key;
  other.rate = 44100.0;
  EXPECT_NE(disk.file_for(*key), disk.file_for(other));
  other = *key;
  other.sofa_hash[7] ^= 1;
  EXPECT_NE(disk.file_for(*key), disk.file_for(other));
  EXPECT_EQ(disk.file_for(*key), disk.file_for(*HrtfDiskCache::key_of(HrtfSet::kDefaultPath, 48000.0, 128)));
  EXPECT_FALSE(HrtfDiskCache::key_of(root_ / "missing.sofa", 48000.0, 128));
}

TEST_F(HrtfDiskCacheTest, OnlyTheFilesUsedLastAreKept) {
  const fs::path sofa = synthetic("set.sofa", kSmall);
  fs::create_directories(dir_);
  std::ofstream(dir_ / "someone_elses.txt") << "not ours";
  std::ofstream(dir_ / "someone_elses.hrtf") << "not ours either";
  HrtfCache c = cache();
  for (std::size_t i = 0; i < HrtfDiskCache::kMaxFiles + 3; ++i) (void)c.get(sofa, 48000.0, 8 + i);
  std::size_t ours = 0;
  for (const auto& p : cache_files()) ours += p.extension() == ".hrtf" && p.stem().string().size() == 32;
  EXPECT_EQ(ours, HrtfDiskCache::kMaxFiles);
  EXPECT_TRUE(fs::exists(dir_ / "someone_elses.txt")) << "a file the cache did not write was removed";
  EXPECT_TRUE(fs::exists(dir_ / "someone_elses.hrtf")) << "a file the cache did not write was removed";
}

TEST_F(HrtfDiskCacheTest, TwoProcessesWritingAtOnceLeaveAWholeFile) {
  const fs::path sofa = synthetic("set.sofa", kSmall);
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i)
    threads.emplace_back([&] {
      HrtfCache c = cache();
      (void)c.get(sofa, 48000.0, 16);
    });
  for (auto& t : threads) t.join();
  ASSERT_EQ(cache_files().size(), 1u) << "temporary files left behind";
  HrtfCache c = cache();
  (void)c.get(sofa, 48000.0, 16);
  EXPECT_EQ(c.disk_loads(), 1u);
  EXPECT_TRUE(notes_.empty());
}

TEST_F(HrtfDiskCacheTest, ABadSofaFileIsStillAnErrorAndNothingIsWritten) {
  const fs::path bad = root_ / "not_sofa.sofa";
  std::ofstream(bad) << "this is not a SOFA file\n";
  HrtfCache c = cache();
  for (const fs::path& p : {bad, root_ / "missing.sofa"}) {
    try {
      (void)c.get(p, 48000.0, 128);
      FAIL() << "a bad file loaded";
    } catch (const earshot::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(p.filename().string()), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(cache_files().empty());
  EXPECT_TRUE(notes_.empty());
}
