// The C API of libearshot.so (linked): the function table's version and
// layout, deferred mode on the rendered samples, misuse (bad, stale and
// destroyed handles, NaN and infinity, the wrong thread) without a crash or
// a changed output, no allocation or lock in esRender, head poses from the
// host and from a live tracker.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "binaural_cues.hpp"
#include "earshot/earshot.h"
#include "earshot/tracker/sources/opentrack_packet.hpp"
#include "earshot/tracker/sources/osc_pose.hpp"
#include "earshot/tracker/sources/udp_pose_source.hpp"
#include "earshot/tracker/sources/udp_socket.hpp"

namespace {

constexpr ESuint kBlock = 128;
constexpr double kRate = 48000.0;

std::vector<float> noise(std::size_t n, unsigned seed) {
  std::vector<float> x(n);
  unsigned s = seed;
  for (auto& v : x) {
    s = s * 1664525u + 1013904223u;
    v = 0.3f * (static_cast<float>(s >> 8) / 8388608.0f - 1.0f);
  }
  return x;
}

/// A world with one looping noise source ahead-left, destroyed at scope end.
struct TestWorld {
  ESworld w = 0;
  ESbuffer buf = 0;
  ESsource src = 0;
  explicit TestWorld(bool deferred = false, unsigned seed = 1) {
    ESworldparams p;
    esWorldParamsDefault(&p);
    p.max_sources = 8;
    EXPECT_EQ(esCreateWorld(&p, &w), ES_OK);
    const auto x = noise(24000, seed);
    EXPECT_EQ(esCreateBuffer(w, x.data(), static_cast<ESuint>(x.size()), 48000, &buf), ES_OK);
    EXPECT_EQ(esCreateSource(w, &src), ES_OK);
    EXPECT_EQ(esSourcei(w, src, ES_BUFFER, static_cast<ESint>(buf)), ES_OK);
    EXPECT_EQ(esSourcei(w, src, ES_LOOPING, ES_TRUE), ES_OK);
    EXPECT_EQ(esSource3f(w, src, ES_POSITION, -1, 0, -1), ES_OK);
    EXPECT_EQ(esSourcePlay(w, src), ES_OK);
    if (deferred) {
      EXPECT_EQ(esWorldi(w, ES_COMMIT_MODE, ES_DEFERRED), ES_OK);
    }
  }
  ~TestWorld() {
    if (w) esDestroyWorld(w);
  }
  TestWorld(const TestWorld&) = delete;
  TestWorld& operator=(const TestWorld&) = delete;

  /// n blocks, appended to l and r.
  void render(int n, std::vector<float>& l, std::vector<float>& r) const {
    std::array<float, kBlock> bl{}, br{};
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(esRender(w, bl.data(), br.data(), kBlock), ES_OK);
      l.insert(l.end(), bl.begin(), bl.end());
      r.insert(r.end(), br.begin(), br.end());
    }
  }
};

std::size_t first_difference(const std::vector<float>& a, const std::vector<float>& b) {
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (a[i] != b[i]) return i;
  return a.size() == b.size() ? std::numeric_limits<std::size_t>::max() : std::min(a.size(), b.size());
}

// ---- ABI ----

// The table's members in order, as the header lists them.
constexpr std::array kTableNames = {
    "esGetErrorString", "esWorldParamsDefault", "esCreateWorld", "esDestroyWorld", "esSetControlThread",
    "esGetErrorMessage", "esWorldi", "esGetWorldi", "esDopplerFactor", "esSpeedOfSound", "esCommit",
    "esListenerf", "esListener3f", "esListenerfv", "esGetListenerfv", "esCreateBuffer", "esDeleteBuffer",
    "esCreateSource", "esDeleteSource", "esSourcef", "esSource3f", "esSourcefv", "esSourcei", "esGetSourcef",
    "esGetSourcefv", "esGetSourcei", "esSourceCallback", "esSourcePlay", "esSourcePause", "esSourceStop",
    "esSourceRewind", "esReverbPreset", "esReverbf", "esReverbi", "esGetReverbf", "esAttachTracker",
    "esRecenter", "esGetHeadPose", "esSetHeadPose", "esRender",
    "esGetTrackerState",  // ABI 1.1 appended
    "esWorldHrtf",        // ABI 1.2 appended
    "esGetTrackerImage",  // ABI 1.3 appended
    "esAttachTrackerEx",  // ABI 1.4 appended
    "esCreateAmbisonicBuffer", "esSourceAmbisonicCallback"};  // ABI 1.5 appended

