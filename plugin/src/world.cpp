#include "world.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>

#include "earshot/audio/ambisonics/ambisonic_bus.hpp"
#include "earshot/audio/ambisonics/decoder_cache.hpp"
#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/audio/crossfade.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "earshot/tracker/live/live_tracker.hpp"
#include "earshot/geometry.hpp"
#include "earshot/tracker/live/source_spec.hpp"
#include "earshot/tracker/live/tracker_options.hpp"
#include "tracker_state.hpp"

namespace earshot::plugin {
namespace {

constexpr ESenum state_of(unsigned i) {
  constexpr std::array<ESenum, 4> states{ES_INITIAL, ES_PLAYING, ES_PAUSED, ES_STOPPED};
  return states[i & 3u];
}
constexpr unsigned index_of(ESenum s) {
  return s == ES_PLAYING ? 1u : s == ES_PAUSED ? 2u : s == ES_STOPPED ? 3u : 0u;
}

}  // namespace

World::World(const ESworldparams& p) : params_(p), control_thread_(std::this_thread::get_id()) {
  // The set's prepared data is shared with every other world of the
  // process that uses the same file, rate and block (audio/hrtf_cache.hpp).
  audio::PreparedHrtf hrtf;
  try {
    std::optional<double> radius;
    if (p.head_radius_m > 0.0f) radius = static_cast<double>(p.head_radius_m);
    hrtf = audio::HrtfCache::shared().get(p.hrtf_path ? p.hrtf_path : hrtf::HrtfSet::kDefaultPath,
                                          static_cast<double>(p.sample_rate), p.block_size, radius);
  } catch (const std::exception& e) {
    throw Failure{ES_HRTF_ERROR, e.what()};
  }
  audio::RendererConfig cfg;
  cfg.sample_rate = p.sample_rate;
  cfg.block = p.block_size;
  cfg.max_sources = p.max_sources;
  cfg.speed_of_sound = p.speed_of_sound;
  cfg.doppler_factor = propagation_delay() ? p.doppler_factor : 0.0;
  renderer_config_ = cfg;
  hrtf_path_ = p.hrtf_path ? p.hrtf_path : "";
  hrtf_ = hrtf;
  renderers_ = audio::CrossfadeSwitch<audio::Renderer>(make_renderer());
  fade_l_.assign(cfg.block, 0.0f);
  fade_r_.assign(cfg.block, 0.0f);
  const audio::LateReverbType late =
      p.late_reverb == ES_REVERB_SCHROEDER ? audio::LateReverbType::schroeder : audio::LateReverbType::fdn;
  control_.room = audio::room_preset("generic");
  room_ = std::make_unique<audio::RoomReverb>(cfg.sample_rate, cfg.block, control_.room, late);
  control_.doppler_factor = p.doppler_factor;
  control_.speed_of_sound = p.speed_of_sound;
  control_.sources.assign(p.max_sources, SourceParams{});
  for (auto& s : snaps_) s = control_;
  source_generation_.assign(p.max_sources, 1);
  buffers_.resize(p.max_buffers);
  playback_.assign(p.max_sources, Playback{});
  bed_voices_.reserve(p.max_sources);
  for (std::size_t i = 0; i < p.max_sources; ++i) bed_voices_.push_back(std::make_unique<BedVoice>());
  bed_gain_.assign(p.max_sources, -1.0);
  status_ = std::make_unique<std::atomic<std::uint64_t>[]>(p.max_sources);
  offsets_ = std::make_unique<std::atomic<double>[]>(p.max_sources);
  for (std::size_t i = 0; i < p.max_sources; ++i) {
    status_[i].store(0);
    offsets_[i].store(0.0);
  }
}

World::~World() {
  std::unique_ptr<audio::Renderer> in(incoming_.exchange(nullptr));
  std::unique_ptr<audio::Renderer> out(outgoing_.exchange(nullptr));
}

void World::reclaim_renderers() { std::unique_ptr<audio::Renderer> done(outgoing_.exchange(nullptr, std::memory_order_acquire)); }

void World::set_hrtf(const char* path) {
  reclaim_renderers();
  audio::PreparedHrtf hrtf;
  try {
    std::optional<double> radius;
    if (params_.head_radius_m > 0.0f) radius = static_cast<double>(params_.head_radius_m);
    hrtf = audio::HrtfCache::shared().get(path ? path : hrtf::HrtfSet::kDefaultPath,
                                          static_cast<double>(params_.sample_rate), params_.block_size, radius);
  } catch (const std::exception& e) {
    throw Failure{ES_HRTF_ERROR, e.what()};
  }
  const std::string old_path = hrtf_path_;
  const audio::PreparedHrtf old = hrtf_;
  hrtf_path_ = path ? path : "";
  hrtf_ = hrtf;
  std::unique_ptr<audio::Renderer> next;
  std::vector<std::unique_ptr<BedUnit>> beds(bed_voices_.size());
  try {
    next = make_renderer();  // the tier's decoder for the new set, when the tier is on
    for (std::size_t i = 0; i < beds.size(); ++i)
      if (const int order = bed_voices_[i]->offered_order(); order > 0)
        beds[i] = std::make_unique<BedUnit>(*decoder(order), params_.block_size);
  } catch (...) {
    hrtf_path_ = old_path;  // nothing changed
    hrtf_ = old;
    throw;
  }
  // A set handed over before and not picked up yet is replaced (and freed here).
  std::unique_ptr<audio::Renderer> unused(incoming_.exchange(next.release(), std::memory_order_acq_rel));
  for (std::size_t i = 0; i < beds.size(); ++i)
    if (beds[i]) bed_voices_[i]->offer(std::move(beds[i]));  // faded in as the renderer is
}

std::shared_ptr<const ambisonics::DecoderFilters> World::decoder(int order) const {
  std::optional<double> radius;
  if (params_.head_radius_m > 0.0f) radius = static_cast<double>(params_.head_radius_m);
  try {
    return ambisonics::DecoderCache::shared().get(hrtf_path_.empty() ? hrtf::HrtfSet::kDefaultPath : hrtf_path_,
                                                  *hrtf_.set, radius, order, design_);
  } catch (const std::exception& e) {
    throw Failure{ES_INVALID_VALUE, "no order-" + std::to_string(order) + " decoder for this HRTF set: " + e.what()};
  }
}

std::unique_ptr<audio::Renderer> World::make_renderer() const {
  if (quality_ == 0) return std::make_unique<audio::Renderer>(hrtf_, renderer_config_);
  const auto filters = decoder(quality_);
  return std::make_unique<audio::Renderer>(
      hrtf_, renderer_config_,
      std::make_unique<ambisonics::AmbisonicBus>(*filters, params_.block_size, renderer_config_.max_sources));
}

void World::set_quality(int order) {
  if (order == quality_) return;
  reclaim_renderers();
  const int old = quality_;
  quality_ = order;
  std::unique_ptr<audio::Renderer> next;
  try {
    next = make_renderer();
  } catch (...) {
    quality_ = old;
    throw;
  }
  std::unique_ptr<audio::Renderer> unused(incoming_.exchange(next.release(), std::memory_order_acq_rel));
}

void World::prepare_bed(std::size_t slot, int order) {
  BedVoice& bv = *bed_voices_[slot];
  bv.reclaim();
  if (order == 0 || bv.offered_order() == order) return;  // a point source keeps its unit for later
  bv.offer(std::make_unique<BedUnit>(*decoder(order), params_.block_size));
  bv.set_offered_order(order);
}

void World::adopt_new_renderer() {
  if (retired_ && !outgoing_.load(std::memory_order_relaxed)) outgoing_.store(retired_.release(), std::memory_order_release);
  if (renderers_.switching() || retired_) return;  // one switch at a time; a newer set waits in incoming_
  audio::Renderer* next = incoming_.exchange(nullptr, std::memory_order_acq_rel);
  if (!next) return;
  (void)renderers_.switch_to(std::unique_ptr<audio::Renderer>(next));  // adopted: released into incoming_ by set_hrtf
  // Before the first block nothing was heard: no fade (a tier chosen right
  // after esCreateWorld is the world's from its first sample).
  if (blocks_.load(std::memory_order_relaxed) == 0) renderers_.cut();
  for (std::size_t i = 0; i < voices_; ++i) {
    audio::SourceState silent;
    silent.gain = 0.0;
    (void)renderers_.current().add_source(silent);  // preallocated voices: no allocation
  }
}

void World::publish() {
  snaps_[back_] = control_;  // same sizes: copies into the existing storage
  back_ = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel) & 3u;
  reclaim_buffers();
}

