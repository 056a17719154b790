#include "earshot/webcam/webcam_source.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <thread>

#include "earshot/errors.hpp"

namespace earshot::webcam {
namespace {

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string mode_text(int w, int h, double fps) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%dx%d @ %.3g fps", w, h, fps);
  return buf;
}

}  // namespace

tracker::LedModel tag_model(double size_mm) {
  tracker::LedModel m;
  const auto corners = tag_corners_mm(size_mm);
  for (std::size_t k = 0; k < 4; ++k) m.leds_mm[k] = tracker::Vec3(corners[k][0], corners[k][1], corners[k][2]);
  m.axis = tracker::Vec3(0.0, 0.0, -1.0);
  m.half_angle = 80.0 * std::numbers::pi / 180.0;  // a printed tag reads until nearly edge-on
  return m;
}

WebcamSource::WebcamSource(WebcamSpec spec, std::unique_ptr<DotDetector> detector, const WebcamOptions& options)
    : spec_(std::move(spec)),
      detector_(std::move(detector)),
      pacing_(options.pacing),
      wait_for_device_(options.wait_for_device) {
  if (!detector_) throw std::invalid_argument("WebcamSource: no detector");
  if (!spec_.calib.empty()) calib_ = load_camera_calibration(spec_.calib);
  if (spec_.is_file()) {
    file_ = std::make_unique<Y4mReader>(spec_.device);
    const auto& h = file_->header();
    set_camera_model(h.width, h.height);
    mode_ = mode_text(h.width, h.height, h.fps());
    ever_connected_ = announce_ = true;
    return;
  }
  std::string why;
  if (!open(why) && !wait_for_device_) throw CameraError(CameraError::Kind::no_device, why);
}

WebcamSource::~WebcamSource() = default;

bool WebcamSource::open(std::string& why) {
  next_attempt_ = steady_seconds() + kRetrySeconds;
  V4l2Options o;
  if (spec_.max_width > 0) {
    o.max_width = spec_.max_width;
    o.max_height = spec_.max_height;
  }
  o.max_fps = spec_.max_fps;
  try {
    auto cam = std::make_unique<V4l2Camera>(spec_.device, o);
    const CaptureMode& m = cam->mode();
    set_camera_model(m.width, m.height);  // a calibration that does not fit throws: the person's to fix
    mode_ = mode_text(m.width, m.height, m.fps());
    device_ = std::move(cam);
  } catch (const CameraError& e) {
    // Before the camera ever worked, a failure is the person's to fix.
    if (!ever_connected_ && !wait_for_device_) throw;
    why = e.what();
    return false;
  }
  ever_connected_ = announce_ = true;
  return true;
}

tracker::Camera centred_camera(double f, int width, int height) {
  tracker::Camera c = tracker::Camera::with_focal(f, width, height);
  // Pixel centres at whole numbers: the centre of W pixels is (W - 1) / 2.
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  return c;
}

UndistortedImage undistorted_image(const CameraCalibration& lens, int width, int height) {
  // The raw image's border, every few pixels, and its corners: where the
  // lens sends them is the ideal image's extent (a barrel lens pushes the
  // corners out; a pincushion one pulls the edges in, and the raw image's
  // own rectangle is kept).
  double x0 = 0.0, y0 = 0.0, x1 = width - 1.0, y1 = height - 1.0;
  auto take = [&](double x, double y) {
    if (const auto u = lens.undistort(tracker::Vec2(x, y))) {
      x0 = std::min(x0, u->x()), x1 = std::max(x1, u->x());
      y0 = std::min(y0, u->y()), y1 = std::max(y1, u->y());
    }
  };
  constexpr int kStep = 4;
  for (int x = 0; x < width; x += kStep) take(x, 0), take(x, height - 1.0);
  for (int y = 0; y < height; y += kStep) take(0, y), take(width - 1.0, y);
  take(width - 1.0, height - 1.0);
  UndistortedImage out;
  out.offset = tracker::Vec2(-std::floor(x0), -std::floor(y0));
  out.width = static_cast<int>(std::ceil(x1 + out.offset.x())) + 1;
  out.height = static_cast<int>(std::ceil(y1 + out.offset.y())) + 1;
  return out;
}

