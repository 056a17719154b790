// Random call sequences through the plugin's C API: every call must return a
// code (no crash, no sanitizer report), and every rendered block must stay
// finite and within full scale whatever came before it. One world lives for
// the whole run (loading the HRTF per input would be too slow); each input
// starts by deleting what the previous one left.
//
// Input: a sequence of operations, one opcode byte each followed by its
// argument bytes (handles picked from the live ones, stale ones or raw
// bytes; floats raw, so NaN and infinity come up, or from a table of edges).
// esGetTrackerState and esGetTrackerImage get any struct size and NULL;
// their answers must be whole. Ambisonic fields (ABI 1.5): buffers of any
// order, layout and scaling with raw samples, field callbacks writing
// garbage, the tier and the decoder chosen with any value.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "earshot/earshot.h"

namespace {

constexpr ESuint kBlock = 64;

class Bytes {
 public:
  Bytes(const std::uint8_t* d, std::size_t n) : d_(d), n_(n) {}
  [[nodiscard]] bool empty() const { return i_ >= n_; }
  std::uint8_t u8() { return i_ < n_ ? d_[i_++] : 0; }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v = (v << 8) | u8();
    return v;
  }
  float f32() {
    const std::uint8_t how = u8();
    if (how < 128) {  // an edge value
      static constexpr std::array<float, 16> edges = {0.0f, 1.0f, -1.0f, 0.5f, 2.0f, 360.0f, 1e-7f, 1e7f,
                                                      1e30f, -1e30f, 343.3f, 0.0625f, 16.0f, 10.0f, 100.0f, -0.0f};
      return edges[how % edges.size()];
    }
    const std::uint32_t bits = u32();  // anything, NaN and infinity included
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }

 private:
  const std::uint8_t* d_;
  std::size_t n_, i_ = 0;
};

struct State {
  ESworld world = 0, dead_world = 0;
  std::vector<ESsource> sources, dead_sources;
  std::vector<ESbuffer> buffers, dead_buffers;
};

State& state() {
  static State s = [] {
    State st;
    ESworldparams p;
    esWorldParamsDefault(&p);
    p.block_size = kBlock;
    p.max_sources = 6;
    p.max_buffers = 6;
    if (esCreateWorld(&p, &st.dead_world) != ES_OK || esDestroyWorld(st.dead_world) != ES_OK) std::abort();
    if (esCreateWorld(&p, &st.world) != ES_OK) std::abort();
    return st;
  }();
  return s;
}

constexpr std::array<ESenum, 25> kParams = {
    ES_AMBISONIC_ORDER,
    ES_POSITION, ES_VELOCITY, ES_GAIN, ES_ORIENTATION, ES_ORIENTATION_QUAT, ES_SOURCE_RELATIVE,
    ES_CONE_INNER_ANGLE, ES_CONE_OUTER_ANGLE, ES_PITCH, ES_DIRECTION, ES_LOOPING, ES_BUFFER,
    ES_MIN_GAIN, ES_MAX_GAIN, ES_SOURCE_STATE, ES_REFERENCE_DISTANCE, ES_ROLLOFF_FACTOR,
    ES_CONE_OUTER_GAIN, ES_MAX_DISTANCE, ES_SAMPLE_OFFSET, ES_DISTANCE_MODEL, ES_REVERB_SEND,
    ES_AIR_ABSORPTION_FACTOR, 0x7777};
constexpr std::array<ESenum, 16> kReverbParams = {
    ES_REVERB_DENSITY, ES_REVERB_DIFFUSION, ES_REVERB_GAIN, ES_REVERB_GAINHF, ES_REVERB_DECAY_TIME,
    ES_REVERB_DECAY_HFRATIO, ES_REVERB_REFLECTIONS_GAIN, ES_REVERB_REFLECTIONS_DELAY, ES_REVERB_LATE_REVERB_GAIN,
    ES_REVERB_LATE_REVERB_DELAY, ES_REVERB_HFREFERENCE, ES_REVERB_WET_DB, ES_REVERB_DRY_DB, ES_REVERB_ENABLED,
    ES_COMMIT_MODE, 0};