// ---- sources ----

std::optional<std::size_t> World::source_slot(ESsource s) const {
  const std::size_t slot = (s & 0xFFFFu);
  if (slot == 0 || slot > control_.sources.size()) return std::nullopt;
  if (control_.sources[slot - 1].handle != s || s == 0) return std::nullopt;
  return slot - 1;
}

ESsource World::create_source() {
  for (std::size_t i = 0; i < control_.sources.size(); ++i) {
    SourceParams& sp = control_.sources[i];
    if (sp.handle != 0) continue;
    const std::uint64_t serial = sp.play_serial;  // keeps counting across lives of the slot
    sp = SourceParams{};
    sp.play_serial = serial + 1;
    sp.handle = (static_cast<ESsource>(source_generation_[i]) << 16) | static_cast<ESsource>(i + 1);
    return sp.handle;
  }
  return 0;
}

void World::delete_source(std::size_t slot) {
  SourceParams& sp = control_.sources[slot];
  const std::uint64_t serial = sp.play_serial;
  sp = SourceParams{};
  sp.play_serial = serial + 1;
  if (++source_generation_[slot] == 0) source_generation_[slot] = 1;
}

ESenum World::source_state(std::size_t slot) const {
  const SourceParams& sp = control_.sources[slot];
  const std::uint64_t st = status_[slot].load(std::memory_order_acquire);
  if ((st >> 8) == sp.play_serial) return state_of(static_cast<unsigned>(st & 0xFFu));
  return sp.play_state;
}

