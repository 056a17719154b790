// Pinhole camera of the Wii Remote (or any camera): intrinsics and image size.
#pragma once

#include "earshot/tracker/core/geometry.hpp"

namespace earshot::tracker {

struct Camera {
  double fx = 1280.0;  ///< focal length, pixels (x)
  double fy = 1280.0;  ///< focal length, pixels (y)
  double cx = 512.0;   ///< principal point, pixels
  double cy = 384.0;
  int width = 1024;    ///< Wii camera reports 1024 x 768
  int height = 768;

  /// A camera with square pixels and the principal point at the image centre.
  [[nodiscard]] static Camera with_focal(double f, int width = 1024, int height = 768);

  /// Pixel of a camera-frame point (must have z > 0).
  [[nodiscard]] Vec2 project(const Vec3& p) const {
    return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  }
  /// Unit bearing vector through a pixel.
  [[nodiscard]] Vec3 bearing(const Vec2& px) const {
    return Vec3((px.x() - cx) / fx, (px.y() - cy) / fy, 1.0).normalized();
  }
  [[nodiscard]] bool inside(const Vec2& px) const {
    return px.x() >= 0.0 && px.y() >= 0.0 && px.x() < width && px.y() < height;
  }
};

}  // namespace earshot::tracker
