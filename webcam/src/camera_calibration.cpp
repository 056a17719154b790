#include "earshot/webcam/camera_calibration.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <vector>

#include "earshot/errors.hpp"

namespace earshot::webcam {
namespace {

constexpr std::size_t kMaxFileBytes = 256 * 1024;  // a calibration is a few hundred bytes
constexpr int kMaxNesting = 64;

/// yaml-cpp recurses once per nesting level: refuse what would overflow the
/// stack before it parses (brackets, and block indentation / "- " markers).
void check_nesting(std::string_view text, std::string_view origin) {
  int depth = 0;
  long line = 1;
  bool line_start = true;
  int prefix = 0;
  for (const char c : text) {
    if (c == '\n') {
      ++line;
      line_start = true;
      prefix = 0;
      continue;
    }
    if (line_start) {
      if (c == ' ' || c == '-' || c == '?' || c == ':' || c == '\t') {
        if (++prefix > 4 * kMaxNesting)
          throw InputError::at(origin, line, "", "indented or nested deeper than a calibration file is");
        continue;
      }
      line_start = false;
    }
    if (c == '[' || c == '{') {
      if (++depth > kMaxNesting) throw InputError::at(origin, line, "", "brackets nested deeper than 64");
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

std::string kind_of(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Scalar: return "'" + n.Scalar().substr(0, 32) + "'";
    default: return "nothing";
  }
}

double number(const YAML::Node& n, std::string_view origin, const std::string& field) {
  double v = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v))
    throw InputError::at(origin, n.Mark().line + 1, field, "not a finite number: " + kind_of(n));
  return v;
}

/// An !!opencv-matrix map: rows, cols, dt, data (rows * cols numbers).
std::vector<double> matrix(const YAML::Node& root, std::string_view origin, const std::string& field, int& rows,
                           int& cols) {
  const YAML::Node m = root[field];
  if (!m) throw InputError::at(origin, 0, field, "missing");
  if (!m.IsMap()) throw InputError::at(origin, m.Mark().line + 1, field, "not an opencv-matrix map: " + kind_of(m));
  const auto count = [&](const char* key) {
    const YAML::Node n = m[key];
    if (!n) throw InputError::at(origin, m.Mark().line + 1, field + "." + key, "missing");
    const double v = number(n, origin, field + "." + key);
    if (v < 1 || v > 64 || v != std::floor(v))
      throw InputError::at(origin, n.Mark().line + 1, field + "." + key, "not a count 1-64");
    return static_cast<int>(v);
  };
  rows = count("rows");
  cols = count("cols");
  if (const YAML::Node dt = m["dt"]; dt && !(dt.IsScalar() && (dt.Scalar() == "d" || dt.Scalar() == "f")))
    throw InputError::at(origin, dt.Mark().line + 1, field + ".dt", "not 'd' or 'f' (one number per element)");
  const YAML::Node data = m["data"];
  if (!data) throw InputError::at(origin, m.Mark().line + 1, field + ".data", "missing");
  if (!data.IsSequence()) throw InputError::at(origin, data.Mark().line + 1, field + ".data", "not a list: " + kind_of(data));
  if (data.size() != static_cast<std::size_t>(rows * cols))
    throw InputError::at(origin, data.Mark().line + 1, field + ".data",
                         std::to_string(data.size()) + " values for " + std::to_string(rows) + "x" + std::to_string(cols));
  std::vector<double> v;
  v.reserve(data.size());
  for (std::size_t i = 0; i < data.size(); ++i)
    v.push_back(number(data[i], origin, field + ".data[" + std::to_string(i) + "]"));
  return v;
}

constexpr double kMaxFocalPx = 1e6, kMaxCentrePx = 1e5;

CameraCalibration from_yaml(const YAML::Node& root, std::string_view origin) {
  if (!root.IsMap()) throw InputError::at(origin, 0, "", "not a calibration file (expected a YAML map with camera_matrix)");
  CameraCalibration c;
  int rows = 0, cols = 0;
  const auto k = matrix(root, origin, "camera_matrix", rows, cols);
  if (rows != 3 || cols != 3) throw InputError::at(origin, 0, "camera_matrix", "not 3x3");
  c.fx = k[0];
  c.cx = k[2];
  c.fy = k[4];
  c.cy = k[5];
  if (!(c.fx > 0.0) || !(c.fy > 0.0) || k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || k[8] != 1.0)
    throw InputError::at(origin, 0, "camera_matrix",
                         "not a camera matrix [fx 0 cx; 0 fy cy; 0 0 1] with positive focal lengths");
  if (std::abs(k[1]) > 1e-6 * c.fx) throw InputError::at(origin, 0, "camera_matrix", "skewed pixels are not supported");
  // Images are at most 16384 px wide: a focal length or principal point
  // beyond these is no camera, and pixels near 1e18 lose every digit a
  // round trip through the lens model needs (found by fuzz_camera_calibration).
  if (c.fx > kMaxFocalPx || c.fy > kMaxFocalPx)
    throw InputError::at(origin, 0, "camera_matrix", "focal length beyond 1e6 px: not a camera matrix");
  if (std::abs(c.cx) > kMaxCentrePx || std::abs(c.cy) > kMaxCentrePx)
    throw InputError::at(origin, 0, "camera_matrix", "principal point beyond 1e5 px of the image: not a camera matrix");
  if (root["distortion_coefficients"]) {
    const auto d = matrix(root, origin, "distortion_coefficients", rows, cols);
    if (rows != 1 && cols != 1) throw InputError::at(origin, 0, "distortion_coefficients", "not a row or a column");
    const std::size_t n = d.size();
    if (n != 4 && n != 5 && n != 8 && n != 12 && n != 14)
      throw InputError::at(origin, 0, "distortion_coefficients",
                           std::to_string(n) + " coefficients (OpenCV writes 4, 5, 8, 12 or 14)");
    if (n == 14 && (d[12] != 0.0 || d[13] != 0.0))
      throw InputError::at(origin, 0, "distortion_coefficients", "tilted-sensor terms (13 and 14) are not supported");
    for (std::size_t i = 0; i < std::min<std::size_t>(n, 12); ++i) c.distortion[i] = d[i];
  }
  const YAML::Node w = root["image_width"], h = root["image_height"];
  if (static_cast<bool>(w) != static_cast<bool>(h))
    throw InputError::at(origin, 0, w ? "image_height" : "image_width", "missing (give both or neither)");
  if (w) {
    const double wv = number(w, origin, "image_width"), hv = number(h, origin, "image_height");
    if (wv < 16 || wv > 16384 || wv != std::floor(wv))
      throw InputError::at(origin, w.Mark().line + 1, "image_width", "not a width 16-16384");
    if (hv < 16 || hv > 16384 || hv != std::floor(hv))
      throw InputError::at(origin, h.Mark().line + 1, "image_height", "not a height 16-16384");
    c.image_width = static_cast<int>(wv);
    c.image_height = static_cast<int>(hv);
  }
  return c;
}

}  // namespace

bool CameraCalibration::distorted() const {
  for (const double d : distortion)
    if (d != 0.0) return true;
  return false;
}

CameraCalibration CameraCalibration::scaled_to(int width, int height, std::string_view origin) const {
  if (image_width <= 0 || (image_width == width && image_height == height)) return *this;
  const double sx = static_cast<double>(width) / image_width, sy = static_cast<double>(height) / image_height;
  if (std::abs(sx / sy - 1.0) > 0.01)
    throw InputError::at(origin, 0, "image_width",
                         "calibrated at " + std::to_string(image_width) + "x" + std::to_string(image_height) +
                             " but capturing " + std::to_string(width) + "x" + std::to_string(height) +
                             " (another aspect ratio: the camera crops; calibrate at this resolution)");
  CameraCalibration c = *this;
  // Pixel centres sit at integer coordinates: scale about the image's corner.
  c.fx *= sx;
  c.fy *= sy;
  c.cx = (cx + 0.5) * sx - 0.5;
  c.cy = (cy + 0.5) * sy - 0.5;
  c.image_width = width;
  c.image_height = height;
  return c;
}

tracker::Camera CameraCalibration::camera(int width, int height) const {
  tracker::Camera cam;
  cam.fx = fx;
  cam.fy = fy;
  cam.cx = cx;
  cam.cy = cy;
  cam.width = width;
  cam.height = height;
  return cam;
}

tracker::Vec2 CameraCalibration::distort(const tracker::Vec2& px) const {
  const auto& d = distortion;
  const double x = (px.x() - cx) / fx, y = (px.y() - cy) / fy;
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double radial = (1 + d[0] * r2 + d[1] * r4 + d[4] * r6) / (1 + d[5] * r2 + d[6] * r4 + d[7] * r6);
  const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x) + d[8] * r2 + d[9] * r4;
  const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y + d[10] * r2 + d[11] * r4;
  return {fx * xd + cx, fy * yd + cy};
}