TEST(PluginAbi, TableVersionAndLayout) {
  const ESproctable* t = esGetProcTable(ES_ABI_VERSION_MAJOR);
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(esGetProcTable(ES_ABI_VERSION_MAJOR + 1), nullptr);
  EXPECT_EQ(esGetProcTable(0), nullptr);
  EXPECT_EQ(t->abi_version, ES_ABI_VERSION);
  EXPECT_EQ(t->abi_version >> 16, 1u);
  EXPECT_EQ(t->size, sizeof(ESproctable));
  // Layout of ABI 1: two 32-bit words, then one pointer per function, frozen.
  EXPECT_EQ(offsetof(ESproctable, GetErrorString), 8u);
  EXPECT_EQ(offsetof(ESproctable, Render), 8u + 39u * sizeof(void*));
  // ABI 1.1 appends esGetTrackerState after Render; nothing before it moves.
  EXPECT_EQ(offsetof(ESproctable, GetTrackerState), 8u + 40u * sizeof(void*));
  // ABI 1.2 appends esWorldHrtf.
  EXPECT_EQ(offsetof(ESproctable, WorldHrtf), 8u + 41u * sizeof(void*));
  // ABI 1.3 appends esGetTrackerImage.
  EXPECT_EQ(offsetof(ESproctable, GetTrackerImage), 8u + 42u * sizeof(void*));
  // ABI 1.4 appends esAttachTrackerEx, 1.5 the Ambisonic fields.
  EXPECT_EQ(t->abi_version & 0xFFFFu, 5u);
  EXPECT_EQ(offsetof(ESproctable, AttachTrackerEx), 8u + 43u * sizeof(void*));
  EXPECT_EQ(t->AttachTrackerEx, &esAttachTrackerEx);
  EXPECT_EQ(offsetof(ESproctable, CreateAmbisonicBuffer), 8u + 44u * sizeof(void*));
  EXPECT_EQ(offsetof(ESproctable, SourceAmbisonicCallback), 8u + 45u * sizeof(void*));
  EXPECT_EQ(sizeof(EStrackerimagedot), 16u) << "EStrackerimagedot changed: that is a new ABI";
  EXPECT_EQ(offsetof(EStrackerimage, time), 32u) << "EStrackerimage changed: that is a new ABI";
  EXPECT_EQ(sizeof(EStrackerimage), 104u + 160u * 120u) << "EStrackerimage changed: that is a new ABI";
  EXPECT_EQ(sizeof(EStrackerdot), 20u) << "EStrackerdot changed: that is a new ABI";
  EXPECT_EQ(sizeof(EStrackerstate), 684u) << "EStrackerstate changed: that is a new ABI";
  EXPECT_EQ(sizeof(ESproctable), 8u + kTableNames.size() * sizeof(void*));
  EXPECT_EQ(sizeof(ESworldparams), 48u) << "ESworldparams changed: that is a new ABI";
  // The struct's size field is checked, and so is every field.
  ESworldparams p;
  esWorldParamsDefault(&p);
  ESworld w = 0;
  p.size = sizeof(ESworldparams) - 4;
  EXPECT_EQ(esCreateWorld(&p, &w), ES_INVALID_VALUE);
  esWorldParamsDefault(&p);
  p.head_radius_m = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(esCreateWorld(&p, &w), ES_INVALID_VALUE);
  esWorldParamsDefault(&p);
  p.block_size = 0;
  EXPECT_EQ(esCreateWorld(&p, &w), ES_INVALID_VALUE);
  esWorldParamsDefault(&p);
  p.hrtf_path = "/nonexistent.sofa";
  EXPECT_EQ(esCreateWorld(&p, &w), ES_HRTF_ERROR);
  EXPECT_EQ(w, 0u);
  EXPECT_EQ(esCreateWorld(nullptr, &w), ES_INVALID_VALUE);
  // Every slot holds the exported function of its name.
  for (std::size_t i = 0; i < kTableNames.size(); ++i) {
    void* slot = nullptr;
    std::memcpy(&slot, reinterpret_cast<const char*>(t) + 8 + i * sizeof(void*), sizeof slot);
    if (*kTableNames[i] == '\0') {
      EXPECT_EQ(slot, nullptr) << "slot " << i;
      continue;
    }
    EXPECT_EQ(slot, dlsym(RTLD_DEFAULT, kTableNames[i])) << kTableNames[i];
  }
}

// ---- deferred mode ----

// Several changes without a commit leave the output unchanged, sample for
// sample; after esCommit all of them are heard from the same block, exactly
// as in a world where the same changes were made at that block boundary.
TEST(PluginDeferred, NothingBeforeCommitEverythingInOneBlockAfter) {
  TestWorld deferred(true), untouched(false), immediate(false);
  std::vector<float> dl, dr, ul, ur, il, ir;
  deferred.render(10, dl, dr);
  untouched.render(10, ul, ur);
  immediate.render(10, il, ir);

  auto changes = [](const TestWorld& t) {
    EXPECT_EQ(esSource3f(t.w, t.src, ES_POSITION, 2, 0, 0.5f), ES_OK);
    EXPECT_EQ(esSourcef(t.w, t.src, ES_GAIN, 0.5f), ES_OK);
    EXPECT_EQ(esSourcef(t.w, t.src, ES_PITCH, 1.25f), ES_OK);
    EXPECT_EQ(esListenerf(t.w, ES_GAIN, 0.8f), ES_OK);
    const ESfloat at_up[6] = {-1, 0, 0, 0, 1, 0};  // face left
    EXPECT_EQ(esListenerfv(t.w, ES_ORIENTATION, at_up), ES_OK);
    EXPECT_EQ(esReverbPreset(t.w, "concert-hall"), ES_OK);
    EXPECT_EQ(esReverbi(t.w, ES_REVERB_ENABLED, ES_TRUE), ES_OK);
    EXPECT_EQ(esSourcef(t.w, t.src, ES_REVERB_SEND, 0.5f), ES_OK);
  };
  changes(deferred);
  deferred.render(20, dl, dr);  // changes made, no commit
  untouched.render(20, ul, ur);
  immediate.render(20, il, ir);
  EXPECT_EQ(first_difference(dl, ul), std::numeric_limits<std::size_t>::max()) << "heard before the commit";
  EXPECT_EQ(first_difference(dr, ur), std::numeric_limits<std::size_t>::max());

  ESint mode = 0;
  ASSERT_EQ(esGetWorldi(deferred.w, ES_COMMIT_MODE, &mode), ES_OK);
  EXPECT_EQ(mode, ES_DEFERRED);
  ASSERT_EQ(esCommit(deferred.w), ES_OK);
  changes(immediate);  // the same changes, at the same block boundary
  const std::size_t commit_at = dl.size();
  deferred.render(20, dl, dr);
  untouched.render(20, ul, ur);
  immediate.render(20, il, ir);
  // All together from the first block after the commit: the deferred world
  // is sample-identical to the immediate one, and differs from the untouched
  // one from that block's first sample on.
  EXPECT_EQ(first_difference(dl, il), std::numeric_limits<std::size_t>::max());
  EXPECT_EQ(first_difference(dr, ir), std::numeric_limits<std::size_t>::max());
  const std::size_t changed = std::min(first_difference(dl, ul), first_difference(dr, ur));
  EXPECT_GE(changed, commit_at);
  EXPECT_LT(changed, commit_at + kBlock) << "not heard in the first block after the commit";

  // A world that gets the changes one block apart differs: one block holds all.
  TestWorld staggered(false);
  std::vector<float> sl, sr;
  staggered.render(30, sl, sr);
  EXPECT_EQ(esSource3f(staggered.w, staggered.src, ES_POSITION, 2, 0, 0.5f), ES_OK);
  staggered.render(1, sl, sr);
  EXPECT_EQ(esSourcef(staggered.w, staggered.src, ES_GAIN, 0.5f), ES_OK);
  staggered.render(19, sl, sr);
  EXPECT_LT(first_difference(sl, dl), dl.size());
}