void WebcamSource::set_camera_model(int width, int height) {
  lens_.reset();
  offset_ = tracker::Vec2::Zero();
  if (calib_) {
    const CameraCalibration c = calib_->scaled_to(width, height, spec_.calib);
    tracker::Camera cam = c.camera(width, height);
    if (spec_.focal_px) cam.fx = cam.fy = *spec_.focal_px;
    if (c.distorted()) {
      // The dots are undistorted into the ideal camera's pixels; corners
      // the lens moves beyond the raw image are still in its view, so the
      // ideal image grows to hold them (shifted so it starts at 0, 0).
      lens_ = c;
      const UndistortedImage u = undistorted_image(c, width, height);
      offset_ = u.offset;
      cam.cx += u.offset.x();
      cam.cy += u.offset.y();
      cam.width = u.width;
      cam.height = u.height;
    }
    camera_ = cam;
    camera_note_ = "camera model from " + spec_.calib + (spec_.focal_px ? " (focal length from focal=)" : "");
    return;
  }
  if (spec_.focal_px) {
    camera_ = centred_camera(*spec_.focal_px, width, height);
    camera_note_ = "focal length " + std::to_string(static_cast<int>(std::lround(*spec_.focal_px))) + " px (focal=)";
    return;
  }
  const double f = focal_from_fov(width, kGuessedFovDeg);
  camera_ = centred_camera(f, width, height);
  camera_note_ = "focal length guessed (" + std::to_string(static_cast<int>(std::lround(f))) +
                 " px, a 60 deg horizontal field of view): distances and positions are only roughly right; give "
                 "focal=PIXELS or calib=FILE (OpenCV's calibration YAML) for accurate ones";
}

std::optional<tracker::LedModel> WebcamSource::model() const {
  if (spec_.beacon == WebcamSpec::Beacon::apriltag) return tag_model(spec_.size_mm);
  return std::nullopt;
}

std::string WebcamSource::describe() const {
  return "webcam:" + spec_.device + " (" + (mode_.empty() ? std::string("not connected") : mode_) + ", " +
         detector_->describe() + ")";
}

tracker::SourceEvent WebcamSource::next(std::chrono::milliseconds timeout) {
  if (announce_) {
    announce_ = false;
    const std::string what = file_ ? "video " + spec_.device : "camera " + spec_.device +
                                                                   (device_ && !device_->name().empty() ? " (" + device_->name() + ")" : "");
    return make_note(tracker::SourceNote::Kind::connected, what + ": " + mode_ + ", " + detector_->describe() + "; " + camera_note_);
  }
  return file_ ? next_from_file(timeout) : next_from_camera(timeout);
}

tracker::SourceEvent WebcamSource::next_from_file(std::chrono::milliseconds timeout) {
  const double fps = file_->header().fps();
  const long index = file_->frames();  // the frame about to be read, from 0
  const double t = static_cast<double>(index) / fps;
  if (pacing_ == tracker::Pacing::real_time) {
    if (index == 0) file_start_ = std::chrono::steady_clock::now();
    const auto due = file_start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                       std::chrono::duration<double>(t));
    const auto now = std::chrono::steady_clock::now();
    if (due > now) {
      if (due - now > timeout) {
        std::this_thread::sleep_for(timeout);
        return make_note(tracker::SourceNote::Kind::timeout);
      }
      std::this_thread::sleep_until(due);
    }
  }
  const auto luma = file_->next();
  if (luma.empty())
    return make_note(tracker::SourceNote::Kind::ended, "video " + spec_.device + " ended after " + std::to_string(index) + " frames", t);
  const auto& h = file_->header();
  return frame_event(GrayView{luma, h.width, h.height, h.width}, t);
}