tracker::Vec2 CameraCalibration::undistort_fixed_point(const tracker::Vec2& px, int iterations) const {
  if (!distorted() || !px.allFinite()) return px;
  const auto& d = distortion;
  const double x0 = (px.x() - cx) / fx, y0 = (px.y() - cy) / fy;
  double x = x0, y = y0;
  // cv::undistortPoints' fixed point: x = (x_d - tangential(x)) / radial(x).
  for (int i = 0; i < iterations; ++i) {
    const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
    const double icdist = (1 + d[5] * r2 + d[6] * r4 + d[7] * r6) / (1 + d[0] * r2 + d[1] * r4 + d[4] * r6);
    if (!(icdist > 0.0)) return px;  // beyond where the model is invertible
    const double dx = 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x) + d[8] * r2 + d[9] * r4;
    const double dy = d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y + d[10] * r2 + d[11] * r4;
    x = (x0 - dx) * icdist;
    y = (y0 - dy) * icdist;
  }
  const tracker::Vec2 out(fx * x + cx, fy * y + cy);
  return out.allFinite() ? out : px;
}

std::optional<tracker::Vec2> CameraCalibration::undistort(const tracker::Vec2& px) const {
  if (!px.allFinite()) return std::nullopt;
  if (!distorted()) return px;
  // Start where OpenCV's fixed point gets in a few steps (close for gentle
  // lenses), then Newton's method on distort(u) = px, with the Jacobian by
  // central differences, halving a step that does not reduce the residual.
  // A strong barrel lens (k1 = -0.44) leaves the fixed point pixels off in
  // the corners after 20 steps; Newton reaches 1e-6 px in a handful.
  tracker::Vec2 u = undistort_fixed_point(px, 5);
  if (!u.allFinite()) u = px;
  const double h = 1e-6 * std::max(fx, fy);  // a millionth of a focal length, in pixels
  auto residual = [&](const tracker::Vec2& v) { return tracker::Vec2(distort(v) - px); };
  tracker::Vec2 r = residual(u);
  for (int i = 0; i < 60 && r.allFinite(); ++i) {
    if (r.norm() <= kUndistortTolerancePx) {
      // On the unfolded branch: the model must still preserve orientation here.
      const tracker::Vec2 jx = (distort(u + tracker::Vec2(h, 0)) - distort(u - tracker::Vec2(h, 0))) / (2 * h);
      const tracker::Vec2 jy = (distort(u + tracker::Vec2(0, h)) - distort(u - tracker::Vec2(0, h))) / (2 * h);
      if (!(jx.x() * jy.y() - jx.y() * jy.x() > 0.0)) return std::nullopt;
      return u;
    }
    const tracker::Vec2 jx = (distort(u + tracker::Vec2(h, 0)) - distort(u - tracker::Vec2(h, 0))) / (2 * h);
    const tracker::Vec2 jy = (distort(u + tracker::Vec2(0, h)) - distort(u - tracker::Vec2(0, h))) / (2 * h);
    const double det = jx.x() * jy.y() - jx.y() * jy.x();
    if (!(det > 0.0) || !std::isfinite(det)) return std::nullopt;  // folded: no unique ideal pixel here
    const tracker::Vec2 step((jy.y() * r.x() - jy.x() * r.y()) / det, (-jx.y() * r.x() + jx.x() * r.y()) / det);
    double scale = 1.0;
    tracker::Vec2 next = u - step;
    tracker::Vec2 rn = residual(next);
    for (int k = 0; k < 20 && !(rn.allFinite() && rn.norm() < r.norm()); ++k) {
      scale *= 0.5;
      next = u - scale * step;
      rn = residual(next);
    }
    if (!(rn.allFinite() && rn.norm() < r.norm())) return std::nullopt;  // no way down: not invertible here
    u = next;
    r = rn;
  }
  return std::nullopt;
}

