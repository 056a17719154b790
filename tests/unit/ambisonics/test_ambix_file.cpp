// Reading ambiX / FuMa / N3D files: order from the channel count, errors
// that name the file, conversion to ambiX.
#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "earshot/audio/ambisonics/ambix_file.hpp"
#include "earshot/errors.hpp"

using namespace earshot;
using namespace earshot::ambisonics;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("earshot_ambix_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

/// Writes frames x channels interleaved, channel c of frame n = value(c, n).
template <class F>
void write(const fs::path& p, int channels, int frames, int format, F value) {
  SF_INFO info{};
  info.samplerate = 48000;
  info.channels = channels;
  info.format = format;
  SNDFILE* f = sf_open(p.c_str(), SFM_WRITE, &info);
  ASSERT_NE(f, nullptr) << sf_strerror(nullptr);
  std::vector<float> x(static_cast<std::size_t>(channels * frames));
  for (int n = 0; n < frames; ++n)
    for (int c = 0; c < channels; ++c) x[static_cast<std::size_t>(n * channels + c)] = value(c, n);
  sf_writef_float(f, x.data(), frames);
  sf_close(f);
}

}  // namespace

TEST(AmbixFile, OrderComesFromTheChannelCount) {
  const fs::path p = temp_dir() / "o2.wav";
  write(p, 9, 100, SF_FORMAT_WAV | SF_FORMAT_FLOAT, [](int c, int n) { return 0.01f * float(c) + 1e-4f * float(n); });
  const AmbixSignal s = read_ambix(p);
  EXPECT_EQ(s.order, 2);
  EXPECT_EQ(s.frames, 100u);
  EXPECT_EQ(s.sample_rate, 48000);
  EXPECT_FLOAT_EQ(s.channel(4)[10], 0.04f + 1e-3f);
}

TEST(AmbixFile, ANonSquareChannelCountIsAnErrorNamingTheFile) {
  for (const char* ext : {"wav", "w64", "caf"}) {
    const fs::path p = temp_dir() / (std::string("five.") + ext);
    const int major = std::string(ext) == "wav" ? SF_FORMAT_WAV : std::string(ext) == "w64" ? SF_FORMAT_W64 : SF_FORMAT_CAF;
    write(p, 5, 10, major | SF_FORMAT_FLOAT, [](int, int) { return 0.0f; });
    try {
      AmbixReader r(p);
      FAIL() << "read a 5-channel file";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(p.string()), std::string::npos) << what;
      EXPECT_NE(what.find("5 channels"), std::string::npos) << what;
      EXPECT_NE(what.find("(N + 1)^2"), std::string::npos) << what;
    }
  }
  const fs::path mono = temp_dir() / "mono.wav";
  write(mono, 1, 10, SF_FORMAT_WAV | SF_FORMAT_PCM_16, [](int, int) { return 0.0f; });
  EXPECT_THROW(AmbixReader r(mono), InputError);
  // FuMa stops at third order: 25 channels are not FuMa.
  const fs::path o4 = temp_dir() / "o4.wav";
  write(o4, 25, 10, SF_FORMAT_WAV | SF_FORMAT_FLOAT, [](int, int) { return 0.0f; });
  EXPECT_NO_THROW(AmbixReader r(o4));
  EXPECT_THROW(AmbixReader r(o4, Convention::fuma), InputError);
}

TEST(AmbixFile, AMissingFileIsAnErrorNamingIt) {
  const fs::path p = temp_dir() / "nowhere.wav";
  try {
    AmbixReader r(p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
}

TEST(AmbixFile, FumaAndN3dAreConvertedToAmbix) {
  // FuMa W X Y Z of a wave from the left at 0 dB: W = 1/sqrt 2, Y = 1.
  const fs::path fuma = temp_dir() / "fuma.wav";
  write(fuma, 4, 4, SF_FORMAT_WAV | SF_FORMAT_FLOAT, [](int c, int) {
    return c == 0 ? float(1.0 / std::sqrt(2.0)) : c == 2 ? 1.0f : 0.0f;
  });
  const AmbixSignal a = read_ambix(fuma, Convention::fuma);
  EXPECT_NEAR(a.channel(0)[0], 1.0f, 1e-6);  // W
  EXPECT_NEAR(a.channel(1)[0], 1.0f, 1e-6);  // Y (ACN 1)
  EXPECT_NEAR(a.channel(2)[0], 0.0f, 1e-6);
  EXPECT_NEAR(a.channel(3)[0], 0.0f, 1e-6);
  // N3D: degree l is sqrt(2l + 1) louder.
  const fs::path n3d = temp_dir() / "n3d.wav";
  write(n3d, 4, 4, SF_FORMAT_WAV | SF_FORMAT_FLOAT, [](int, int) { return 0.5f; });
  const AmbixSignal b = read_ambix(n3d, Convention::n3d);
  EXPECT_NEAR(b.channel(0)[0], 0.5f, 1e-6);
  EXPECT_NEAR(b.channel(3)[0], 0.5f / std::sqrt(3.0f), 1e-6);
  // Streaming: the reader gives the frames in pieces, zero past the end.
  AmbixReader r(n3d, Convention::n3d);
  std::vector<float> out(4 * 3);
  EXPECT_EQ(r.read(out, 3), 3u);
  EXPECT_EQ(r.read(out, 3), 1u);
  EXPECT_NEAR(out[0], 0.5f, 1e-6);
  EXPECT_EQ(out[1], 0.0f);
}