TEST(PluginDeferred, ImmediateModeAppliesAtTheNextBlock) {
  TestWorld a(false), b(false);
  std::vector<float> al, ar, bl, br;
  a.render(5, al, ar);
  b.render(5, bl, br);
  ASSERT_EQ(esSourcef(a.w, a.src, ES_GAIN, 0.0f), ES_OK);
  a.render(3, al, ar);
  b.render(3, bl, br);
  const std::size_t d = first_difference(al, bl);
  EXPECT_GE(d, 5u * kBlock);
  EXPECT_LT(d, 6u * kBlock);
}

TEST(PluginDeferred, SwitchingToImmediateAppliesPendingChanges) {
  TestWorld t(true);
  ASSERT_EQ(esSourcef(t.w, t.src, ES_GAIN, 0.25f), ES_OK);
  ASSERT_EQ(esWorldi(t.w, ES_COMMIT_MODE, ES_IMMEDIATE), ES_OK);
  TestWorld ref(false);
  ASSERT_EQ(esSourcef(ref.w, ref.src, ES_GAIN, 0.25f), ES_OK);
  std::vector<float> l, r, rl, rr;
  t.render(4, l, r);
  ref.render(4, rl, rr);
  EXPECT_EQ(first_difference(l, rl), std::numeric_limits<std::size_t>::max());
}

// ---- sources: pitch, OpenAL Doppler, state, callbacks ----

/// Frequency of the left channel by counting upward zero crossings.
double frequency_hz(const std::vector<float>& x) {
  std::size_t up = 0, first = 0, last = 0;
  for (std::size_t i = 1; i < x.size(); ++i)
    if (x[i - 1] < 0.0f && x[i] >= 0.0f) {
      if (up++ == 0) first = i;
      last = i;
    }
  return up > 1 ? static_cast<double>(up - 1) * kRate / static_cast<double>(last - first) : 0.0;
}

std::vector<float> sine(double hz, std::size_t n) {
  std::vector<float> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = 0.5f * static_cast<float>(std::sin(2 * std::numbers::pi * hz * static_cast<double>(i) / kRate));
  return x;
}

double rendered_frequency(void (*setup)(ESworld, ESsource)) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  ESworld w = 0;
  EXPECT_EQ(esCreateWorld(&p, &w), ES_OK);
  const auto x = sine(500.0, 48000);
  ESbuffer b = 0;
  ESsource s = 0;
  EXPECT_EQ(esCreateBuffer(w, x.data(), 48000, 48000, &b), ES_OK);
  EXPECT_EQ(esCreateSource(w, &s), ES_OK);
  EXPECT_EQ(esSourcei(w, s, ES_BUFFER, static_cast<ESint>(b)), ES_OK);
  EXPECT_EQ(esSourcei(w, s, ES_LOOPING, ES_TRUE), ES_OK);
  EXPECT_EQ(esSource3f(w, s, ES_POSITION, 0, 0, -3), ES_OK);
  setup(w, s);
  EXPECT_EQ(esSourcePlay(w, s), ES_OK);
  std::vector<float> l, r;
  std::array<float, kBlock> bl{}, br{};
  for (int i = 0; i < 200; ++i) {
    EXPECT_EQ(esRender(w, bl.data(), br.data(), kBlock), ES_OK);
    if (i >= 20) l.insert(l.end(), bl.begin(), bl.end());
  }
  esDestroyWorld(w);
  return frequency_hz(l);
}

TEST(PluginSources, PitchAndOpenAlDopplerShiftTheFrequency) {
  EXPECT_NEAR(rendered_frequency([](ESworld, ESsource) {}), 500.0, 1.0);
  EXPECT_NEAR(rendered_frequency([](ESworld w, ESsource s) { EXPECT_EQ(esSourcef(w, s, ES_PITCH, 1.5f), ES_OK); }),
              750.0, 1.5);
  // Approaching at a tenth of the speed of sound: f c / (c - v) = 555.6 Hz.
  EXPECT_NEAR(rendered_frequency([](ESworld w, ESsource s) { EXPECT_EQ(esSource3f(w, s, ES_VELOCITY, 0, 0, 34.33f), ES_OK); }),
              500.0 / 0.9, 1.5);
  // The listener moving away at the same speed: f (c - v) / c = 450 Hz; a Doppler factor of 0 removes it.
  EXPECT_NEAR(rendered_frequency([](ESworld w, ESsource) { EXPECT_EQ(esListener3f(w, ES_VELOCITY, 0, 0, 34.33f), ES_OK); }),
              450.0, 1.5);
  EXPECT_NEAR(rendered_frequency([](ESworld w, ESsource) {
                EXPECT_EQ(esListener3f(w, ES_VELOCITY, 0, 0, 34.33f), ES_OK);
                EXPECT_EQ(esDopplerFactor(w, 0.0f), ES_OK);
              }),
              500.0, 1.0);
}

