#include "binaural_panner.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace earshot::lv2 {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

audio::RendererConfig renderer_config(double rate) {
  audio::RendererConfig c;
  c.sample_rate = rate;
  c.block = BinauralPanner::kBlock;
  c.max_sources = 1;
  // No propagation delay: a panner's distance knob must not glide the pitch
  // or move the signal in time; distance is heard as level (and the room).
  c.doppler_factor = 0.0;
  return c;
}

}  // namespace

Vec3 position_of(double azimuth_deg, double elevation_deg, double distance_m) {
  const double az = azimuth_deg * kDeg, el = elevation_deg * kDeg;
  return {-distance_m * std::sin(az) * std::cos(el), distance_m * std::sin(el),
          -distance_m * std::cos(az) * std::cos(el)};
}

BinauralPanner::BinauralPanner(const audio::PreparedHrtf& hrtf, double sample_rate, std::string hrtf_path)
    : rate_(sample_rate),
      hrtf_path_(std::move(hrtf_path)),
      hrtf_(hrtf),
      renderer_(hrtf, renderer_config(sample_rate)),
      room_(sample_rate, kBlock, audio::room_preset("generic")),
      in_(kBlock, 0.0f),
      out_l_(kBlock, 0.0f),
      out_r_(kBlock, 0.0f) {
  source_ = renderer_.add_source(audio::SourceState{});
  update(PannerParams{});
}

BinauralPanner::~BinauralPanner() = default;

void BinauralPanner::update(const PannerParams& p) {
  audio::SourceState s;
  s.position = position_of(p.azimuth_deg, p.elevation_deg, std::max(p.distance_m, 0.0));
  s.gain = std::pow(10.0, p.gain_db / 20.0);
  s.distance.model = p.distance_model;
  s.reverb_send = p.room > 0 && p.reverb_send_db > kReverbOffDb ? std::pow(10.0, p.reverb_send_db / 20.0) : 0.0;
  renderer_.set_source(source_, s);

  HeadPose l;
  l.orientation = normalised(p.head_orientation).value_or(Quat{1, 0, 0, 0});
  l.position = p.head_position;
  renderer_.set_listener(l);

  const auto presets = audio::room_presets();
  const int room = std::clamp(p.room, 0, static_cast<int>(presets.size()));
  if (room != room_index_) {
    if (room > 0) {
      room_.update(presets[static_cast<std::size_t>(room - 1)].params);  // shipped presets are valid
      room_.reset();  // a new room starts from silence, not from the old one's tail
    }
    room_index_ = room;
  }
}

void BinauralPanner::process(const float* in, float* left, float* right, std::size_t frames) {
  std::size_t done = 0;
  while (done < frames) {
    const std::size_t n = std::min(frames - done, kBlock - fill_);
    // Input first: the host may pass the same buffer for input and output.
    std::copy_n(in + done, n, in_.begin() + static_cast<std::ptrdiff_t>(fill_));
    std::copy_n(out_l_.begin() + static_cast<std::ptrdiff_t>(fill_), n, left + done);
    std::copy_n(out_r_.begin() + static_cast<std::ptrdiff_t>(fill_), n, right + done);
    fill_ += n;
    done += n;
    if (fill_ == kBlock) {
      render_block();
      fill_ = 0;
    }
  }
}

void BinauralPanner::render_block() {
  const auto input = renderer_.source_input(source_);
  std::copy(in_.begin(), in_.end(), input.begin());
  renderer_.render(out_l_, out_r_);
  // The room's return joins the next block's mix, as in `earshot render`.
  if (room_index_ > 0) room_.process(renderer_.reverb_send(), renderer_.return_left(), renderer_.return_right());
}

void BinauralPanner::reset() {
  std::fill(in_.begin(), in_.end(), 0.0f);
  std::fill(out_l_.begin(), out_l_.end(), 0.0f);
  std::fill(out_r_.begin(), out_r_.end(), 0.0f);
  fill_ = 0;
  room_.reset();
}

}  // namespace earshot::lv2
