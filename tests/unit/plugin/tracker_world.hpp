// A world for the tracker tests of the C API (esGetTrackerState,
// esGetTrackerImage): created with two sources, destroyed at scope end, and
// asked for the tracker's state and picture.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <thread>

#include "earshot/earshot.h"

namespace earshot::plugin_tests {

struct TrackerWorld {
  static constexpr ESuint kBlock = 128;
  ESworld w = 0;
  TrackerWorld() {
    ESworldparams p;
    esWorldParamsDefault(&p);
    p.max_sources = 2;
    EXPECT_EQ(esCreateWorld(&p, &w), ES_OK);
  }
  ~TrackerWorld() {
    if (w) esDestroyWorld(w);
  }
  TrackerWorld(const TrackerWorld&) = delete;
  TrackerWorld& operator=(const TrackerWorld&) = delete;

  EStrackerstate state() const {
    EStrackerstate s{};
    s.size = sizeof s;
    EXPECT_EQ(esGetTrackerState(w, &s), ES_OK) << esGetErrorMessage(w);
    return s;
  }
  /// On the heap: the struct is ~19 kB.
  std::unique_ptr<EStrackerimage> image() const {
    auto im = std::make_unique<EStrackerimage>();
    im->size = sizeof(EStrackerimage);
    EXPECT_EQ(esGetTrackerImage(w, im.get()), ES_OK) << esGetErrorMessage(w);
    return im;
  }
  /// Polls (rendering a block each time, so the head pose moves) until `ok`.
  bool wait_for(const std::function<bool(const EStrackerstate&)>& ok, int tries = 1000) const {
    std::array<float, kBlock> l{}, r{};
    for (int i = 0; i < tries; ++i) {
      EXPECT_EQ(esRender(w, l.data(), r.data(), kBlock), ES_OK);
      if (ok(state())) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  double head_angle_deg() const {
    ESfloat p[3], q[4];
    EXPECT_EQ(esGetHeadPose(w, p, q), ES_OK);
    return 2.0 * std::acos(std::min(1.0, std::abs(double(q[0])))) * 180.0 / 3.14159265358979;
  }
};

}  // namespace earshot::plugin_tests
