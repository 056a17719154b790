// The demo's audio callback body (PortAudio's block -> AudioOutput::on_block
// -> render_block -> esRender with the host layer's callback sources, reverb
// and a tracker) allocates nothing and takes no lock.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "audio_output.hpp"
#include "block_render.hpp"
#include "earshot/host/scene_sources.hpp"
#include "earshot/host/tracker_status.hpp"
#include "earshot/host/world_handle.hpp"

namespace {

TEST(DemoRealTime, TheCallbackBodyNeitherAllocatesNorLocks) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  p.block_size = 128;
  const earshot::host::WorldHandle world(p);
  earshot::scenes::Scene scene;
  scene.room = "medium-room";
  earshot::scenes::SceneSource src;
  src.signal.type = earshot::scenes::Signal::Type::voice;
  src.position = {1, 0, -2};
  src.reverb_send_db = -10;
  scene.sources.push_back(src);
  earshot::host::SceneSources sources(world, 48000);
  sources.load(scene);
  const auto tracker = earshot::host::attach_tracker(world.id(), "sim");
  ASSERT_TRUE(tracker.failed.empty()) << tracker.failed;

  earshot::demo::AudioSide side;
  side.world = world.id();
  side.capture.assign(2 * 128 * 400, 0.0f);
  earshot::demo::AudioOutput out;
  out.prepare(&earshot::demo::render_block, &side, 128, 48000);
  std::vector<float> left(128), right(128);
  for (int i = 0; i < 20; ++i) out.on_block(left.data(), right.data(), 128, false);  // warm up
  std::size_t allocs = 0, locks = 0;
  {
    earshot::testing::AllocationProbe probe;
    for (int i = 0; i < 300; ++i) out.on_block(left.data(), right.data(), 128, i == 7);
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
}

}  // namespace