TEST(PluginSources, BufferEndsStopsAndRewinds) {
  TestWorld t(false);
  ASSERT_EQ(esSourceStop(t.w, t.src), ES_OK);
  ASSERT_EQ(esSourcei(t.w, t.src, ES_LOOPING, ES_FALSE), ES_OK);
  ASSERT_EQ(esSourcePlay(t.w, t.src), ES_OK);
  ESint st = 0;
  ASSERT_EQ(esGetSourcei(t.w, t.src, ES_SOURCE_STATE, &st), ES_OK);
  EXPECT_EQ(st, ES_PLAYING);
  std::vector<float> l, r;
  t.render(100, l, r);  // 12800 frames of a 24000-frame buffer
  ESfloat offset = 0;
  ASSERT_EQ(esGetSourcef(t.w, t.src, ES_SAMPLE_OFFSET, &offset), ES_OK);
  EXPECT_EQ(offset, 12800.0f);
  ASSERT_EQ(esSourcePause(t.w, t.src), ES_OK);
  t.render(10, l, r);
  ASSERT_EQ(esGetSourcei(t.w, t.src, ES_SOURCE_STATE, &st), ES_OK);
  EXPECT_EQ(st, ES_PAUSED);
  ASSERT_EQ(esGetSourcef(t.w, t.src, ES_SAMPLE_OFFSET, &offset), ES_OK);
  EXPECT_EQ(offset, 12800.0f);
  ASSERT_EQ(esSourcePlay(t.w, t.src), ES_OK);  // resumes
  t.render(100, l, r);
  ASSERT_EQ(esGetSourcei(t.w, t.src, ES_SOURCE_STATE, &st), ES_OK);
  EXPECT_EQ(st, ES_STOPPED);
  ASSERT_EQ(esSourceRewind(t.w, t.src), ES_OK);
  ASSERT_EQ(esGetSourcei(t.w, t.src, ES_SOURCE_STATE, &st), ES_OK);
  EXPECT_EQ(st, ES_INITIAL);
  // Stopped, the buffer can be changed and then deleted once no source has it.
  ASSERT_EQ(esSourcei(t.w, t.src, ES_BUFFER, 0), ES_OK);
  EXPECT_EQ(esDeleteBuffer(t.w, t.buf), ES_OK);
}

void ramp(void* user, float* out, ESuint frames) {
  auto* calls = static_cast<int*>(user);
  ++*calls;
  for (ESuint i = 0; i < frames; ++i) out[i] = 0.2f;
}

TEST(PluginSources, CallbackFeedsTheSource) {
  TestWorld t(false);
  ASSERT_EQ(esDeleteSource(t.w, t.src), ES_OK);
  int calls = 0;
  ESsource s = 0;
  ASSERT_EQ(esCreateSource(t.w, &s), ES_OK);
  ASSERT_EQ(esSourceCallback(t.w, s, ramp, &calls), ES_OK);
  std::vector<float> l, r;
  t.render(5, l, r);
  EXPECT_EQ(calls, 0) << "not playing yet";
  ASSERT_EQ(esSourcePlay(t.w, s), ES_OK);
  t.render(20, l, r);
  EXPECT_EQ(calls, 20);
  double e = 0;
  for (float v : l) e += v * v;
  EXPECT_GT(e, 0.0);
}

// ---- misuse ----

struct Reentry {
  ESworld world = 0;
  ESenum result = ES_OK, destroy = ES_OK;
};
void reenter(void* user, float* out, ESuint frames) {
  auto* r = static_cast<Reentry*>(user);
  std::array<float, kBlock> l{}, rr{};
  r->result = esRender(r->world, l.data(), rr.data(), kBlock);  // a second render while one runs
  r->destroy = esDestroyWorld(r->world);                        // would wait for itself
  for (ESuint i = 0; i < frames; ++i) out[i] = std::numeric_limits<float>::quiet_NaN();
}