tracker::SourceEvent WebcamSource::next_from_camera(std::chrono::milliseconds timeout) {
  if (!device_) {
    const double wait = next_attempt_ - steady_seconds();
    if (wait > 0.0) {
      std::this_thread::sleep_for(
          std::min(timeout, std::chrono::milliseconds(static_cast<long>(wait * 1000.0) + 1)));
      return make_note(tracker::SourceNote::Kind::timeout);
    }
    std::string why;
    if (open(why)) return next(timeout);  // the connected note
    if (!ever_connected_) return make_note(tracker::SourceNote::Kind::searching, why);
    return make_note(tracker::SourceNote::Kind::timeout);
  }
  try {
    const auto f = device_->next(timeout);
    if (!f) return make_note(tracker::SourceNote::Kind::timeout);
    return frame_event(GrayView{f->pixels, f->width, f->height, f->stride}, f->t);
  } catch (const CameraError& e) {
    if (e.kind() != CameraError::Kind::disconnected && e.kind() != CameraError::Kind::io) throw;
    device_.reset();
    next_attempt_ = steady_seconds() + kRetrySeconds;
    return make_note(tracker::SourceNote::Kind::disconnected,
                     std::string(e.what()) + "; reconnecting (plug it in again, or close the program using it)");
  }
}

tracker::SourceEvent WebcamSource::frame_event(const GrayView& view, double t) {
  const Detection d = detector_->detect(view);
  ++frames_;
  tracker::CameraFrame f;
  f.dots.t = t;
  f.labelled = d.labelled;
  const int n = std::clamp(d.count, 0, static_cast<int>(tracker::kSlots));
  for (int k = 0; k < n; ++k) {
    const auto& p = d.points[static_cast<std::size_t>(k)];
    const tracker::Vec2 px(p.x, p.y);
    // A dot the lens model cannot undistort (it folds there) is no dot.
    if (!lens_) f.dots.slots[static_cast<std::size_t>(k)] = px;
    else if (const auto u = lens_->undistort(px)) f.dots.slots[static_cast<std::size_t>(k)] = tracker::Vec2(*u + offset_);
    f.dot_size[static_cast<std::size_t>(k)] =
        std::isfinite(p.size) ? static_cast<int>(std::lround(std::clamp(p.size, 0.0, 1e6))) : -1;
  }
  update_thumbnail(view, d, t);
  return f;
}

void WebcamSource::update_thumbnail(const GrayView& v, const Detection& d, double t) {
  tracker::Thumbnail& th = scratch_;
  // The largest size with the frame's aspect that fits 160x120.
  const double scale = std::min(static_cast<double>(tracker::Thumbnail::kMaxWidth) / v.width,
                                static_cast<double>(tracker::Thumbnail::kMaxHeight) / v.height);
  th.width = std::clamp(static_cast<int>(std::lround(v.width * scale)), 1, tracker::Thumbnail::kMaxWidth);
  th.height = std::clamp(static_cast<int>(std::lround(v.height * scale)), 1, tracker::Thumbnail::kMaxHeight);
  // Box filter: each thumbnail pixel averages the frame pixels it covers.
  for (int ty = 0; ty < th.height; ++ty) {
    const int y0 = ty * v.height / th.height, y1 = std::max(y0 + 1, (ty + 1) * v.height / th.height);
    for (int tx = 0; tx < th.width; ++tx) {
      const int x0 = tx * v.width / th.width, x1 = std::max(x0 + 1, (tx + 1) * v.width / th.width);
      unsigned sum = 0;
      for (int y = y0; y < y1; ++y) {
        const std::uint8_t* row = v.pixels.data() + y * v.stride;
        for (int x = x0; x < x1; ++x) sum += row[x];
      }
      th.pixels[static_cast<std::size_t>(ty * th.width + tx)] =
          static_cast<std::uint8_t>(sum / static_cast<unsigned>((y1 - y0) * (x1 - x0)));
    }
  }
  const double sx = static_cast<double>(th.width) / v.width, sy = static_cast<double>(th.height) / v.height;
  for (std::size_t k = 0; k < tracker::kSlots; ++k) {
    th.dots[k].reset();
    if (static_cast<int>(k) < d.count) th.dots[k] = tracker::Vec2((d.points[k].x + 0.5) * sx - 0.5, (d.points[k].y + 0.5) * sy - 0.5);
  }
  th.labelled = d.labelled;
  th.frame = frames_;
  th.t = t;
  std::lock_guard lock(thumb_mutex_);
  thumb_ = th;
}

bool WebcamSource::thumbnail(tracker::Thumbnail& out) const {
  std::lock_guard lock(thumb_mutex_);
  if (thumb_.width == 0) return false;
  out = thumb_;
  return true;
}

}  // namespace earshot::webcam