constexpr std::array<const char*, 5> kPresets = {"generic", "concert-hall", "padded-cell", "hangar", "no-such-room"};

template <typename T>
T pick(Bytes& in, const std::vector<T>& live, const std::vector<T>& dead) {
  const std::uint8_t how = in.u8();
  if (how < 160 && !live.empty()) return live[how % live.size()];
  if (how < 220 && !dead.empty()) return dead[how % dead.size()];
  return in.u32();
}

ESint int_value(Bytes& in, const State& s) {
  const std::uint8_t how = in.u8();
  if (how < 64) return how % 2;                                               // ES_TRUE / ES_FALSE
  if (how < 128) return ES_NONE + (how % 8 == 0 ? 0 : 0xD000 + how % 8);      // distance models
  if (how < 192 && !s.buffers.empty()) return static_cast<ESint>(s.buffers[how % s.buffers.size()]);
  return static_cast<ESint>(in.u32());
}

void garbage(void* user, float* out, ESuint frames) {
  const auto seed = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(user));
  for (ESuint i = 0; i < frames; ++i) {
    std::uint32_t bits = seed * 2654435761u + i * 40503u;
    std::memcpy(&out[i], &bits, sizeof(float));  // NaN, infinity, huge: all must be survived
  }
}

void garbage_field(void* user, float* out, ESuint channels, ESuint frames) {
  for (ESuint c = 0; c < channels; ++c) garbage(static_cast<char*>(user) + c, out + std::size_t{c} * frames, frames);
}

