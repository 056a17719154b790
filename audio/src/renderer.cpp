#include "earshot/audio/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <optional>
#include <stdexcept>

namespace earshot::audio {

/// A point as the listener's head sees it: the unit vector towards it in
/// SOFA's frame (x ahead, y left, z up; zero when it is at the head) and
/// its distance. No trigonometry.
struct Renderer::HeadFrame {
  Vec3 direction{0, 0, 0};
  double distance = 0.0;
};

namespace {

using HeadFrame = Renderer::HeadFrame;

/// The frame of a head-relative source: the listener at the origin, unturned.
constexpr HeadPose kAtOrigin{};

HeadFrame head_frame(const Vec3& point, const HeadPose& l) {
  const Vec3 d{point[0] - l.position[0], point[1] - l.position[1], point[2] - l.position[2]};
  const Vec3 h = rotate_inverse(l.orientation, d);
  // Head frame (OpenAL): +x right, +y up, -z ahead. SOFA: x ahead, y left, z up.
  const double sx = -h[2], sy = -h[0], sz = h[1];
  HeadFrame f;
  f.distance = std::sqrt(sx * sx + sy * sy + sz * sz);
  if (f.distance > 0.0) f.direction = {sx / f.distance, sy / f.distance, sz / f.distance};
  return f;
}

}  // namespace

HeadRelative head_relative(const Vec3& point, const HeadPose& l) {
  const HeadFrame f = head_frame(point, l);
  HeadRelative r;
  r.distance = f.distance;
  r.azimuth = f.distance > 0.0 ? std::atan2(f.direction[1], f.direction[0]) : 0.0;
  r.elevation = std::asin(std::clamp(f.direction[2], -1.0, 1.0));
  return r;
}

struct Renderer::Voice {
  Voice(std::size_t block, double max_delay, double rate)
      : air(rate), delay(block, max_delay), input(block, 0.0f), ear_l(block), ear_r(block),
        near(std::make_unique<Near>(block)) {}
  SourceState state;
  AirAbsorption air;
  FractionalDelay delay;  // the source's signal, read once per ear (propagation delay plus that ear's ITD)
  std::vector<float> input;
  AlignedVector<float> ear_l, ear_r;  // what each ear hears before its filter
  double gain = -1.0;  // previous block's gain, ramped to avoid zipper noise
  std::array<double, 2> ear_delay{-1.0, -1.0};  // previous block's delay per ear, samples (< 0: none yet)
  std::uint32_t triangle = hrtf::SphereTriangulation::kNoHint;  // where the direction was last block
  Vec3 direction{2, 2, 2};           // head-frame direction of `recipe` (none yet: not a unit vector)
  hrtf::Interpolation recipe{};           // measurements, weights and delays for that direction
  // A near source (nearer than the farthest shell): each ear has its own
  // direction (parallax); `recipe` is then the left ear's and near->recipe_r
  // the right's. Kept apart from the voice, which is prefetched whole every
  // block, so far sources do not stream it.
  bool split = false;
  std::size_t shell = 0;  // the shell the recipes are in
  struct Near {
    explicit Near(std::size_t block) : filter_l(block), filter_r(block) {}
    Vec3 direction_r{2, 2, 2};
    hrtf::Interpolation recipe_r{};
    std::uint32_t triangle_r = hrtf::SphereTriangulation::kNoHint;
    std::array<double, 2> shift{0.0, 0.0};  // seconds added to each ear's delay (near_field.hpp)
    NearFieldFilter filter_l, filter_r;     // the near-field level, per ear
    std::array<NearFieldTable::GridPoint, 2> grid{};  // where each ear's taps were last computed
    std::array<float, NearFieldTable::kTaps> taps{};
  };
  std::unique_ptr<Near> near;
  // The panning into the bank at the end of the last two blocks: which
  // measurements, and per ear the gain each got (blend weight x ear gain x
  // distance gain). This block's gains follow a quadratic B-spline through
  // them and the new ones (see pan()).
  struct Pan {
    std::array<std::array<std::uint32_t, 3>, 2> index{};  // [ear]: the same for both unless split
    std::array<std::array<float, 3>, 2> gain{};
  };
  std::array<Pan, 2> pans{};  // [0]: two blocks ago, [1]: last block
  bool panned = false;
  std::optional<Vec3> moved_from;  // the source's position in the previous block
};

Renderer::Renderer(std::shared_ptr<const hrtf::HrtfSet> hrtf, RendererConfig cfg)
    : Renderer(PreparedHrtf{hrtf, hrtf && cfg.block > 0 ? std::make_shared<const HrtfSpectra>(*hrtf, cfg.block)
                                                         : nullptr},
               cfg) {}

Renderer::Renderer(const PreparedHrtf& hrtf, RendererConfig cfg) : Renderer(hrtf, cfg, nullptr) {}

Renderer::Renderer(const PreparedHrtf& hrtf, RendererConfig cfg, std::unique_ptr<SourceBus> bus)
    : hrtf_(hrtf.set), cfg_(cfg), bus_(std::move(bus)) {
  if (!hrtf_) throw std::invalid_argument("Renderer: no HRTF set");
  if (cfg_.block == 0) throw std::invalid_argument("Renderer: block must be > 0");
  if (!hrtf.spectra || hrtf.spectra->block() != cfg_.block ||
      hrtf.spectra->measurements() != hrtf_->all_measurement_count())
    throw std::invalid_argument("Renderer: the HRTF spectra are not for this set and block");
  if (std::abs(hrtf_->sample_rate() - cfg_.sample_rate) > 0.5)
    throw std::invalid_argument("Renderer: HRTF set is not at the render rate");
  const double max_delay =
      cfg_.max_distance_m / cfg_.speed_of_sound * cfg_.sample_rate * std::max(0.0, cfg_.doppler_factor) +
      0.002 * cfg_.sample_rate + FractionalDelay::kMinDelay + 8;
  if (bus_) {
    // The tier: the bus's decoder is the HRTF; no bank, no near field.
    if (bus_->voices() < cfg_.max_sources) throw std::invalid_argument("Renderer: the bus takes fewer voices than max_sources");
  } else {
    bank_ = std::make_unique<DirectionBank>(hrtf.spectra);
    std::vector<double> shells(hrtf_->shell_count());
    for (std::size_t i = 0; i < shells.size(); ++i) shells[i] = hrtf_->shell(i).radius_m;
    if (cfg_.near_field) near_field_ = NearFieldTable::shared(cfg_.sample_rate, shells);
  }
  voices_.reserve(cfg_.max_sources);
  for (std::size_t i = 0; i < cfg_.max_sources; ++i)
    voices_.push_back(std::make_unique<Voice>(cfg_.block, max_delay, cfg_.sample_rate));
  for (auto* v : {&send_, &ret_l_, &ret_r_, &mix_l_, &mix_r_}) v->assign(cfg_.block, 0.0f);
}

Renderer::~Renderer() = default;

void Renderer::pan(Voice& v, const hrtf::Interpolation& in_l, const hrtf::Interpolation& in_r, double gain) {
  // Each ear's blended filter is sum_k w_k h_k scaled to the interpolated
  // energy (ear_gain); the bank applies it as gains on the measurements.
  Voice::Pan now;
  for (std::size_t ear = 0; ear < 2; ++ear) {
    const hrtf::Interpolation& in = ear == 0 ? in_l : in_r;
    now.index[ear] = in.blend.index;
    const double g = in.ear_gain(ear) * gain;
    for (std::size_t k = 0; k < 3; ++k) now.gain[ear][k] = static_cast<float>(in.blend.weight[k] * g);
  }
  if (!v.panned) {  // the first block starts where it is
    v.pans = {now, now};
    v.panned = true;
  }
  // A measurement's gain across the block is the block-long moving average
  // of the piecewise-linear path through its gains at the last three block
  // ends a, b, c: the quadratic B-spline a(1-r)^2/2 + b(1+2r-2r^2)/2 + c r^2/2,
  // r = 0..1 across the block. Its slope never jumps, so the corners where a
  // direction crosses into another triangle of measurements (and the
  // block-rate corners of a ramp) do not spread sidebands that the HRTF's
  // 2-4 kHz boost would lift; it lags the linear ramp by half a block.
  const std::array<const Voice::Pan*, 3> path{&v.pans[0], &v.pans[1], &now};
  for (std::size_t ear = 0; ear < 2; ++ear) {
    std::array<std::uint32_t, 9> seen{};
    std::size_t n_seen = 0;
    for (const Voice::Pan* p : path)
      for (const std::uint32_t m : p->index[ear])
        if (std::find(seen.begin(), seen.begin() + static_cast<std::ptrdiff_t>(n_seen), m) ==
            seen.begin() + static_cast<std::ptrdiff_t>(n_seen))
          seen[n_seen++] = m;
    const std::span<const float> x = ear == 0 ? v.ear_l : v.ear_r;
    for (std::size_t j = 0; j < n_seen; ++j) {
      std::array<float, 3> g{};  // a, b, c
      for (std::size_t t = 0; t < 3; ++t)
        for (std::size_t k = 0; k < 3; ++k)
          if (path[t]->index[ear][k] == seen[j]) g[t] = path[t]->gain[ear][k];
      if (g[0] == 0.0f && g[1] == 0.0f && g[2] == 0.0f) continue;
      bank_->add(seen[j], ear, x, {0.5f * (g[0] + g[1]), g[1] - g[0], 0.5f * (g[0] - 2.0f * g[1] + g[2])});
    }
  }
  v.pans = {v.pans[1], now};
}

int Renderer::add_source(const SourceState& s) {
  if (active_ >= voices_.size()) return -1;
  Voice& v = *voices_[active_];
  v.state = s;
  v.gain = -1.0;
  v.ear_delay = {-1.0, -1.0};
  v.triangle = hrtf::SphereTriangulation::kNoHint;
  v.direction = {2, 2, 2};
  v.split = false;
  v.shell = 0;
  v.near->direction_r = {2, 2, 2};
  v.near->triangle_r = hrtf::SphereTriangulation::kNoHint;
  v.near->shift = {0.0, 0.0};
  v.near->filter_l.reset();
  v.near->filter_r.reset();
  v.near->grid = {};
  v.panned = false;
  v.moved_from.reset();
  v.air.reset();
  v.delay.reset();
  if (bus_) bus_->reset_voice(active_);
  return static_cast<int>(active_++);
}

void Renderer::set_source(int i, const SourceState& s) {
  if (i >= 0 && static_cast<std::size_t>(i) < active_) voices_[static_cast<std::size_t>(i)]->state = s;
}

std::span<float> Renderer::source_input(int i) {
  if (i < 0 || static_cast<std::size_t>(i) >= active_) return {};
  return voices_[static_cast<std::size_t>(i)]->input;
}

void Renderer::render(std::span<float> left, std::span<float> right) {
  const HeadPose listener = listener_;  // the pose, read once per block
  const double listener_gain = listener_gain_;
  std::copy(ret_l_.begin(), ret_l_.end(), mix_l_.begin());
  std::copy(ret_r_.begin(), ret_r_.end(), mix_r_.begin());
  std::fill(ret_l_.begin(), ret_l_.end(), 0.0f);
  std::fill(ret_r_.begin(), ret_r_.end(), 0.0f);
  std::fill(send_.begin(), send_.end(), 0.0f);
  if (bus_) {
    bus_->begin_block();
    for (std::size_t s = 0; s < active_; ++s) {
      prefetch_after(s);  // the tier never pans: only the state and the delay lines
      render_to_bus(s, *voices_[s], listener, listener_gain);
    }
    bus_->mix_into(mix_l_, mix_r_);
  } else {
    for (std::size_t s = 0; s < active_; ++s) {
      prefetch_after(s);
      render_source(*voices_[s], listener, listener_gain);
    }
    bank_->process(mix_l_, mix_r_);
  }
  limit(left, right);
}

void Renderer::prefetch_after(std::size_t s) const {
  if (s + 2 < active_) {  // the state of the source after next, read below one step from now
    const auto* after = reinterpret_cast<const char*>(voices_[s + 2].get());
    for (std::size_t b = 0; b < sizeof(Voice); b += 64) __builtin_prefetch(after + b, 0, 3);
  }
  if (s + 1 < active_) {
    // With many sources, the next one's delayed samples and the bank
    // lanes it panned into have left the nearer caches: ask for them now,
    // so they arrive while this source renders.
    const Voice& next = *voices_[s + 1];
    if (next.ear_delay[0] >= 0.0) next.delay.prefetch(cfg_.block, next.ear_delay[0], next.ear_delay[1]);
    if (next.panned)
      for (const std::uint32_t m : next.pans[1].index[0]) bank_->prefetch(m);
  }
}

void Renderer::render_source(Voice& v, const HeadPose& listener, double listener_gain) {
  // A relative source's position is already head-relative.
  const HeadPose& frame = v.state.relative ? kAtOrigin : listener;
  HeadFrame hr = head_frame(v.state.position, frame);
  if (hr.distance == 0.0) hr.direction = {1, 0, 0};  // at the head: as if ahead
  // Nearer than the farthest shell: the shell nearest the source, and
  // each ear's own direction to it (near_field.hpp).
  const bool near = near_field_ && !near_field_->empty() && hr.distance < hrtf_->shell(0).radius_m;
  if (near) aim_near(v, hr);
  else aim_far(v, hr);
  const hrtf::Interpolation& right_recipe = v.split ? v.near->recipe_r : v.recipe;
  // The ITD follows every move, through the delay lines.
  hrtf::Delays d{v.recipe.delays.left_s, right_recipe.delays.right_s};
  if (v.split) d = {d.left_s + v.near->shift[0], d.right_s + v.near->shift[1]};
  const double prop = propagation_delay(v, hr, frame);
  const double g = source_gain(v, hr, frame, listener_gain);
  const double g0 = v.gain < 0.0 ? g : v.gain;
  v.gain = g;

  v.air.update(hr.distance, v.state.air_absorption);
  v.air.process(v.input);
  // Each ear hears the source late by the propagation delay plus its own
  // onset delay (the ITD); its onset-free filters are in the bank.
  v.delay.write(v.input);
  const double base = FractionalDelay::kMinDelay + prop;
  const std::array<double, 2> to{v.delay.clamp_delay(base + d.left_s * cfg_.sample_rate),
                                 v.delay.clamp_delay(base + d.right_s * cfg_.sample_rate)};
  v.delay.read(v.ear_l, v.ear_delay[0] < 0.0 ? to[0] : v.ear_delay[0], to[0]);
  v.delay.read(v.ear_r, v.ear_delay[1] < 0.0 ? to[1] : v.ear_delay[1], to[1]);
  v.ear_delay = to;
  if (near || v.near->filter_l.active() || v.near->filter_r.active()) near_field_level(v, hr);
  pan(v, v.recipe, right_recipe, g);
  add_send(v, g0, g);
}

// OpenAL's order: source gain x distance x cone, clamped to [min, max],
// then the listener's gain.
double Renderer::source_gain(const Voice& v, const HeadFrame& hr, const HeadPose& frame, double listener_gain) const {
  const Vec3& sp = v.state.position;
  const Vec3 to_listener{frame.position[0] - sp[0], frame.position[1] - sp[1], frame.position[2] - sp[2]};
  const double attenuated =
      v.state.gain * distance_gain(hr.distance, v.state.distance) * cone_gain(to_listener, v.state.cone);
  return std::clamp(attenuated, v.state.min_gain, std::max(v.state.min_gain, v.state.max_gain)) * listener_gain;
}

// The reverb send, the gain ramped across the block as the direct sound's.
void Renderer::add_send(const Voice& v, double g0, double g) {
  const std::size_t B = cfg_.block;
  const auto send = static_cast<float>(v.state.reverb_send);
  if (send != 0.0f) {
    const auto gain0 = static_cast<float>(g0), gain_step = static_cast<float>((g - g0) / static_cast<double>(B));
    for (std::size_t i = 0; i < B; ++i) send_[i] += send * (gain0 + gain_step * static_cast<float>(i + 1)) * v.input[i];
  }
}

// The Ambisonic tier: the source as the direct path has it up to the HRTF
// (distance gain, cone, air absorption, propagation delay and Doppler), one
// delay read (no ITD: the decoder's filters carry it), then into the bus
// from its direction as the head sees it.
void Renderer::render_to_bus(std::size_t index, Voice& v, const HeadPose& listener, double listener_gain) {
  const HeadPose& frame = v.state.relative ? kAtOrigin : listener;
  HeadFrame hr = head_frame(v.state.position, frame);
  if (hr.distance == 0.0) hr.direction = {1, 0, 0};  // at the head: as if ahead
  const double prop = propagation_delay(v, hr, frame);
  const double g = source_gain(v, hr, frame, listener_gain);
  const double g0 = v.gain < 0.0 ? g : v.gain;
  v.gain = g;
  v.air.update(hr.distance, v.state.air_absorption);
  v.air.process(v.input);
  v.delay.write(v.input);
  const double to = v.delay.clamp_delay(FractionalDelay::kMinDelay + prop);
  v.delay.read(v.ear_l, v.ear_delay[0] < 0.0 ? to : v.ear_delay[0], to);
  v.ear_delay = {to, to};
  bus_->add(index, hr.direction, static_cast<float>(g), v.ear_l);
  add_send(v, g0, g);
}

void Renderer::aim_far(Voice& v, const HeadFrame& hr) {
  if (hr.direction != v.direction || v.split) {
    v.recipe = hrtf_->interpolate(hr.direction, v.triangle);
    v.triangle = v.recipe.blend.triangle;
    v.direction = hr.direction;
    v.split = false;
    v.shell = 0;
  }
}

void Renderer::aim_near(Voice& v, const HeadFrame& hr) {
  const std::size_t shell = hrtf_->nearest_shell(hr.distance);
  const double R = hrtf_->shell(shell).radius_m, a = near_field_->head().radius_m;
  const double r = std::max(hr.distance, near_field_->min_distance_m());
  const Vec3 at{hr.direction[0] * r, hr.direction[1] * r, hr.direction[2] * r};
  const Vec3 dl = parallax_direction(at, a, R), dr = parallax_direction(at, -a, R);
  Voice::Near& n = *v.near;
  if (dl != v.direction || !v.split || shell != v.shell) {
    v.recipe = hrtf_->interpolate_in_shell(dl, shell, v.triangle);
    v.triangle = v.recipe.blend.triangle;
    v.direction = dl;
  }
  if (dr != n.direction_r || !v.split || shell != v.shell) {
    n.recipe_r = hrtf_->interpolate_in_shell(dr, shell, n.triangle_r);
    n.triangle_r = n.recipe_r.blend.triangle;
    n.direction_r = dr;
  }
  v.split = true;
  v.shell = shell;
  // The sphere's path to each ear from the source, less its path from
  // where that ear's HRTF was measured: the measured delays then give
  // the near ITD (zero at the shell).
  const hrtf::SphereHead& head = near_field_->head();
  const double uy = std::clamp(hr.direction[1], -1.0, 1.0);
  n.shift = {hrtf::sphere_path_delay(r, std::acos(uy), head) -
                 hrtf::sphere_path_delay(R, std::acos(std::clamp(dl[1], -1.0, 1.0)), head),
             hrtf::sphere_path_delay(r, std::acos(-uy), head) -
                 hrtf::sphere_path_delay(R, std::acos(std::clamp(-dr[1], -1.0, 1.0)), head)};
}

// Propagation delay to the listener's ear now from where the source was
// when it emitted: d = DF r / (c + DF r_s'), with r_s' the rate at which
// the source's own motion changes the distance. Gliding the delay line by
// that gives OpenAL's Doppler shift, f (c - DF v_l) / (c - DF v_s).
double Renderer::propagation_delay(Voice& v, const HeadFrame& hr, const HeadPose& frame) const {
  double rate_src = 0.0;
  if (v.moved_from) {
    const Vec3& p = *v.moved_from;
    const double dx = p[0] - frame.position[0], dy = p[1] - frame.position[1], dz = p[2] - frame.position[2];
    rate_src = (hr.distance - std::sqrt(dx * dx + dy * dy + dz * dz)) * cfg_.sample_rate / static_cast<double>(cfg_.block);
  }
  v.moved_from = v.state.position;
  const double c = cfg_.speed_of_sound;
  const double approach = std::max(cfg_.doppler_factor * rate_src, -0.5 * c);  // no sonic booms
  return cfg_.doppler_factor * hr.distance / (c + approach) * cfg_.sample_rate;
}

// Each ear's level from the sphere model, for its angle to the source; new
// taps only once the source has moved a fraction of a grid cell.
void Renderer::near_field_level(Voice& v, const HeadFrame& hr) {
  Voice::Near& n = *v.near;
  const double uy = std::clamp(hr.direction[1], -1.0, 1.0);
  const std::span<const float> taps(n.taps);
  for (std::size_t ear = 0; ear < 2; ++ear) {
    NearFieldFilter& filter = ear == 0 ? n.filter_l : n.filter_r;
    const std::span<float> x = ear == 0 ? std::span<float>(v.ear_l) : std::span<float>(v.ear_r);
    const NearFieldTable::GridPoint at = near_field_->locate(v.shell, hr.distance, std::acos(ear == 0 ? uy : -uy));
    if (!NearFieldTable::moved_enough(n.grid[ear], at)) {
      filter.hold(x);
      continue;
    }
    if (at.on) near_field_->taps_at(at, n.taps);
    filter.process(x, at.on ? taps : std::span<const float>{});
    n.grid[ear] = at;
  }
}

// Master gain, then a peak limiter: instant attack, ~50 ms release, and a
// final clamp so nothing ever leaves beyond full scale; NaN becomes silence.
void Renderer::limit(std::span<float> left, std::span<float> right) {
  constexpr double kCeiling = 0.98;
  const double release = std::exp(-1.0 / (0.05 * cfg_.sample_rate));
  for (std::size_t i = 0; i < cfg_.block; ++i) {
    double l = mix_l_[i] * cfg_.master_gain, r = mix_r_[i] * cfg_.master_gain;
    if (!std::isfinite(l)) l = 0.0;
    if (!std::isfinite(r)) r = 0.0;
    const double peak = std::max(std::abs(l), std::abs(r));
    const double needed = peak * limiter_gain_ > kCeiling ? kCeiling / peak : 1.0;
    limiter_gain_ = needed < limiter_gain_ ? needed : 1.0 - (1.0 - limiter_gain_) * release;
    left[i] = static_cast<float>(std::clamp(l * limiter_gain_, -1.0, 1.0));
    right[i] = static_cast<float>(std::clamp(r * limiter_gain_, -1.0, 1.0));
  }
}

}  // namespace earshot::audio
