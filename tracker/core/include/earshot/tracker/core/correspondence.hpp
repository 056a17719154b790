// Labelled observations: which LED produced which image dot.
#pragma once

#include <array>
#include <span>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/geometry.hpp"
#include "earshot/tracker/core/led_model.hpp"

namespace earshot::tracker {

struct Correspondence {
  int led = 0;  ///< 0-3, index into LedModel::leds_mm
  Vec2 pixel;
};

/// At most four labelled dots of one frame.
struct LabelledDots {
  std::array<Correspondence, 4> items{};
  int count = 0;

  void add(int led, const Vec2& px) { items[static_cast<size_t>(count++)] = {led, px}; }
  [[nodiscard]] std::span<const Correspondence> view() const {
    return {items.data(), static_cast<size_t>(count)};
  }
};

/// Root-mean-square reprojection error (pixels) of a pose over the dots.
[[nodiscard]] double rms_reprojection_error(const Pose& pose, std::span<const Correspondence> dots,
                                            const Camera& cam, const LedModel& model);

}  // namespace earshot::tracker