void render_and_check(ESworld w) {
  static std::array<float, kBlock> l, r;
  const ESenum e = esRender(w, l.data(), r.data(), kBlock);
  if (e != ES_OK) std::abort();
  for (ESuint i = 0; i < kBlock; ++i)
    if (!std::isfinite(l[i]) || !std::isfinite(r[i]) || std::abs(l[i]) > 1.0f || std::abs(r[i]) > 1.0f) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  State& s = state();
  const ESworld w = s.world;
  // Start clean: stop and delete what the last input left, immediate mode.
  esWorldi(w, ES_COMMIT_MODE, ES_IMMEDIATE);
  esWorldi(w, ES_QUALITY, ES_QUALITY_DIRECT);
  esWorldi(w, ES_AMBISONIC_DECODER, ES_DECODER_MAGLS);
  for (ESsource src : s.sources) {
    esDeleteSource(w, src);
    s.dead_sources.push_back(src);
  }
  for (ESbuffer b : s.buffers) {
    esDeleteBuffer(w, b);
    s.dead_buffers.push_back(b);
  }
  s.sources.clear();
  s.buffers.clear();
  if (s.dead_sources.size() > 64) s.dead_sources.erase(s.dead_sources.begin(), s.dead_sources.begin() + 32);
  if (s.dead_buffers.size() > 64) s.dead_buffers.erase(s.dead_buffers.begin(), s.dead_buffers.begin() + 32);

  Bytes in(data, size);
  int ops = 0;
  while (!in.empty() && ops++ < 256) {
    const ESworld target = in.u8() < 240 ? w : (in.u8() & 1 ? s.dead_world : in.u32());
    const std::uint8_t op = in.u8() % 27;
    switch (op) {
      case 0: {
        ESsource src = 0;
        if (esCreateSource(target, &src) == ES_OK) s.sources.push_back(src);
        break;
      }
      case 1: {
        const ESsource src = pick(in, s.sources, s.dead_sources);
        if (esDeleteSource(target, src) == ES_OK) {
          std::erase(s.sources, src);
          s.dead_sources.push_back(src);
        }
        break;
      }
      case 2: {
        std::array<float, 256> pcm;
        const ESuint frames = 1 + in.u8();
        for (ESuint i = 0; i < frames; ++i) pcm[i] = in.f32();
        const ESuint rate = in.u8() < 200 ? 48000u : in.u32();
        ESbuffer b = 0;
        if (esCreateBuffer(target, pcm.data(), frames, rate, &b) == ES_OK) s.buffers.push_back(b);
        break;
      }
      case 3: {
        const ESbuffer b = pick(in, s.buffers, s.dead_buffers);
        if (esDeleteBuffer(target, b) == ES_OK) {
          std::erase(s.buffers, b);
          s.dead_buffers.push_back(b);
        }
        break;
      }
      case 4: esSourcef(target, pick(in, s.sources, s.dead_sources), kParams[in.u8() % kParams.size()], in.f32()); break;
      case 5: {
        const ESsource src = pick(in, s.sources, s.dead_sources);
        const ESenum p = kParams[in.u8() % kParams.size()];
        const float x = in.f32(), y = in.f32(), z = in.f32();
        esSource3f(target, src, p, x, y, z);
        break;
      }
      case 6: {
        const ESsource src = pick(in, s.sources, s.dead_sources);
        const ESenum p = kParams[in.u8() % kParams.size()];
        esSourcei(target, src, p, int_value(in, s));
        break;
      }
      case 7: {
        std::array<float, 6> v;
        const ESenum p = kParams[in.u8() % kParams.size()];
        for (float& x : v) x = in.f32();
        esListenerfv(target, p, in.u8() < 250 ? v.data() : nullptr);
        // The same six floats into a source: ES_ORIENTATION takes six (ABI 1.5).
        esSourcefv(target, pick(in, s.sources, s.dead_sources), p, in.u8() < 250 ? v.data() : nullptr);
        break;
      }
      case 8: {
        const ESsource src = pick(in, s.sources, s.dead_sources);
        switch (in.u8() % 4) {
          case 0: esSourcePlay(target, src); break;
          case 1: esSourcePause(target, src); break;
          case 2: esSourceStop(target, src); break;
          default: esSourceRewind(target, src); break;
        }
        break;
      }
      case 9: render_and_check(w); break;
      case 10: esCommit(target); break;
      case 11: esWorldi(target, ES_COMMIT_MODE, in.u8() & 1 ? ES_DEFERRED : ES_IMMEDIATE); break;
      case 12: esReverbPreset(target, kPresets[in.u8() % kPresets.size()]); break;
      case 13: {
        const ESenum p = kReverbParams[in.u8() % kReverbParams.size()];
        esReverbf(target, p, in.f32());
        break;
      }
      case 14: esReverbi(target, ES_REVERB_ENABLED, int_value(in, s)); break;
      case 15: {
        std::array<float, 4> pos{}, q{};
        for (float& x : pos) x = in.f32();
        for (float& x : q) x = in.f32();
        esSetHeadPose(target, pos.data(), q.data());
        break;
      }
      case 16: {
        const ESsource src = pick(in, s.sources, s.dead_sources);
        const bool on = in.u8() & 1;
        esSourceCallback(target, src, on ? garbage : nullptr, reinterpret_cast<void*>(std::uintptr_t{in.u8()}));
        break;
      }
      case 17: {
        const ESsource src = pick(in, s.sources, s.dead_sources);
        std::array<float, 6> v{};  // ES_ORIENTATION on a source answers six (ABI 1.5)
        ESint i = 0;
        esGetSourcefv(target, src, kParams[in.u8() % kParams.size()], v.data());
        esGetSourcei(target, src, kParams[in.u8() % kParams.size()], &i);
        break;
      }
      case 18: {
        std::array<float, 6> v{};
        esGetListenerfv(target, kParams[in.u8() % kParams.size()], v.data());
        ESfloat f = 0;
        esGetReverbf(target, kReverbParams[in.u8() % kReverbParams.size()], &f);
        ESint i = 0;
        esGetWorldi(target, static_cast<ESenum>(0x4000 + in.u8() % 9), &i);
        break;
      }
      case 19: esDopplerFactor(target, in.f32()); break;
      case 20: esSpeedOfSound(target, in.f32()); break;
      case 21: {  // the tracker's state (ABI 1.1): any size, NULL, a spec that cannot start
        EStrackerstate ts;
        std::memset(&ts, 0xA5, sizeof ts);
        const std::uint8_t how = in.u8();
        ts.size = how < 200 ? ESuint{sizeof ts} : in.u32();
        if (how == 255) esAttachTracker(target, "carrier-pigeon");
        const ESenum e = esGetTrackerState(target, how == 254 ? nullptr : &ts);
        if (e == ES_OK) {  // every field written: texts NUL-ended, dots within the table
          if (ts.dot_count > ES_TRACKER_MAX_DOTS || !std::memchr(ts.message, 0, sizeof ts.message) ||
              !std::memchr(ts.source, 0, sizeof ts.source) || !std::isfinite(ts.rate_hz))
            std::abort();
        }
        break;
      }
      case 22: {  // the tracker's picture (ABI 1.3): any size, NULL; none from these sources
        static EStrackerimage im;  // ~19 kB: not on the fuzzer's stack
        std::memset(&im, 0xA5, sizeof im);
        const std::uint8_t how = in.u8();
        im.size = how < 200 ? ESuint{sizeof im} : in.u32();
        // 253: a running source without a picture (detached again below, so
        // inputs stay independent); 255: a spec that cannot start.
        if (how == 253) esAttachTracker(target, "sim");
        if (how == 255) esAttachTracker(target, "carrier-pigeon");
        const ESenum e = esGetTrackerImage(target, how == 254 ? nullptr : &im);
        if (how == 253) esAttachTracker(target, nullptr);
        if (e == ES_OK) {  // every field written, within its bounds
          if (im.dot_count > ES_TRACKER_MAX_DOTS || im.width > ES_TRACKER_IMAGE_MAX_WIDTH ||
              im.height > ES_TRACKER_IMAGE_MAX_HEIGHT || (im.available != ES_FALSE && im.available != ES_TRUE) ||
              !std::isfinite(im.time))
            std::abort();
          for (std::size_t i = std::size_t{im.width} * im.height; i < sizeof im.pixels; ++i)
            if (im.pixels[i] != 0) std::abort();
        }
        break;
      }
      case 24: {  // an Ambisonic buffer (ABI 1.5): any order, layout, scaling, raw samples
        static std::array<float, 64 * 12> raw;
        for (float& x : raw) x = in.f32();
        const ESuint order = in.u8() % 9;
        const ESuint frames = in.u8() % 13;
        constexpr std::array<ESenum, 3> layouts{ES_AMBISONIC_LAYOUT_ACN, ES_AMBISONIC_LAYOUT_FUMA, 0x6005};
        constexpr std::array<ESenum, 4> scalings{ES_AMBISONIC_SCALING_SN3D, ES_AMBISONIC_SCALING_N3D,
                                                 ES_AMBISONIC_SCALING_FUMA, 0};
        const ESenum layout = layouts[in.u8() % layouts.size()], scaling = scalings[in.u8() % scalings.size()];
        // At most 64 channels x 12 frames fit `raw`: larger counts pass a NULL instead.
        const bool fits = std::size_t(order + 1) * (order + 1) * frames <= raw.size();
        ESbuffer b = 0;
        if (esCreateAmbisonicBuffer(target, fits ? raw.data() : nullptr, frames, 8000 + 1000 * (in.u8() % 200), order,
                                    layout, scaling, &b) == ES_OK)
          s.buffers.push_back(b);
        break;
      }
      case 25: {  // a field callback (garbage samples), or none
        const ESsource src = pick(in, s.sources, s.dead_sources);
        const ESuint order = in.u8() % 9;
        esSourceAmbisonicCallback(target, src, order, in.u8() & 1 ? garbage_field : nullptr,
                                  reinterpret_cast<void*>(std::uintptr_t{in.u8()}));
        break;
      }
      case 26: {  // the tier and the decoder, any value (a change designs a decoder: slow once per order)
        const std::uint8_t how = in.u8();
        const ESint v = how < 100 ? ES_QUALITY_DIRECT + how % 10 : how < 200 ? ES_DECODER_MAGLS + how % 3
                                                                             : static_cast<ESint>(in.u32());
        esWorldi(target, how & 1 ? ES_QUALITY : ES_AMBISONIC_DECODER, v);
        break;
      }
      default: {
        const char* m = esGetErrorMessage(target);
        if (!m) std::abort();
        for (int k = 0; k < 3; ++k) render_and_check(w);
        break;
      }
    }
  }
  render_and_check(w);
  return 0;
}