CameraCalibration parse_camera_calibration(std::string_view text, std::string_view origin) {
  if (text.size() > kMaxFileBytes) throw InputError::at(origin, 0, "", "larger than 256 KiB: not a calibration file");
  std::string body(text);
  // OpenCV's first line, "%YAML:1.0", is a directive yaml-cpp rejects (it
  // wants "%YAML 1.0"); blank it, keeping the line numbers.
  if (body.starts_with("%YAML:")) body.replace(0, body.find('\n') == std::string::npos ? body.size() : body.find('\n'), "");
  check_nesting(body, origin);
  try {
    return from_yaml(YAML::Load(body), origin);
  } catch (const YAML::Exception& e) {
    throw InputError::at(origin, e.mark.is_null() ? 0 : e.mark.line + 1, "", "not valid YAML: " + e.msg);
  }
}

CameraCalibration load_camera_calibration(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError::at(path.string(), 0, "", "cannot open the calibration file");
  std::string text;
  text.resize(kMaxFileBytes + 1);
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  return parse_camera_calibration(text, path.string());
}

double focal_from_fov(int width, double horizontal_fov_deg) {
  return 0.5 * width / std::tan(0.5 * horizontal_fov_deg * std::numbers::pi / 180.0);
}

}  // namespace earshot::webcam
