// The Y4M reader: every colour space's luma, frame parameters, and errors
// naming the file, the frame and the field; the writer's output read back.
#include "earshot/webcam/y4m_reader.hpp"
#include "earshot/webcam/y4m_writer.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <numeric>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "earshot/errors.hpp"

namespace earshot::tracker {
namespace {
using namespace earshot::webcam;  // the webcam module: sources, capture, files, lens

std::string frame_bytes(int w, int h, std::size_t chroma, std::uint8_t base) {
  std::string s(static_cast<std::size_t>(w * h), '\0');
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = static_cast<char>(base + i);
  s.append(chroma, '\x80');
  return s;
}

std::string error_of(const std::string& bytes, int frames_to_read = 10) {
  std::istringstream in(bytes);
  try {
    Y4mReader r(in, "take.y4m");
    for (int i = 0; i < frames_to_read; ++i)
      if (r.next().empty()) break;
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "read without error";
  return {};
}

TEST(Y4mReader, ReadsTheLumaOfEveryColourSpace) {
  struct Case {
    const char* c;
    std::size_t chroma;  // for 5x3
  } cases[] = {{" Cmono", 0}, {"", 2 * 3 * 2}, {" C420jpeg", 12}, {" C420paldv", 12}, {" C420mpeg2", 12},
               {" C420", 12}, {" C422", 2 * 3 * 3}, {" C444", 2 * 15}};
  for (const auto& c : cases) {
    std::string bytes = std::string("YUV4MPEG2 W5 H3 F25:1 Ip A1:1") + c.c + " XYSCSS=420JPEG\n";
    bytes += "FRAME\n" + frame_bytes(5, 3, c.chroma, 10);
    bytes += "FRAME Ip XTAG=1\n" + frame_bytes(5, 3, c.chroma, 100);
    std::istringstream in(bytes);
    Y4mReader r(in, "t.y4m");
    EXPECT_EQ(r.header().width, 5);
    EXPECT_EQ(r.header().height, 3);
    EXPECT_DOUBLE_EQ(r.header().fps(), 25.0);
    EXPECT_EQ(r.header().chroma_bytes, c.chroma) << c.c;
    auto f = r.next();
    ASSERT_EQ(f.size(), 15u) << c.c;
    EXPECT_EQ(f[0], 10);
    EXPECT_EQ(f[14], 24);
    f = r.next();
    ASSERT_EQ(f.size(), 15u) << c.c;
    EXPECT_EQ(f[0], 100);
    EXPECT_EQ(f[14], 114);
    EXPECT_TRUE(r.next().empty());
    EXPECT_EQ(r.frames(), 2);
  }
}

TEST(Y4mReader, HeaderParameters) {
  const Y4mHeader h = parse_y4m_header("YUV4MPEG2 W640 H480 F30000:1001 It A4:3 C422 Xfoo", "x");
  EXPECT_NEAR(h.fps(), 29.97, 0.001);
  EXPECT_EQ(h.interlace, 't');
  EXPECT_EQ(h.aspect, "4:3");
  EXPECT_EQ(h.colour, "422");
  EXPECT_EQ(h.chroma_bytes, 2u * 320 * 480);
  // Odd sizes round the subsampled planes up.
  EXPECT_EQ(parse_y4m_header("YUV4MPEG2 W5 H5 F1:1 C420", "x").chroma_bytes, 2u * 3 * 3);
}

TEST(Y4mReader, BadHeadersNameTheFileAndField) {
  EXPECT_EQ(error_of(""), "take.y4m: field 'header': empty file (no YUV4MPEG2 header)");
  EXPECT_EQ(error_of("RIFF....\n"), "take.y4m: field 'header': not a YUV4MPEG2 stream (the file must start with 'YUV4MPEG2 ')");
  EXPECT_EQ(error_of("YUV4MPEG2 H4 F1:1\n"), "take.y4m: field 'W': the header gives no width");
  EXPECT_EQ(error_of("YUV4MPEG2 W4 F1:1\n"), "take.y4m: field 'H': the header gives no height");
  EXPECT_EQ(error_of("YUV4MPEG2 W4 H4\n"), "take.y4m: field 'F': the header gives no frame rate");
  EXPECT_EQ(error_of("YUV4MPEG2 W4 H4 F1:1 C420p10\n"),
            "take.y4m: field 'C': unsupported colour space '420p10' (8-bit mono, 420jpeg, 420paldv, 420mpeg2, 420, 422 or "
            "444; convert with ffmpeg -pix_fmt gray)");
  const std::pair<const char*, const char*> bad[] = {
      {"YUV4MPEG2 W0 H4 F1:1\n", "field 'W': bad width '0'"},
      {"YUV4MPEG2 W4 H-4 F1:1\n", "field 'H': bad height '-4'"},
      {"YUV4MPEG2 W99999 H4 F1:1\n", "field 'W': bad width '99999'"},
      {"YUV4MPEG2 W16000 H16000 F1:1\n", "larger than 8192x4320"},
      {"YUV4MPEG2 W4 H4 F30\n", "field 'F': bad frame rate '30'"},
      {"YUV4MPEG2 W4 H4 F30:0\n", "field 'F': bad frame rate '30:0'"},
      {"YUV4MPEG2 W4 H4 F1:1 Iq\n", "field 'I': bad interlacing 'q'"},
      {"YUV4MPEG2 W4 H4 F1:1 Z9\n", "unknown header parameter 'Z9'"},
      {"YUV4MPEG2 W4 H4 F1:1", "the stream ends inside a line"},
      {"YUV4MPEG2X W4\n", "not a YUV4MPEG2 stream"},
  };
  for (const auto& [bytes, why] : bad) {
    const std::string e = error_of(bytes);
    EXPECT_EQ(e.rfind("take.y4m: ", 0), 0u) << e;
    EXPECT_NE(e.find(why), std::string::npos) << bytes << " -> " << e;
  }
  EXPECT_NE(error_of("YUV4MPEG2 W4 H4 F1:1 X" + std::string(5000, 'a') + "\n").find("line longer than 4096"),
            std::string::npos);
}

TEST(Y4mReader, BadFramesNameTheFrame) {
  const std::string head = "YUV4MPEG2 W4 H2 F1:1 C420\n";
  const std::string ok = "FRAME\n" + frame_bytes(4, 2, 4, 0);
  EXPECT_EQ(error_of(head + ok + "FRAME\n" + frame_bytes(4, 2, 0, 0).substr(0, 5)),
            "take.y4m: field 'Y': frame 2: truncated: 5 of 8 luma bytes");
  EXPECT_EQ(error_of(head + ok + ok + "FRAME\n" + frame_bytes(4, 2, 2, 0)),
            "take.y4m: field 'C': frame 3: truncated: 2 of 4 chroma bytes");
  EXPECT_EQ(error_of(head + ok + "FRAMES\n"), "take.y4m: field 'FRAME': frame 2: expected a 'FRAME' line, got 'FRAMES'");
  EXPECT_EQ(error_of(head + "FRAME"), "take.y4m: field 'FRAME': frame 1: the stream ends inside a line");
}

TEST(Y4mReader, WriterOutputReadsBack) {
  std::ostringstream out;
  Y4mWriter w(out, 7, 5, 30000, 1001);
  std::vector<std::uint8_t> a(35), b(35);
  std::iota(a.begin(), a.end(), 0);
  std::iota(b.begin(), b.end(), 200);
  w.write(a);
  w.write(b);
  EXPECT_THROW(w.write(std::span(a).first(3)), std::invalid_argument);
  std::istringstream in(out.str());
  Y4mReader r(in, "w");
  EXPECT_EQ(r.header().colour, "mono");
  EXPECT_EQ(r.header().fps_num, 30000);
  EXPECT_EQ(r.header().fps_den, 1001);
  const auto fa = r.next();
  EXPECT_TRUE(std::equal(fa.begin(), fa.end(), a.begin(), a.end()));
  const auto fb = r.next();
  EXPECT_TRUE(std::equal(fb.begin(), fb.end(), b.begin(), b.end()));
  EXPECT_TRUE(r.next().empty());
}

TEST(Y4mReader, FilesThatCannotBeOpenedAreNamed) {
  try {
    Y4mReader r(std::filesystem::path("/nonexistent/take.y4m"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/take.y4m: cannot open the video file");
  }
}

/// Read speed of a 640x480 4:2:0 file, for BENCHMARKS (printed, not asserted).
TEST(Y4mReader, ReadSpeed) {
  const auto path = std::filesystem::temp_directory_path() / ("earshot_y4m_speed_" + std::to_string(::getpid()) + ".y4m");
  const int frames = 300;
  {
    std::ofstream f(path, std::ios::binary);
    f << "YUV4MPEG2 W640 H480 F30:1 Ip A1:1 C420jpeg\n";
    const std::string frame = "FRAME\n" + std::string(640 * 480 * 3 / 2, '\x40');
    for (int i = 0; i < frames; ++i) f << frame;
  }
  const auto t0 = std::chrono::steady_clock::now();
  Y4mReader r(path);
  long sum = 0, n = 0;
  for (auto f = r.next(); !f.empty(); f = r.next(), ++n) sum += f[n % f.size()];
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::filesystem::remove(path);
  EXPECT_EQ(n, frames);
  EXPECT_EQ(sum, 0x40L * frames);
  std::printf("Y4M 640x480 4:2:0: %d frames in %.1f ms (%.0f frames/s)\n", frames, s * 1e3, frames / s);
}

}  // namespace
}  // namespace earshot::tracker
