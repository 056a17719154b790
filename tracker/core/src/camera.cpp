#include "earshot/tracker/core/camera.hpp"

namespace earshot::tracker {

Camera Camera::with_focal(double f, int width, int height) {
  Camera c;
  c.fx = c.fy = f;
  c.width = width;
  c.height = height;
  c.cx = width / 2.0;
  c.cy = height / 2.0;
  return c;
}

}  // namespace earshot::tracker
