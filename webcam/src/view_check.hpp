// The GrayView contract both detectors enforce.
#pragma once

#include "earshot/webcam/dot_detector.hpp"

namespace earshot::webcam::detail {

/// Throws std::invalid_argument when the view's sizes, stride or span do not
/// describe a frame; returns false for a frame without pixels (width or
/// height 0), which has nothing to find.
bool check_view(const GrayView& frame);

}  // namespace earshot::webcam::detail
