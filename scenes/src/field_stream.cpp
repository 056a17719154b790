#include "earshot/scenes/field_stream.hpp"

#include <samplerate.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "earshot/errors.hpp"

namespace earshot::scenes {
namespace {
constexpr std::size_t kChunk = 4096;  // frames read from the file at a time
}  // namespace

ambisonics::Convention bed_convention(const SceneBed& bed) {
  if (bed.convention == "n3d") return ambisonics::Convention::n3d;
  if (bed.convention == "fuma") return ambisonics::Convention::fuma;
  return ambisonics::Convention::ambix;
}

Scene scene_of_field(const std::filesystem::path& file, const std::string& convention) {
  SceneBed bed;
  bed.name = file.filename().string();
  bed.path = file;
  bed.convention = convention;
  const ambisonics::AmbixReader reader(bed.path, bed_convention(bed));  // throws, naming the file
  Scene s;
  s.origin = file.string();
  s.description = "the Ambisonic file " + file.string();
  s.sample_rate = reader.sample_rate();
  s.duration_s = static_cast<double>(reader.frames()) / reader.sample_rate();
  s.beds.push_back(bed);
  return s;
}

struct FieldStream::Resampler {
  SRC_STATE* state = nullptr;
  double ratio = 1.0;
  ~Resampler() {
    if (state) src_delete(state);
  }
};

FieldStream::FieldStream(const SceneBed& bed, double sample_rate) : bed_(bed), rate_(sample_rate) {
  reader_ = std::make_unique<ambisonics::AmbixReader>(bed_.path, bed_convention(bed_));  // throws, naming the file
  order_ = reader_->order();
  channels_ = reader_->channels();
  file_rate_ = reader_->sample_rate();
  file_frames_ = reader_->frames();
  if (!(file_rate_ > 0)) throw InputError::at(bed_.path.string(), 0, "", "no sample rate");
  if (std::abs(file_rate_ - rate_) > 1e-9) {
    src_ = std::make_unique<Resampler>();
    int err = 0;
    src_->state = src_new(SRC_SINC_MEDIUM_QUALITY, static_cast<int>(channels_), &err);
    src_->ratio = rate_ / file_rate_;
    if (!src_->state || src_is_valid_ratio(src_->ratio) == 0)
      throw InputError::at(bed_.path.string(), 0, "",
                           "cannot resample from " + std::to_string(file_rate_) + " Hz to " + std::to_string(rate_) +
                               " Hz" + (err ? std::string(": ") + src_strerror(err) : ""));
  }
  planar_.resize(channels_ * kChunk);
  in_.resize(channels_ * kChunk);
}

FieldStream::~FieldStream() = default;

void FieldStream::reopen() { reader_ = std::make_unique<ambisonics::AmbixReader>(bed_.path, bed_convention(bed_)); }

std::size_t FieldStream::fill_input() {
  in_frames_ = in_used_ = 0;
  if (file_done_) return 0;
  std::size_t got = reader_->read(planar_, kChunk);
  if (got == 0 && bed_.loop && file_frames_ > 0) {
    reopen();
    got = reader_->read(planar_, kChunk);
  }
  if (got == 0) {
    file_done_ = true;
    return 0;
  }
  for (std::size_t c = 0; c < channels_; ++c)
    for (std::size_t i = 0; i < got; ++i) in_[i * channels_ + c] = planar_[c * kChunk + i];
  in_frames_ = got;
  return got;
}

std::size_t FieldStream::read(std::span<float> out, std::size_t frames) {
  frames = std::min(frames, out.size() / std::max<std::size_t>(channels_, 1));
  std::size_t done = 0;
  while (done < frames && !ended_) {
    if (in_used_ == in_frames_) fill_input();
    const std::size_t avail = in_frames_ - in_used_;
    if (!src_) {
      if (avail == 0) {
        ended_ = true;
        break;
      }
      const std::size_t n = std::min(avail, frames - done);
      std::copy_n(in_.begin() + static_cast<std::ptrdiff_t>(in_used_ * channels_), n * channels_,
                  out.begin() + static_cast<std::ptrdiff_t>(done * channels_));
      in_used_ += n;
      done += n;
      continue;
    }
    SRC_DATA d{};
    d.data_in = in_.data() + in_used_ * channels_;
    d.input_frames = static_cast<long>(avail);
    d.data_out = out.data() + done * channels_;
    d.output_frames = static_cast<long>(frames - done);
    d.end_of_input = file_done_ ? 1 : 0;
    d.src_ratio = src_->ratio;
    if (const int err = src_process(src_->state, &d); err != 0)
      throw InputError::at(bed_.path.string(), 0, "", std::string("cannot resample: ") + src_strerror(err));
    in_used_ += static_cast<std::size_t>(d.input_frames_used);
    done += static_cast<std::size_t>(d.output_frames_gen);
    if (file_done_ && d.output_frames_gen == 0) ended_ = true;
  }
  return done;
}

}  // namespace earshot::scenes
