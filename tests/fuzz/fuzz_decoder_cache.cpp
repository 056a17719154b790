// Fuzzes the reader of the decoder cache's files (DecoderCache::parse): a
// file in a directory anyone may write, so outside bytes. Each input is read
// with the checksum checked and again with it ignored (a hostile file can
// carry a right one), and filters that are accepted are used: a decoder
// built from them renders two blocks.
//
// Seed: at start-up a valid file (order 1, 8-tap filters) is written into
// the corpus directory given on the command line, so the seed always has the
// current format (the committed corpus holds only the file magic).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <span>
#include <vector>

#include "earshot/audio/ambisonics/binaural_decoder.hpp"
#include "earshot/audio/ambisonics/decoder_cache.hpp"
#include "corpus_dir.hpp"

using earshot::ambisonics::DecoderCache;
using earshot::ambisonics::DecoderFilters;

namespace {

DecoderCache::Key fuzz_key() {
  DecoderCache::Key k;
  for (std::size_t i = 0; i < k.sofa_hash.size(); ++i) k.sofa_hash[i] = static_cast<std::uint8_t>(i * 29 + 3);
  k.rate = 48000.0;
  k.order = 1;
  k.design = "fuzz";
  return k;
}

std::vector<std::uint8_t> valid_file() {
  DecoderFilters f;
  f.order = 1;
  f.sample_rate = 48000.0;
  f.length = 8;
  f.taps.resize(2 * f.channels() * f.length);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (float& x : f.taps) x = u(rng);
  return DecoderCache::serialize(fuzz_key(), f);
}

void use(const DecoderFilters& f) {
  constexpr std::size_t kBlock = 16;
  earshot::ambisonics::BinauralDecoder d(f, kBlock);
  std::vector<float> in(f.channels() * kBlock, 0.25f), l(kBlock), r(kBlock);
  for (int b = 0; b < 2; ++b) d.process(in, l, r);
  volatile float sink = l[0] + r[kBlock - 1];
  (void)sink;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  if (const auto dir = earshot::fuzz::corpus_dir(*argc, *argv)) earshot::fuzz::write_seed(*dir, "valid.ambi", valid_file());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const DecoderCache::Key key = fuzz_key();
  for (const bool verify : {true, false}) {
    try {
      const DecoderFilters f = DecoderCache::parse(std::span(data, size), key, verify);
      if (f.length <= 4096) use(f);  // a large valid design is just slow to convolve, not wrong
    } catch (const std::exception&) {
      // Refused: the cache designs the decoder again.
    }
  }
  return 0;
}
