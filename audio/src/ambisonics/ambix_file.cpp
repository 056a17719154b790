#include "earshot/audio/ambisonics/ambix_file.hpp"

#include <sndfile.h>

#include <algorithm>
#include <string>

#include "earshot/errors.hpp"

namespace earshot::ambisonics {

struct AmbixReader::File {
  SNDFILE* f = nullptr;
  ~File() {
    if (f) sf_close(f);
  }
};

namespace {
std::string allowed_counts(Convention c) {
  if (c == Convention::fuma) return "4, 9 or 16 (FuMa orders 1..3)";
  std::string s;
  for (int n = 1; n <= kMaxOrder; ++n) s += (n > 1 ? (n == kMaxOrder ? " or " : ", ") : "") + std::to_string(channel_count(n));
  return s + ": (N + 1)^2";
}
}  // namespace

AmbixReader::AmbixReader(const std::filesystem::path& path, Convention convention)
    : path_(path), file_(std::make_unique<File>()) {
  const std::string name = path.string();
  SF_INFO info{};
  file_->f = sf_open(name.c_str(), SFM_READ, &info);
  if (!file_->f) throw InputError::at(name, 0, "", std::string("cannot open: ") + sf_strerror(nullptr));
  const auto ch = static_cast<std::size_t>(std::max(info.channels, 0));
  const int order = order_from_channels(ch);
  if (order < 1 || (convention == Convention::fuma && order > kMaxFumaOrder))
    throw InputError::at(name, 0, "channels",
                         std::to_string(ch) + " channel" + (ch == 1 ? "" : "s") + " is not an Ambisonic signal in " +
                             std::string(convention_name(convention)) + " (" + allowed_counts(convention) + ")");
  order_ = order;
  rate_ = info.samplerate;
  frames_ = static_cast<std::size_t>(std::max<sf_count_t>(info.frames, 0));
  map_ = to_ambix(convention, order);
}

AmbixReader::~AmbixReader() = default;
AmbixReader::AmbixReader(AmbixReader&&) noexcept = default;
AmbixReader& AmbixReader::operator=(AmbixReader&&) noexcept = default;

std::size_t AmbixReader::read(std::span<float> out, std::size_t frames) {
  const std::size_t C = channels();
  if (out.size() < C * frames) throw std::invalid_argument("AmbixReader::read: output smaller than channels x frames");
  interleaved_.resize(C * frames);
  const sf_count_t got = sf_readf_float(file_->f, interleaved_.data(), static_cast<sf_count_t>(frames));
  if (got < 0) throw InputError::at(path_.string(), 0, "", std::string("read error: ") + sf_strerror(file_->f));
  const auto n = static_cast<std::size_t>(got);
  for (std::size_t c = 0; c < C; ++c) {
    const std::size_t s = map_.source[c];
    const auto g = static_cast<float>(map_.gain[c]);
    float* dst = out.data() + c * frames;
    for (std::size_t i = 0; i < n; ++i) dst[i] = g * interleaved_[i * C + s];
    std::fill(dst + n, dst + frames, 0.0f);
  }
  return n;
}

AmbixSignal read_ambix(const std::filesystem::path& path, Convention convention) {
  AmbixReader r(path, convention);
  AmbixSignal s;
  s.order = r.order();
  s.sample_rate = r.sample_rate();
  s.frames = r.frames();
  s.samples.assign(r.channels() * s.frames, 0.0f);
  if (s.frames) (void)r.read(s.samples, s.frames);
  return s;
}

}  // namespace earshot::ambisonics