double World::source_offset(std::size_t slot) const {
  const SourceParams& sp = control_.sources[slot];
  const std::uint64_t st = status_[slot].load(std::memory_order_acquire);
  if ((st >> 8) != sp.play_serial) return 0.0;
  return offsets_[slot].load(std::memory_order_relaxed);
}

// ---- buffers ----

std::optional<World::BufferInfo> World::buffer(ESbuffer b) const {
  const std::size_t i = (b & 0xFFFFu);
  if (i == 0 || i > buffers_.size()) return std::nullopt;
  const Buffer& buf = buffers_[i - 1];
  if (!buf.alive || (b >> 16) != buf.generation) return std::nullopt;
  const std::size_t channels = buf.order > 0 ? ambisonics::channel_count(buf.order) : 1;
  return BufferInfo{buf.samples.data(), buf.samples.size() / channels, buf.rate / static_cast<double>(params_.sample_rate),
                    buf.order};
}

ESbuffer World::create_ambisonic_buffer(std::vector<float> planar, double rate, int order) {
  reclaim_buffers();
  for (std::size_t i = 0; i < buffers_.size(); ++i) {
    Buffer& b = buffers_[i];
    if (b.alive || !b.samples.empty()) continue;
    b.samples = std::move(planar);
    for (float& x : b.samples)
      if (!std::isfinite(x)) x = 0.0f;
    b.rate = rate;
    b.order = order;
    b.alive = true;
    return (static_cast<ESbuffer>(b.generation) << 16) | static_cast<ESbuffer>(i + 1);
  }
  return 0;
}