TEST(PluginMisuse, BadHandlesValuesAndThreadsChangeNothing) {
  TestWorld abused(false), ref(false);
  const ESworld w = abused.w;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::array<float, kBlock> l{}, r{};

  // Null, made-up and foreign handles.
  EXPECT_EQ(esSourcef(0, abused.src, ES_GAIN, 1), ES_INVALID_WORLD);
  EXPECT_EQ(esSourcef(0xDEADBEEF, abused.src, ES_GAIN, 1), ES_INVALID_WORLD);
  EXPECT_EQ(esRender(0, l.data(), r.data(), kBlock), ES_INVALID_WORLD);
  EXPECT_EQ(esSourcef(w, 0, ES_GAIN, 1), ES_INVALID_SOURCE);
  EXPECT_EQ(esSourcef(w, 0x12345678, ES_GAIN, 1), ES_INVALID_SOURCE);
  EXPECT_EQ(esSourcei(w, abused.src, ES_BUFFER, 0x7777), ES_INVALID_BUFFER);
  EXPECT_EQ(esSourcei(w, abused.src, ES_BUFFER, static_cast<ESint>(ref.buf + 0x10000)), ES_INVALID_BUFFER);
  EXPECT_NE(std::string(esGetErrorMessage(w)), "");
  // Stale: a deleted source and buffer, even when their slots are reused.
  ESsource gone = 0, reused = 0;
  ASSERT_EQ(esCreateSource(w, &gone), ES_OK);
  ASSERT_EQ(esDeleteSource(w, gone), ES_OK);
  ASSERT_EQ(esCreateSource(w, &reused), ES_OK);
  EXPECT_NE(gone, reused);
  EXPECT_EQ(esSourcef(w, gone, ES_GAIN, 1), ES_INVALID_SOURCE);
  EXPECT_EQ(esDeleteSource(w, gone), ES_INVALID_SOURCE);
  ASSERT_EQ(esDeleteSource(w, reused), ES_OK);
  const auto x = noise(100, 9);
  ESbuffer b = 0;
  ASSERT_EQ(esCreateBuffer(w, x.data(), 100, 48000, &b), ES_OK);
  ASSERT_EQ(esDeleteBuffer(w, b), ES_OK);
  EXPECT_EQ(esDeleteBuffer(w, b), ES_INVALID_BUFFER);
  EXPECT_EQ(esSourcei(w, abused.src, ES_BUFFER, static_cast<ESint>(b)), ES_INVALID_BUFFER);
  EXPECT_EQ(esDeleteBuffer(w, abused.buf), ES_INVALID_OPERATION);  // playing

  // NaN, infinity, out of range, null pointers, wrong enums.
  for (float bad : {nan, inf, -inf}) {
    EXPECT_EQ(esSource3f(w, abused.src, ES_POSITION, bad, 0, 0), ES_INVALID_VALUE);
    EXPECT_EQ(esSource3f(w, abused.src, ES_VELOCITY, 0, bad, 0), ES_INVALID_VALUE);
    EXPECT_EQ(esSource3f(w, abused.src, ES_DIRECTION, 0, 0, bad), ES_INVALID_VALUE);
    for (ESenum p : {ES_GAIN, ES_MIN_GAIN, ES_MAX_GAIN, ES_PITCH, ES_REFERENCE_DISTANCE, ES_ROLLOFF_FACTOR,
                     ES_MAX_DISTANCE, ES_CONE_INNER_ANGLE, ES_CONE_OUTER_ANGLE, ES_CONE_OUTER_GAIN, ES_REVERB_SEND,
                     ES_AIR_ABSORPTION_FACTOR})
      EXPECT_EQ(esSourcef(w, abused.src, p, bad), ES_INVALID_VALUE) << p;
    EXPECT_EQ(esListener3f(w, ES_POSITION, bad, 0, 0), ES_INVALID_VALUE);
    EXPECT_EQ(esListenerf(w, ES_GAIN, bad), ES_INVALID_VALUE);
    const ESfloat q[4] = {bad, 0, 0, 0}, ori[6] = {0, 0, -1, 0, bad, 0};
    EXPECT_EQ(esListenerfv(w, ES_ORIENTATION_QUAT, q), ES_INVALID_VALUE);
    EXPECT_EQ(esListenerfv(w, ES_ORIENTATION, ori), ES_INVALID_VALUE);
    EXPECT_EQ(esReverbf(w, ES_REVERB_DECAY_TIME, bad), ES_INVALID_VALUE);
    EXPECT_EQ(esSetHeadPose(w, q, q), ES_INVALID_VALUE);
  }
  EXPECT_EQ(esSourcef(w, abused.src, ES_PITCH, 0.0f), ES_INVALID_VALUE);
  EXPECT_EQ(esSourcef(w, abused.src, ES_GAIN, -1.0f), ES_INVALID_VALUE);
  EXPECT_EQ(esReverbf(w, ES_REVERB_DECAY_TIME, 100.0f), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(w)).find("decay_time"), std::string::npos) << esGetErrorMessage(w);
  EXPECT_EQ(esReverbPreset(w, "bathtub"), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(w)).find("concert-hall"), std::string::npos) << esGetErrorMessage(w);
  const ESfloat zero_q[4] = {0, 0, 0, 0}, parallel[6] = {0, 1, 0, 0, 2, 0};
  EXPECT_EQ(esListenerfv(w, ES_ORIENTATION_QUAT, zero_q), ES_INVALID_VALUE);
  EXPECT_EQ(esListenerfv(w, ES_ORIENTATION, parallel), ES_INVALID_VALUE);
  EXPECT_EQ(esListenerfv(w, ES_POSITION, nullptr), ES_INVALID_VALUE);
  EXPECT_EQ(esGetSourcei(w, abused.src, ES_SOURCE_STATE, nullptr), ES_INVALID_VALUE);
  EXPECT_EQ(esSourcef(w, abused.src, 0x7FFF, 1), ES_INVALID_ENUM);
  EXPECT_EQ(esSourcei(w, abused.src, ES_LOOPING, 7), ES_INVALID_VALUE);
  EXPECT_EQ(esSourcei(w, abused.src, ES_DISTANCE_MODEL, 12), ES_INVALID_VALUE);
  EXPECT_EQ(esSourcei(w, abused.src, ES_BUFFER, 0), ES_INVALID_OPERATION);  // playing
  EXPECT_EQ(esWorldi(w, ES_COMMIT_MODE, 3), ES_INVALID_VALUE);
  EXPECT_EQ(esCreateBuffer(w, nullptr, 10, 48000, &b), ES_INVALID_VALUE);
  EXPECT_EQ(esCreateBuffer(w, x.data(), 10, 0, &b), ES_INVALID_VALUE);
  EXPECT_EQ(esRender(w, nullptr, r.data(), kBlock), ES_INVALID_VALUE);
  EXPECT_EQ(esRender(w, l.data(), r.data(), kBlock - 1), ES_INVALID_VALUE);
  EXPECT_EQ(esAttachTracker(w, "carrier-pigeon"), ES_TRACKER_ERROR);
  EXPECT_NE(std::string(esGetErrorMessage(w)).find("carrier-pigeon"), std::string::npos);
  EXPECT_EQ(esDopplerFactor(w, nan), ES_INVALID_VALUE);
  EXPECT_EQ(esSpeedOfSound(w, 0.0f), ES_INVALID_VALUE);

  // The wrong thread: every control call, and esDestroyWorld.
  std::thread([&] {
    EXPECT_EQ(esSourcef(w, abused.src, ES_GAIN, 0.1f), ES_WRONG_THREAD);
    EXPECT_EQ(esCommit(w), ES_WRONG_THREAD);
    EXPECT_EQ(esDestroyWorld(w), ES_WRONG_THREAD);
    ESsource s = 0;
    EXPECT_EQ(esCreateSource(w, &s), ES_WRONG_THREAD);
    ESfloat pos[3], ori[4];
    EXPECT_EQ(esGetHeadPose(w, pos, ori), ES_OK);  // any thread
  }).join();

  // After all that, the abused world sounds exactly like the untouched one.
  std::vector<float> al, ar, rl, rr;
  abused.render(40, al, ar);
  ref.render(40, rl, rr);
  EXPECT_EQ(first_difference(al, rl), std::numeric_limits<std::size_t>::max());
  EXPECT_EQ(first_difference(ar, rr), std::numeric_limits<std::size_t>::max());

  // A callback rendering the same world again is refused; its NaNs are dropped.
  Reentry re{w, ES_OK};
  ESsource cb = 0;
  ASSERT_EQ(esCreateSource(w, &cb), ES_OK);
  ASSERT_EQ(esSourceCallback(w, cb, reenter, &re), ES_OK);
  ASSERT_EQ(esSourcePlay(w, cb), ES_OK);
  ASSERT_EQ(esRender(w, l.data(), r.data(), kBlock), ES_OK);
  EXPECT_EQ(re.result, ES_WRONG_THREAD);
  EXPECT_EQ(re.destroy, ES_INVALID_OPERATION);
  for (std::size_t i = 0; i < kBlock; ++i) ASSERT_TRUE(std::isfinite(l[i]) && std::isfinite(r[i]));

  // Calls after destroy, and a handle of a new world in the same slot.
  ESworld old = abused.w;
  ASSERT_EQ(esDestroyWorld(old), ES_OK);
  abused.w = 0;
  EXPECT_EQ(esDestroyWorld(old), ES_INVALID_WORLD);
  EXPECT_EQ(esSourcef(old, abused.src, ES_GAIN, 1), ES_INVALID_WORLD);
  EXPECT_EQ(esRender(old, l.data(), r.data(), kBlock), ES_INVALID_WORLD);
  EXPECT_STREQ(esGetErrorMessage(old), "invalid world handle");
  TestWorld again(false);
  EXPECT_NE(again.w, old);
  EXPECT_EQ(esSourcef(old, again.src, ES_GAIN, 1), ES_INVALID_WORLD);
}

