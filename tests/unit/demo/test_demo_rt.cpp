// The demo's audio callback body (PortAudio's block -> AudioOutput::on_block
// -> render_block -> esRender with callback sources, reverb and a tracker)
// allocates nothing and takes no lock.
#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "audio_output.hpp"
#include "block_render.hpp"
#include "earshot/scenes/signal_source.hpp"

namespace {

void generate(void* user, float* out, ESuint frames) {
  static_cast<earshot::scenes::SignalSource*>(user)->generate(std::span<float>(out, frames));
}

TEST(DemoRealTime, TheCallbackBodyNeitherAllocatesNorLocks) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  p.block_size = 128;
  ESworld w = 0;
  ASSERT_EQ(esCreateWorld(&p, &w), ES_OK);
  ASSERT_EQ(esReverbPreset(w, "medium-room"), ES_OK);
  ASSERT_EQ(esReverbi(w, ES_REVERB_ENABLED, 1), ES_OK);
  earshot::scenes::Signal sig;
  sig.type = earshot::scenes::Signal::Type::voice;
  earshot::scenes::SignalSource sound(sig, 48000);
  ESsource s = 0;
  ASSERT_EQ(esCreateSource(w, &s), ES_OK);
  ASSERT_EQ(esSourceCallback(w, s, &generate, &sound), ES_OK);
  ASSERT_EQ(esSourcef(w, s, ES_REVERB_SEND, 0.3f), ES_OK);
  ASSERT_EQ(esSource3f(w, s, ES_POSITION, 1, 0, -2), ES_OK);
  ASSERT_EQ(esSourcePlay(w, s), ES_OK);
  ASSERT_EQ(esAttachTracker(w, "sim"), ES_OK);

  earshot::demo::AudioSide side;
  side.world = w;
  side.capture.assign(2 * 128 * 400, 0.0f);
  earshot::demo::AudioOutput out;
  out.prepare(&earshot::demo::render_block, &side, 128, 48000);
  std::vector<float> left(128), right(128);
  for (int i = 0; i < 20; ++i) out.on_block(left.data(), right.data(), 128, false);  // warm up
  std::size_t allocs = 0, locks = 0;
  {
    earshot::testing::AllocationProbe probe;
    for (int i = 0; i < 300; ++i) {
      out.on_block(left.data(), right.data(), 128, i == 7);
      // Move the source between blocks as the control side does.
    }
    allocs = probe.count();
    locks = probe.lock_count();
  }
  EXPECT_EQ(allocs, 0u);
  EXPECT_EQ(locks, 0u);
  EXPECT_EQ(out.stats().blocks.load(), 320u);
  EXPECT_EQ(out.stats().xruns.load(), 1u);
  EXPECT_GT(side.captured.load(), 0u);
  float peak = 0;
  for (float x : side.capture) peak = std::max(peak, std::abs(x));
  EXPECT_GT(peak, 0.0f) << "the callback wrote silence";
  EXPECT_EQ(esDestroyWorld(w), ES_OK);
}

}  // namespace