ESbuffer World::create_buffer(const float* samples, std::size_t frames, double rate) {
  reclaim_buffers();
  for (std::size_t i = 0; i < buffers_.size(); ++i) {
    Buffer& b = buffers_[i];
    if (b.alive || !b.samples.empty()) continue;  // in use, or waiting to be reclaimed
    b.samples.assign(samples, samples + frames);
    for (float& x : b.samples)
      if (!std::isfinite(x)) x = 0.0f;
    b.rate = rate;
    b.order = 0;
    b.alive = true;
    return (static_cast<ESbuffer>(b.generation) << 16) | static_cast<ESbuffer>(i + 1);
  }
  return 0;
}

bool World::delete_buffer(ESbuffer h) {
  for (const SourceParams& sp : control_.sources)
    if (sp.handle != 0 && sp.buffer == h) return false;
  Buffer& b = buffers_[(h & 0xFFFFu) - 1];
  b.alive = false;
  if (++b.generation == 0) b.generation = 1;
  reclaim_buffers();
  return true;
}

void World::reclaim_buffers() {
  for (Buffer& b : buffers_) {
    if (b.alive || b.samples.empty()) continue;
    const float* data = b.samples.data();
    bool used = false;
    for (const Snapshot* s : {&control_, &snaps_[0], &snaps_[1], &snaps_[2]})
      for (const SourceParams& sp : s->sources) used = used || sp.data == data;
    if (!used) std::vector<float>().swap(b.samples);
  }
}

// ---- tracking ----

void World::attach_tracker(const char* spec) { attach_tracker(spec, tracker::TrackerOptions{}); }

void World::attach_tracker(const char* spec, const tracker::TrackerOptions& options) {
  tracker_on_.store(false, std::memory_order_release);
  tracker_.reset();  // stops and joins the old one
  if (!spec || !*spec) return;
  try {
    tracker_ = std::make_unique<head::TrackedHead>(spec, tracker_slot_, options);
  } catch (const std::exception& e) {
    throw Failure{ES_TRACKER_ERROR, std::string("tracker '") + spec + "': " + e.what()};
  }
  tracker_on_.store(true, std::memory_order_release);
}

void World::tracker_image(EStrackerimage& out) const {
  if (!tracker_) {
    fill_tracker_image(nullptr, 0, 0, out);
    return;
  }
  tracker::Thumbnail th;  // on the control thread's stack: ~19 kB
  const bool has = tracker_->tracker().thumbnail(th);
  fill_tracker_image(has ? &th : nullptr, tracker_->camera_width(), tracker_->camera_height(), out);
}

void World::recenter() {
  if (tracker_) tracker_->recenter();
}

void World::tracker_state(EStrackerstate& out) const {
  if (!tracker_) {
    fill_tracker_state(nullptr, out);
    return;
  }
  const tracker::LiveTracker::Status st = tracker_->tracker().status();
  fill_tracker_state(&st, out);
}

// ---- audio thread ----

double World::doppler_shift(const SourceParams& sp, const Snapshot& s) const {
  // OpenAL 1.1, section 3.5.2: f' = f (SS - DF vls) / (SS - DF vss), with the
  // velocities projected on the line from the source to the listener (positive:
  // moving towards the listener's side) and clamped below SS / DF.
  if (propagation_delay() || s.doppler_factor <= 0.0) return 1.0;
  const Vec3 lp = sp.state.relative ? Vec3{0, 0, 0} : s.listener.position;
  const Vec3 lv = sp.state.relative ? Vec3{0, 0, 0} : s.listener_velocity;
  const Vec3 d{lp[0] - sp.state.position[0], lp[1] - sp.state.position[1], lp[2] - sp.state.position[2]};
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(len > 1e-9)) return 1.0;
  const double ss = s.speed_of_sound, df = s.doppler_factor;
  const double limit = ss / df;
  const double vls = std::min((lv[0] * d[0] + lv[1] * d[1] + lv[2] * d[2]) / len, limit);
  const double vss = std::min((sp.velocity[0] * d[0] + sp.velocity[1] * d[1] + sp.velocity[2] * d[2]) / len, limit);
  const double den = ss - df * vss;
  if (!(den > 1e-9)) return 1.0;
  const double shift = (ss - df * vls) / den;
  return std::isfinite(shift) && shift > 0.0 ? shift : 1.0;
}

