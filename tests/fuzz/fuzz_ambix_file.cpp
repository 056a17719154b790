// Fuzzes the reading of Ambisonic files (AmbixReader: libsndfile's header
// parsing behind it, then ours: the order from the channel count, the
// conventions' channel maps, streamed reads) on outside bytes. The input's
// first byte picks the convention (ambiX, N3D, FuMa); the rest is the file,
// handed over through a memfd so libsndfile opens it by path as it would a
// user's file. Whatever opens is read to its end in blocks.
//
// Seeds: at start-up small WAV files (first order, third order, FuMa, a
// 5-channel file that must be refused) are written into the corpus
// directory given on the command line (binary files stay out of the
// repository; the committed corpus holds one small text seed).
#include <sndfile.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "earshot/audio/ambisonics/ambix_file.hpp"
#include "corpus_dir.hpp"

namespace {

void write_seed(const std::filesystem::path& p, std::uint8_t convention, int channels, int format) {
  const auto tmp = p.string() + ".wav.tmp";
  SF_INFO info{};
  info.samplerate = 48000;
  info.channels = channels;
  info.format = format;
  SNDFILE* f = sf_open(tmp.c_str(), SFM_WRITE, &info);
  if (!f) return;
  std::vector<float> x(static_cast<std::size_t>(channels) * 300);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>((i * 7919) % 200) / 200.0f - 0.5f;
  sf_writef_float(f, x.data(), 300);
  sf_close(f);
  std::ifstream in(tmp, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
  std::ofstream out(p, std::ios::binary);
  out.put(static_cast<char>(convention));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  std::filesystem::remove(tmp);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  if (const auto dir = earshot::fuzz::corpus_dir(*argc, *argv)) {
    write_seed(*dir / "o1_float", 0, 4, SF_FORMAT_WAV | SF_FORMAT_FLOAT);
    write_seed(*dir / "o3_pcm16", 0, 16, SF_FORMAT_WAV | SF_FORMAT_PCM_16);
    write_seed(*dir / "fuma_o2", 2, 9, SF_FORMAT_WAV | SF_FORMAT_PCM_24);
    write_seed(*dir / "n3d_w64", 1, 4, SF_FORMAT_W64 | SF_FORMAT_FLOAT);
    write_seed(*dir / "five", 0, 5, SF_FORMAT_WAV | SF_FORMAT_FLOAT);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1 || size > (1u << 20)) return 0;
  using earshot::ambisonics::Convention;
  const Convention c = data[0] % 3 == 0 ? Convention::ambix : data[0] % 3 == 1 ? Convention::n3d : Convention::fuma;
  const int fd = memfd_create("fuzz_ambix", MFD_CLOEXEC);
  if (fd < 0) return 0;
  std::size_t done = 1;
  while (done < size) {
    const ssize_t k = ::write(fd, data + done, size - done);
    if (k <= 0) break;
    done += static_cast<std::size_t>(k);
  }
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  try {
    earshot::ambisonics::AmbixReader r(path, c);
    std::vector<float> block(r.channels() * 64);
    for (int i = 0; i < 4096 && r.read(block, 64) > 0; ++i) {
    }
  } catch (const std::exception&) {
    // Refused, naming the file: as a user's bad file is.
  }
  ::close(fd);
  return 0;
}