TEST(PluginMisuse, ControlThreadCanBeHandedOver) {
  TestWorld t(false);
  std::thread([&] {
    EXPECT_EQ(esSourcef(t.w, t.src, ES_GAIN, 0.5f), ES_WRONG_THREAD);
    EXPECT_EQ(esSetControlThread(t.w), ES_OK);
    EXPECT_EQ(esSourcef(t.w, t.src, ES_GAIN, 0.5f), ES_OK);
  }).join();
  EXPECT_EQ(esSourcef(t.w, t.src, ES_GAIN, 0.5f), ES_WRONG_THREAD);
  EXPECT_EQ(esSetControlThread(t.w), ES_OK);
  EXPECT_EQ(esSourcef(t.w, t.src, ES_GAIN, 0.5f), ES_OK);
}

// ---- threads ----

// The audio thread renders while the control thread changes everything,
// commits, and creates and deletes sources and buffers: every block is
// finite and in range (under ThreadSanitizer: no race in the hand-off).
TEST(PluginThreads, ControlAndAudioThreadsTogether) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  p.max_sources = 8;
  p.max_buffers = 8;
  ESworld w = 0;
  ASSERT_EQ(esCreateWorld(&p, &w), ES_OK);
  ASSERT_EQ(esReverbi(w, ES_REVERB_ENABLED, ES_TRUE), ES_OK);
  std::atomic<bool> stop{false}, bad{false};
  std::atomic<int> blocks{0};
  std::thread audio([&] {
    std::array<float, kBlock> l{}, r{};
    while (!stop.load()) {
      if (esRender(w, l.data(), r.data(), kBlock) != ES_OK) bad = true;
      for (std::size_t i = 0; i < kBlock; ++i)
        if (!std::isfinite(l[i]) || !std::isfinite(r[i]) || std::abs(l[i]) > 1 || std::abs(r[i]) > 1) bad = true;
      blocks.fetch_add(1);
    }
  });
  const auto x = noise(2000, 4);
  std::vector<ESsource> live;
  std::vector<ESbuffer> buffers;
  for (int round = 0; round < 300 || blocks.load() < 200; ++round) {
    if (round % 2 == 0) {
      EXPECT_EQ(esWorldi(w, ES_COMMIT_MODE, round % 4 == 0 ? ES_DEFERRED : ES_IMMEDIATE), ES_OK);
    }
    ESbuffer b = 0;
    if (esCreateBuffer(w, x.data(), 2000, 48000, &b) == ES_OK) buffers.push_back(b);
    ESsource s = 0;
    if (esCreateSource(w, &s) == ES_OK) {
      live.push_back(s);
      EXPECT_EQ(esSourcei(w, s, ES_BUFFER, static_cast<ESint>(buffers.back())), ES_OK);
      EXPECT_EQ(esSourcePlay(w, s), ES_OK);
    }
    for (ESsource src : live)
      EXPECT_EQ(esSource3f(w, src, ES_POSITION, std::sin(static_cast<float>(round)), 0, -1), ES_OK);
    EXPECT_EQ(esReverbf(w, ES_REVERB_DECAY_TIME, 0.5f + static_cast<float>(round % 10) * 0.1f), ES_OK);
    EXPECT_EQ(esCommit(w), ES_OK);
    if (live.size() > 4) {  // retire the oldest source and its buffer
      EXPECT_EQ(esDeleteSource(w, live.front()), ES_OK);
      live.erase(live.begin());
    }
    if (buffers.size() > live.size() + 1) {
      ESint used = 0;
      bool in_use = false;
      for (ESsource src : live) {
        EXPECT_EQ(esGetSourcei(w, src, ES_BUFFER, &used), ES_OK);
        in_use = in_use || static_cast<ESbuffer>(used) == buffers.front();
      }
      if (!in_use) {
        EXPECT_EQ(esDeleteBuffer(w, buffers.front()), ES_OK);
        buffers.erase(buffers.begin());
      }
    }
    if (round > 100000) break;
  }
  stop = true;
  audio.join();
  EXPECT_FALSE(bad.load());
  EXPECT_GE(blocks.load(), 200);
  EXPECT_EQ(esDestroyWorld(w), ES_OK);
}

// Worlds share one prepared HRTF set (audio/hrtf_cache.hpp). Four worlds,
// each made and driven by its own thread at once, with the same sources and
// the same moves, must render the same samples as one world alone: shared
// data that any of them wrote to would show here (and TSan would see it).
TEST(PluginThreads, WorldsSharingTheHrtfRenderAtOnceAsOneAlone) {
  constexpr int kBlocks = 120;
  const auto run = [](std::vector<float>& l, std::vector<float>& r) {
    TestWorld t;
    std::array<float, kBlock> bl{}, br{};
    for (int i = 0; i < kBlocks; ++i) {
      const float a = 0.05f * static_cast<float>(i);
      EXPECT_EQ(esSource3f(t.w, t.src, ES_POSITION, 2.0f * std::sin(a), 0.3f, -2.0f * std::cos(a)), ES_OK);
      ASSERT_EQ(esRender(t.w, bl.data(), br.data(), kBlock), ES_OK);
      l.insert(l.end(), bl.begin(), bl.end());
      r.insert(r.end(), br.begin(), br.end());
    }
  };
  std::vector<float> l1, r1;
  run(l1, r1);
  constexpr int kWorlds = 4;
  std::array<std::vector<float>, kWorlds> ls, rs;
  std::vector<std::thread> threads;
  for (int k = 0; k < kWorlds; ++k)
    threads.emplace_back([&, k] { run(ls[static_cast<std::size_t>(k)], rs[static_cast<std::size_t>(k)]); });
  for (auto& t : threads) t.join();
  for (int k = 0; k < kWorlds; ++k) {
    EXPECT_EQ(first_difference(ls[static_cast<std::size_t>(k)], l1), std::numeric_limits<std::size_t>::max()) << k;
    EXPECT_EQ(first_difference(rs[static_cast<std::size_t>(k)], r1), std::numeric_limits<std::size_t>::max()) << k;
  }
}