namespace {
/// Play, stop, pause or rewind since the last block.
void follow_requests(World::Playback& pb, const SourceParams& sp) {
  if (pb.handle != sp.handle) pb = World::Playback{sp.handle, 0, ES_INITIAL, 0.0};
  if (pb.serial != sp.play_serial) {
    pb.serial = sp.play_serial;
    if (sp.play_state == ES_PLAYING && pb.state != ES_PAUSED) pb.position = 0.0;
    if (sp.play_state == ES_INITIAL || sp.play_state == ES_STOPPED) pb.position = 0.0;
    pb.state = sp.play_state;
  }
}
}  // namespace

void World::feed_field(std::size_t slot, const SourceParams& sp, std::span<float> planar) {
  Playback& pb = playback_[slot];
  follow_requests(pb, sp);
  std::fill(planar.begin(), planar.end(), 0.0f);
  const std::size_t C = ambisonics::channel_count(sp.order), B = params_.block_size;
  if (sp.handle != 0 && pb.state == ES_PLAYING) {
    if (sp.field_callback) {
      sp.field_callback(sp.user, planar.data(), static_cast<ESuint>(C), static_cast<ESuint>(B));
      for (float& x : planar)
        if (!std::isfinite(x)) x = 0.0f;
    } else if (sp.data && sp.frames > 0) {
      // A field has no position: no Doppler, only the rate and the pitch.
      const double step = std::clamp(sp.rate_ratio * sp.pitch, 1.0 / 256.0, 64.0);
      const std::size_t F = sp.frames;
      const auto n = static_cast<double>(F);
      for (std::size_t k = 0; k < B; ++k) {
        if (pb.position >= n) {
          if (!sp.looping) {
            pb.state = ES_STOPPED;
            pb.position = 0.0;
            break;
          }
          pb.position = std::fmod(pb.position, n);
        }
        const auto i = static_cast<std::size_t>(pb.position);
        const auto f = static_cast<float>(pb.position - static_cast<double>(i));
        const bool has_next = i + 1 < F || sp.looping;
        const std::size_t j = i + 1 < F ? i + 1 : 0;
        for (std::size_t c = 0; c < C; ++c) {  // linear interpolation, as mono buffers
          const float* ch = sp.data + c * F;
          const float a = ch[i], b = has_next ? ch[j] : 0.0f;
          planar[c * B + k] = a + (b - a) * f;
        }
        pb.position += step;
      }
    } else {
      pb.state = ES_STOPPED;  // nothing to play
    }
  }
  status_[slot].store((pb.serial << 8) | index_of(pb.state), std::memory_order_release);
  offsets_[slot].store(pb.position, std::memory_order_relaxed);
}

