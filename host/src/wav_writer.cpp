#include "earshot/host/wav_writer.hpp"

#include <sndfile.h>

#include <string>

#include "earshot/errors.hpp"

namespace earshot::host {

void WavWriter::Close::operator()(void* f) const { sf_close(static_cast<SNDFILE*>(f)); }

WavWriter::WavWriter(const std::filesystem::path& path, int sample_rate, WavFormat format) : path_(path) {
  SF_INFO info{};
  info.samplerate = sample_rate;
  info.channels = 2;
  info.format = SF_FORMAT_WAV | (format == WavFormat::float32 ? SF_FORMAT_FLOAT : SF_FORMAT_PCM_24);
  file_.reset(sf_open(path.c_str(), SFM_WRITE, &info));
  if (!file_) throw InputError::at(path.string(), 0, "", std::string("cannot write: ") + sf_strerror(nullptr));
  sf_command(static_cast<SNDFILE*>(file_.get()), SFC_SET_ADD_PEAK_CHUNK, nullptr, SF_FALSE);
}

WavWriter::~WavWriter() = default;

void WavWriter::write_interleaved(std::span<const float> lr) {
  auto* f = static_cast<SNDFILE*>(file_.get());
  if (!f) throw InputError::at(path_.string(), 0, "", "write after close");
  const auto frames = static_cast<sf_count_t>(lr.size() / 2);
  if (sf_writef_float(f, lr.data(), frames) != frames)
    throw InputError::at(path_.string(), 0, "", std::string("write failed: ") + sf_strerror(f));
}

void WavWriter::close() {
  if (!file_) return;
  if (const int e = sf_close(static_cast<SNDFILE*>(file_.release())); e != 0)
    throw InputError::at(path_.string(), 0, "", std::string("write failed: ") + sf_error_number(e));
}

void WavWriter::write(std::span<const float> left, std::span<const float> right) {
  interleaved_.resize(2 * left.size());
  for (std::size_t i = 0; i < left.size(); ++i) {
    interleaved_[2 * i] = left[i];
    interleaved_[2 * i + 1] = right[i];
  }
  write_interleaved(interleaved_);
}

}  // namespace earshot::host