// ---- real time ----

TEST(PluginRealtime, RenderTakesNoAllocationOrLock) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  ESworld w = 0;
  ASSERT_EQ(esCreateWorld(&p, &w), ES_OK);
  const auto x = noise(4800, 3);
  ESbuffer b = 0;
  ASSERT_EQ(esCreateBuffer(w, x.data(), 4800, 44100, &b), ES_OK);
  ASSERT_EQ(esReverbPreset(w, "hangar"), ES_OK);
  ASSERT_EQ(esReverbi(w, ES_REVERB_ENABLED, ES_TRUE), ES_OK);
  std::vector<ESsource> s(32);
  for (std::size_t i = 0; i < s.size(); ++i) {
    ASSERT_EQ(esCreateSource(w, &s[i]), ES_OK);
    ASSERT_EQ(esSourcei(w, s[i], ES_BUFFER, static_cast<ESint>(b)), ES_OK);
    ASSERT_EQ(esSourcei(w, s[i], ES_LOOPING, ES_TRUE), ES_OK);
    ASSERT_EQ(esSourcef(w, s[i], ES_REVERB_SEND, 0.3f), ES_OK);
    ASSERT_EQ(esSourcePlay(w, s[i]), ES_OK);
  }
  {
    // The probe sees the library's own allocations (so zero below means zero).
    earshot::testing::AllocationProbe probe;
    ESbuffer extra = 0;
    ASSERT_EQ(esCreateBuffer(w, x.data(), 4800, 48000, &extra), ES_OK);
    EXPECT_GT(probe.count(), 0u);
  }
  std::array<float, 128> l{}, r{};
  ASSERT_EQ(esRender(w, l.data(), r.data(), 128), ES_OK);
  std::size_t allocations = 0, locks = 0;
  for (int block = 0; block < 50; ++block) {
    // Control changes between blocks (immediate mode: a snapshot each).
    const auto a = static_cast<float>(block) * 0.1f;
    for (std::size_t i = 0; i < s.size(); ++i)
      ASSERT_EQ(esSource3f(w, s[i], ES_POSITION, 2 * std::cos(a + static_cast<float>(i)), 0,
                           2 * std::sin(a + static_cast<float>(i))),
                ES_OK);
    const ESfloat q[4] = {std::cos(a / 2), 0, std::sin(a / 2), 0};
    ASSERT_EQ(esListenerfv(w, ES_ORIENTATION_QUAT, q), ES_OK);
    earshot::testing::AllocationProbe probe;
    ASSERT_EQ(esRender(w, l.data(), r.data(), 128), ES_OK);
    allocations += probe.count();
    locks += probe.lock_count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(locks, 0u);
  EXPECT_EQ(esDestroyWorld(w), ES_OK);
}

// ---- head poses ----

double ild_of(const TestWorld& t, int blocks) {
  std::vector<float> l, r;
  t.render(blocks, l, r);
  return earshot::analysis::ild_db(std::span(l).subspan(l.size() / 2), std::span(r).subspan(r.size() / 2));
}

TEST(PluginHead, HostPoseTurnsTheHead) {
  TestWorld t(false);
  ASSERT_EQ(esSource3f(t.w, t.src, ES_POSITION, 0, 0, -2), ES_OK);  // ahead
  EXPECT_NEAR(ild_of(t, 40), 0.0, 1.0);
  const double yaw = std::numbers::pi / 3;  // 60 deg to the left: the source is now on the right
  const ESfloat pos[3] = {0, 0, 0}, q[4] = {static_cast<ESfloat>(std::cos(yaw / 2)), 0,
                                             static_cast<ESfloat>(std::sin(yaw / 2)), 0};
  ASSERT_EQ(esSetHeadPose(t.w, pos, q), ES_OK);
  EXPECT_LT(ild_of(t, 40), -6.0);
  ESfloat p[3], o[4];
  ASSERT_EQ(esGetHeadPose(t.w, p, o), ES_OK);
  EXPECT_NEAR(o[2], q[2], 1e-6);
}

// Head prediction's two world properties: defaults, round trips, and bad
// values refused with the setting left as it was.
TEST(PluginHead, PredictionSettingsRoundTripAndBadValuesAreRefused) {
  TestWorld t(false);
  ESint v = -1;
  ASSERT_EQ(esGetWorldi(t.w, ES_HEAD_PREDICTION, &v), ES_OK);
  EXPECT_EQ(v, ES_TRUE);
  ASSERT_EQ(esGetWorldi(t.w, ES_OUTPUT_LATENCY_US, &v), ES_OK);
  EXPECT_EQ(v, 0);
  ASSERT_EQ(esWorldi(t.w, ES_OUTPUT_LATENCY_US, 10667), ES_OK);
  ASSERT_EQ(esWorldi(t.w, ES_HEAD_PREDICTION, ES_FALSE), ES_OK);
  ASSERT_EQ(esGetWorldi(t.w, ES_HEAD_PREDICTION, &v), ES_OK);
  EXPECT_EQ(v, ES_FALSE);
  ASSERT_EQ(esGetWorldi(t.w, ES_OUTPUT_LATENCY_US, &v), ES_OK);
  EXPECT_EQ(v, 10667) << "switching prediction off and on keeps the latency";
  EXPECT_EQ(esWorldi(t.w, ES_HEAD_PREDICTION, 2), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("ES_HEAD_PREDICTION"), std::string::npos);
  EXPECT_EQ(esWorldi(t.w, ES_OUTPUT_LATENCY_US, -1), ES_INVALID_VALUE);
  EXPECT_EQ(esWorldi(t.w, ES_OUTPUT_LATENCY_US, 1000001), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("ES_OUTPUT_LATENCY_US"), std::string::npos);
  ASSERT_EQ(esGetWorldi(t.w, ES_OUTPUT_LATENCY_US, &v), ES_OK);
  EXPECT_EQ(v, 10667);
  ASSERT_EQ(esGetWorldi(t.w, ES_HEAD_PREDICTION, &v), ES_OK);
  EXPECT_EQ(v, ES_FALSE);
}