void World::render_bed(std::size_t slot, const SourceParams& sp, const Snapshot& s, const Quat& listener,
                       audio::Renderer& renderer, audio::Renderer* fading) {
  BedVoice& bv = *bed_voices_[slot];
  bv.adopt(blocks_.load(std::memory_order_relaxed) == 0);
  BedUnit* u = bv.current();
  if (!u || u->order() != sp.order) {  // its renderer is on its way (deferred commits): not yet
    bed_gain_[slot] = -1.0;
    return;
  }
  feed_field(slot, sp, u->input);
  // A wave from the field's direction d comes from the world's O d (O: the
  // field's orientation); a head turned by L hears it from L^-1 O d: as a
  // head turned by O^-1 L in a field fixed in the world. A relative field
  // turns with the head.
  const Quat q = sp.state.relative ? conjugate(sp.orientation) : multiply(conjugate(sp.orientation), listener);
  u->bed.set_orientation(q);
  u->bed.process(u->input, u->left, u->right);
  if (BedUnit* f = bv.fading()) {  // a new HRTF set's decoder fading in: the old one hears the same field
    std::copy(u->input.begin(), u->input.end(), f->input.begin());
    f->bed.set_orientation(q);
    f->bed.process(f->input, f->left, f->right);
    bv.blend(u->left, u->right, f->left, f->right);
  }
  // OpenAL's gain for a field: the source's, clamped to [min, max], then
  // the listener's; no distance, no cone. Ramped across the block.
  const double g = std::clamp(sp.state.gain, sp.state.min_gain, std::max(sp.state.min_gain, sp.state.max_gain)) *
                   s.listener_gain;
  const double g0 = bed_gain_[slot] < 0.0 ? g : bed_gain_[slot];
  bed_gain_[slot] = g;
  const std::size_t B = params_.block_size;
  const auto gain0 = static_cast<float>(g0), step = static_cast<float>((g - g0) / static_cast<double>(B));
  // Into the mix of this block, before the limiter (the renderers' return
  // buffers are added at the start of their render).
  for (audio::Renderer* r : {&renderer, fading}) {
    if (!r) continue;
    const std::span<float> ml = r->return_left(), mr = r->return_right();
    for (std::size_t k = 0; k < B; ++k) {
      const float gk = gain0 + step * static_cast<float>(k + 1);
      ml[k] += gk * u->left[k];
      mr[k] += gk * u->right[k];
    }
  }
}

void World::feed(std::size_t slot, const SourceParams& sp, std::span<float> in, double shift) {
  Playback& pb = playback_[slot];
  follow_requests(pb, sp);
  std::fill(in.begin(), in.end(), 0.0f);
  if (sp.handle != 0 && pb.state == ES_PLAYING) {
    if (sp.callback) {
      sp.callback(sp.user, in.data(), static_cast<ESuint>(in.size()));
      for (float& x : in)
        if (!std::isfinite(x)) x = 0.0f;
    } else if (sp.data && sp.frames > 0) {
      const double step = std::clamp(sp.rate_ratio * sp.pitch * shift, 1.0 / 256.0, 64.0);
      const auto n = static_cast<double>(sp.frames);
      for (float& x : in) {
        if (pb.position >= n) {
          if (!sp.looping) {
            pb.state = ES_STOPPED;
            pb.position = 0.0;
            break;
          }
          pb.position = std::fmod(pb.position, n);
        }
        const auto i = static_cast<std::size_t>(pb.position);
        const double f = pb.position - static_cast<double>(i);
        const float a = sp.data[i];
        const float b = i + 1 < sp.frames ? sp.data[i + 1] : (sp.looping ? sp.data[0] : 0.0f);
        x = static_cast<float>(a + (b - a) * f);  // linear interpolation
        pb.position += step;
      }
    } else {
      pb.state = ES_STOPPED;  // nothing to play
    }
  }
  status_[slot].store((pb.serial << 8) | index_of(pb.state), std::memory_order_release);
  offsets_[slot].store(pb.position, std::memory_order_relaxed);
}

