// Fuzzes the reader of the HRTF disk cache's files (HrtfDiskCache::parse):
// a file in a directory anyone may write, so outside bytes. Each input is
// read with the checksum checked and again with it ignored (a hostile file
// carries a right one), and a set that is accepted is used: interpolated,
// its spectra read, two blocks rendered.
//
// Seed: at start-up a valid file of a small set (eight directions, 8-tap
// filters, 4-frame blocks) is written into the corpus directory given on
// the command line, so the seed always has the current format (the
// committed corpus holds only the file magic).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <span>
#include <vector>

#include "earshot/audio/hrtf_disk_cache.hpp"
#include "earshot/audio/renderer.hpp"
#include "corpus_dir.hpp"

using earshot::audio::HrtfDiskCache;
using earshot::audio::HrtfSpectra;
using earshot::hrtf::HrtfSet;

namespace {

HrtfDiskCache::Key fuzz_key() {
  HrtfDiskCache::Key k;
  for (std::size_t i = 0; i < k.sofa_hash.size(); ++i) k.sofa_hash[i] = static_cast<std::uint8_t>(i * 37 + 1);
  k.rate = 48000.0;
  k.block = 4;
  return k;
}

/// A small set made from arrays (an octahedron and two more directions).
std::vector<std::uint8_t> valid_file() {
  const std::vector<earshot::Vec3> dirs{{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},     {0, -1, 0},
                                        {0, 0, 1},  {0, 0, -1}, {0.6, 0.8, 0}, {0, 0.6, 0.8}};
  const std::size_t M = dirs.size(), L = 8;
  HrtfSet::Stored s;
  s.rate = 48000.0;
  s.filter_length = L;
  s.hrir_length = L;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  s.filters.resize(2 * M * L);
  for (float& x : s.filters) x = u(rng);
  s.hrirs = s.filters;
  for (const auto& d : dirs) {
    s.directions.push_back({std::atan2(d[1], d[0]), std::asin(d[2])});
    s.delays.push_back({0.0001 * (1.0 + d[1]), 0.0001 * (1.0 - d[1])});
  }
  const auto dot = [&](std::size_t i, std::size_t j, std::size_t ear) {
    double sum = 0.0;
    for (std::size_t k = 0; k < L; ++k) sum += double(s.filters[(2 * i + ear) * L + k]) * s.filters[(2 * j + ear) * L + k];
    return sum;
  };
  for (std::size_t m = 0; m < M; ++m) s.energies.push_back({dot(m, m, 0), dot(m, m, 1)});
  HrtfSet::StoredShell shell;
  shell.info = {1.0, 0, M};
  shell.triangulation = earshot::hrtf::SphereTriangulation(dirs).stored();
  for (const auto& v : shell.triangulation.vertices) {
    std::array<std::array<double, 6>, 2> g{};
    constexpr std::array<std::array<int, 2>, 6> kPairs{{{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}}};
    for (std::size_t ear = 0; ear < 2; ++ear)
      for (std::size_t k = 0; k < 6; ++k) g[ear][k] = dot(v[kPairs[k][0]], v[kPairs[k][1]], ear);
    shell.gram.push_back(g);
  }
  s.shells.push_back(std::move(shell));
  const HrtfSet set = HrtfSet::from_stored(std::move(s));
  const HrtfSpectra spectra(set, 4);
  return HrtfDiskCache::serialize(fuzz_key(), set, spectra);
}

void use(const HrtfDiskCache::Loaded& l) {
  float sum = 0.0f;
  for (const earshot::Vec3& d : {earshot::Vec3{1, 0, 0}, earshot::Vec3{0, -0.6, 0.8}, earshot::Vec3{-0.3, 0.1, -0.95}}) {
    const auto in = l.set.interpolate(d);
    for (const std::uint32_t m : in.blend.index) {
      for (const float v : l.spectra.head(m, earshot::hrtf::Ear::right)) sum += v;
      for (const std::int16_t v : l.spectra.tail(m, earshot::hrtf::Ear::left)) sum += static_cast<float>(v);
    }
  }
  earshot::audio::RendererConfig cfg;
  cfg.sample_rate = l.set.sample_rate();
  cfg.block = l.spectra.block();
  cfg.max_sources = 1;
  cfg.near_field = false;  // its table costs milliseconds to build
  cfg.max_distance_m = 2.0;
  earshot::audio::Renderer r({std::make_shared<const HrtfSet>(l.set), std::make_shared<const HrtfSpectra>(l.spectra)},
                             cfg);
  const int id = r.add_source({});
  std::vector<float> left(cfg.block), right(cfg.block);
  for (int b = 0; b < 2; ++b) {
    for (float& x : r.source_input(id)) x = 0.5f;
    r.render(left, right);
  }
  volatile float sink = sum + left[0] + right[0];
  (void)sink;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  if (const auto dir = earshot::fuzz::corpus_dir(*argc, *argv)) earshot::fuzz::write_seed(*dir, "valid.hrtf", valid_file());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const HrtfDiskCache::Key key = fuzz_key();
  for (const bool verify : {true, false}) {
    try {
      use(HrtfDiskCache::parse(std::span(data, size), key, verify));
    } catch (const std::exception&) {
      // Refused, as it should be: the cache then prepares the set again.
    }
  }
  return 0;
}