// The live tracker behind esAttachTracker: opentrack packets on the
// loopback interface turn the head (the first pose is the neutral one).
TEST(PluginHead, LiveTrackerTurnsTheHead) {
  TestWorld t(false);
  ASSERT_EQ(esSource3f(t.w, t.src, ES_POSITION, 0, 0, -2), ES_OK);
  constexpr std::uint16_t kPort = 47311;
  ASSERT_EQ(esAttachTracker(t.w, ("opentrack:" + std::to_string(kPort)).c_str()), ES_OK) << esGetErrorMessage(t.w);
  std::array<float, kBlock> l{}, r{};
  // Sends the packet until the head pose shows the yaw (no time limit in the
  // assertion: at most ~10 s of real time).
  auto turn_to = [&](double opentrack_yaw_deg, double sin_half_yaw) {
    const auto packet = earshot::tracker::encode_opentrack({0, 0, 0, opentrack_yaw_deg, 0, 0});
    for (int i = 0; i < 1000; ++i) {
      earshot::tracker::send_udp_loopback(kPort, packet);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      EXPECT_EQ(esRender(t.w, l.data(), r.data(), kBlock), ES_OK);
      ESfloat p[3], o[4];
      EXPECT_EQ(esGetHeadPose(t.w, p, o), ES_OK);
      if (std::abs(o[2] - sin_half_yaw) < 0.01) return true;
    }
    return false;
  };
  ASSERT_TRUE(turn_to(0.0, 0.0));
  // opentrack's yaw is positive to the right: -60 there turns the head 60 deg left.
  ASSERT_TRUE(turn_to(-60.0, std::sin(std::numbers::pi / 6)));
  EXPECT_LT(ild_of(t, 40), -6.0) << "the source ahead should now be on the right";
  ASSERT_EQ(esAttachTracker(t.w, nullptr), ES_OK);
}

// esAttachTrackerEx (ABI 1.4): the tracker's options as name/value pairs.
// "send" sends every pose the tracker publishes on: opentrack in with the
// head turned 60 degrees left (opentrack's yaw -60), SPARTA's /ypr out, read
// back by our own OSC input: the head there turns left too.
TEST(PluginTracker, AttachTrackerExSendsThePosesOn) {
  TestWorld t(false);
  earshot::tracker::UdpPoseSource rx("osc", 0, std::string("127.0.0.1"),
                                     earshot::tracker::OscPoseDecoder::packet_decoder());
  constexpr std::uint16_t kPort = 47312;
  const std::string in = "opentrack:" + std::to_string(kPort);
  const std::string out = "osc:127.0.0.1:" + std::to_string(rx.port()) + ",format=sparta";
  const char* options[] = {"send", out.c_str(), nullptr};
  ASSERT_EQ(esAttachTrackerEx(t.w, in.c_str(), options), ES_OK) << esGetErrorMessage(t.w);
  const auto packet = earshot::tracker::encode_opentrack({0, 0, 0, -60.0, 0, 0});
  bool left = false;
  for (int i = 0; i < 500 && !left; ++i) {  // bounded: at most ~5 s
    earshot::tracker::send_udp_loopback(kPort, packet);
    const auto e = rx.next(std::chrono::milliseconds(10));
    if (const auto* p = std::get_if<earshot::HeadPose>(&e)) {
      const auto ahead = earshot::tracker::to_eigen(p->orientation) * earshot::tracker::Vec3(0, 0, -1);
      left = ahead.isApprox(earshot::tracker::Vec3(-std::sin(std::numbers::pi / 3), 0, -0.5), 1e-4);
    }
  }
  EXPECT_TRUE(left) << "SPARTA's /ypr never showed the head turned left; " << rx.last_error();
  ASSERT_EQ(esAttachTracker(t.w, nullptr), ES_OK);

  // Bad options: named, and nothing attached.
  const char* unknown[] = {"colour", "red", nullptr};
  EXPECT_EQ(esAttachTrackerEx(t.w, "sim", unknown), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("esAttachTrackerEx: unknown option 'colour' (send)"), std::string::npos)
      << esGetErrorMessage(t.w);
  const char* bad[] = {"send", "osc:70000", nullptr};
  EXPECT_EQ(esAttachTrackerEx(t.w, "sim", bad), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("send 'osc:70000': bad UDP port"), std::string::npos)
      << esGetErrorMessage(t.w);
  const char* no_value[] = {"send", nullptr};
  EXPECT_EQ(esAttachTrackerEx(t.w, "sim", no_value), ES_INVALID_VALUE);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("option 'send' has no value"), std::string::npos);
  const char* nowhere[] = {"send", "osc:no-such-host.invalid", nullptr};
  EXPECT_EQ(esAttachTrackerEx(t.w, "sim", nowhere), ES_TRACKER_ERROR);
  EXPECT_NE(std::string(esGetErrorMessage(t.w)).find("cannot resolve host 'no-such-host.invalid'"), std::string::npos)
      << esGetErrorMessage(t.w);
  EStrackerstate st{};
  st.size = sizeof st;
  ASSERT_EQ(esGetTrackerState(t.w, &st), ES_OK);
  EXPECT_EQ(st.state, ES_TRACKER_NONE);
  // NULL options: as esAttachTracker.
  EXPECT_EQ(esAttachTrackerEx(t.w, "sim", nullptr), ES_OK) << esGetErrorMessage(t.w);
  ASSERT_EQ(esAttachTracker(t.w, nullptr), ES_OK);
}

}  // namespace