void World::render(float* left, float* right) {
  if (middle_.load(std::memory_order_acquire) & kFresh)
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & 3u;
  const Snapshot& s = snaps_[front_];

  // The head: the tracker's newest pose carried on to when this block is
  // heard (the pose is a camera frame, the tracker and this buffer old by
  // then), else the host's.
  HeadPose head;
  head.position = s.head_position;
  head.orientation = s.head_orientation;
  if (tracker_on_.load(std::memory_order_acquire)) {
    const HeadPose heard = head_reader_.read(
        tracker_slot_, {.predict = predict_head_.load(std::memory_order_relaxed), .lead_s = output_latency_s()});
    head.position = heard.position;
    head.orientation = heard.orientation;
  }
  adopt_new_renderer();
  audio::Renderer& renderer = renderers_.current();
  audio::Renderer* const fading = renderers_.fading();  // the old set during a switch, else null
  const HeadPose l = head::compose(s.listener, head);
  renderer.set_listener(l, s.listener_gain);
  if (fading) fading->set_listener(l, s.listener_gain);
  head.state = PoseState::tracking;
  head.t = static_cast<double>(blocks_.load(std::memory_order_relaxed)) * static_cast<double>(params_.block_size) /
           static_cast<double>(params_.sample_rate);
  (void)used_pose_.publish(head);

  // Sources: renderer voices are added as slots come into use (no allocation).
  std::size_t highest = 0;
  for (std::size_t i = 0; i < s.sources.size(); ++i)
    if (s.sources[i].handle != 0) highest = i + 1;
  while (voices_ < highest) {
    audio::SourceState silent;
    silent.gain = 0.0;
    (void)renderer.add_source(silent);
    if (fading) (void)fading->add_source(silent);
    ++voices_;
  }
  for (std::size_t i = 0; i < voices_; ++i) {
    const SourceParams& sp = s.sources[i];
    audio::SourceState st = sp.state;
    const bool field = sp.handle != 0 && sp.order > 0;
    if (sp.handle == 0 || field) {  // a field's voice stays silent: its bed renders it
      st = audio::SourceState{};
      st.position = s.sources[i].state.position;
      st.gain = 0.0;
    }
    renderer.set_source(static_cast<int>(i), st);
    if (field) {
      const std::span<float> in = renderer.source_input(static_cast<int>(i));
      std::fill(in.begin(), in.end(), 0.0f);
      render_bed(i, sp, s, l.orientation, renderer, fading);
    } else {
      bed_gain_[i] = -1.0;
      feed(i, sp, renderer.source_input(static_cast<int>(i)), doppler_shift(sp, s));
    }
    if (fading) {  // the old set hears the same input
      fading->set_source(static_cast<int>(i), st);
      const auto from = renderer.source_input(static_cast<int>(i));
      std::copy(from.begin(), from.end(), fading->source_input(static_cast<int>(i)).begin());
    }
  }

  std::span<float> l_out(left, params_.block_size), r_out(right, params_.block_size);
  renderer.render(l_out, r_out);
  if (fading) {
    fading->render(fade_l_, fade_r_);
    renderers_.blend(l_out, r_out, fade_l_, fade_r_);
  }

  // The room on the send bus, back into the next block's mix (as earshot render).
  if (s.room_serial != room_serial_seen_) {
    room_serial_seen_ = s.room_serial;
    try {
      room_->update(s.room);  // validated on the control side: does not throw
    } catch (...) {
    }
  }
  if (s.reverb_enabled) {
    if (!reverb_was_on_) room_->reset();
    room_->process(renderer.reverb_send(), renderer.return_left(), renderer.return_right());
    if (renderers_.fading()) {  // the room returns into both mixes (their weights sum to one)
      std::copy(renderer.return_left().begin(), renderer.return_left().end(), fading->return_left().begin());
      std::copy(renderer.return_right().begin(), renderer.return_right().end(), fading->return_right().begin());
    }
  }
  if (auto done = renderers_.finished()) {
    // Faded out: back to the control side to be freed (or held until the slot is free).
    if (!outgoing_.load(std::memory_order_relaxed)) outgoing_.store(done.release(), std::memory_order_release);
    else retired_ = std::move(done);
  }
  reverb_was_on_ = s.reverb_enabled;
  blocks_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace earshot::plugin
