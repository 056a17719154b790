#include "earshot/webcam/v4l2_camera.hpp"

#include <fcntl.h>
#include <libv4l2.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <system_error>

namespace earshot::webcam {
namespace {

using Kind = CameraError::Kind;

int xioctl(int fd, unsigned long request, void* arg) {
  int r = 0;
  do r = v4l2_ioctl(fd, request, arg);
  while (r == -1 && errno == EINTR);
  return r;
}

std::string errno_text(int err) { return std::generic_category().message(err); }

double monotonic_now() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Every (size, interval) the camera offers in `fourcc`: stepwise ranges
/// contribute their largest size and a few of their steps.
void enumerate_modes(int fd, std::uint32_t fourcc, std::vector<CaptureMode>& out) {
  std::vector<std::pair<int, int>> sizes;
  v4l2_frmsizeenum fs{};
  fs.pixel_format = fourcc;
  for (fs.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMESIZES, &fs) == 0 && fs.index < 256; ++fs.index) {
    if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
      sizes.emplace_back(static_cast<int>(fs.discrete.width), static_cast<int>(fs.discrete.height));
    } else {
      // Stepwise or continuous: the common sizes inside the range.
      for (const auto& [w, h] : {std::pair{320, 240}, {640, 480}, {800, 600}, {1280, 720}, {1920, 1080}})
        if (static_cast<std::uint32_t>(w) >= fs.stepwise.min_width && static_cast<std::uint32_t>(w) <= fs.stepwise.max_width &&
            static_cast<std::uint32_t>(h) >= fs.stepwise.min_height && static_cast<std::uint32_t>(h) <= fs.stepwise.max_height)
          sizes.emplace_back(w, h);
      break;
    }
  }
  for (const auto& [w, h] : sizes) {
    v4l2_frmivalenum fi{};
    fi.pixel_format = fourcc;
    fi.width = static_cast<std::uint32_t>(w);
    fi.height = static_cast<std::uint32_t>(h);
    bool any = false;
    for (fi.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMEINTERVALS, &fi) == 0 && fi.index < 256; ++fi.index) {
      const v4l2_fract f = fi.type == V4L2_FRMIVAL_TYPE_DISCRETE ? fi.discrete : fi.stepwise.min;
      if (f.numerator == 0 || f.denominator == 0) continue;
      out.push_back({fourcc, w, h, static_cast<int>(f.numerator), static_cast<int>(f.denominator)});
      any = true;
      if (fi.type != V4L2_FRMIVAL_TYPE_DISCRETE) break;
    }
    if (!any) out.push_back({fourcc, w, h, 1, 30});  // no rates listed: assume the usual
  }
}

}  // namespace

CameraError camera_open_error(const std::string& device, int err, const std::vector<std::string>& cameras) {
  switch (err) {
    case ENOENT:
    case ENODEV:
    case ENXIO: {
      std::string list;
      for (const auto& c : cameras) list += (list.empty() ? "" : ", ") + c;
      return {Kind::no_device, "no camera at " + device + "; connected cameras: " +
                                   (list.empty() ? std::string("none (is it plugged in? `v4l2-ctl --list-devices` lists them)")
                                                 : list)};
    }
    case EBUSY:
      return {Kind::busy, device + " is busy: another program is using the camera (close it; `fuser " + device +
                              "` shows which)"};
    case EACCES:
    case EPERM:
      return {Kind::permission, "no permission to open " + device +
                                    ": the user is not in the 'video' group (run `sudo usermod -aG video $USER`, then log "
                                    "out and in again)"};
    default: return {Kind::io, "cannot open " + device + ": " + errno_text(err)};
  }
}

std::vector<std::string> list_video_devices(const std::filesystem::path& dir) {
  std::vector<std::pair<long, std::string>> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!name.starts_with("video") || name.size() == 5) continue;
    char* end = nullptr;
    const long n = std::strtol(name.c_str() + 5, &end, 10);
    if (*end == '\0') found.emplace_back(n, e.path().string());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  for (auto& f : found) out.push_back(std::move(f.second));
  return out;
}

std::optional<CaptureMode> choose_capture_mode(std::span<const CaptureMode> offered, int max_width, int max_height,
                                               int max_fps) {
  std::optional<CaptureMode> best;
  for (const auto& m : offered) {
    if (m.width > max_width || m.height > max_height || m.width <= 0 || m.height <= 0) continue;
    if (m.interval_num <= 0 || m.interval_den <= 0) continue;
    if (max_fps > 0 && m.fps() > max_fps + 0.5) continue;
    if (!best || m.fps() > best->fps() + 1e-6 ||
        (m.fps() > best->fps() - 1e-6 && m.width * m.height > best->width * best->height))
      best = m;
  }
  return best;
}

std::string fourcc_name(std::uint32_t f) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((f >> (8 * i)) & 0xff);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

V4l2Camera::V4l2Camera(std::string device, const V4l2Options& options) : device_(std::move(device)) {
  open_device();
  try {
    choose_mode(options);
    set_format();
    set_frame_rate();
    start_streaming();
  } catch (...) {
    close();
    throw;
  }
}

// Plain open and QUERYCAP first: v4l2_open refuses a non-V4L2 file with only
// ENOTTY (and a line on stderr); this way each case has its message. Then
// libv4l2 over the descriptor (it converts what the camera sends).
void V4l2Camera::open_device() {
  const int fd = ::open(device_.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw camera_open_error(device_, errno, list_video_devices());
  v4l2_capability cap{};
  int r = 0;
  do r = ::ioctl(fd, VIDIOC_QUERYCAP, &cap);
  while (r == -1 && errno == EINTR);
  if (r != 0) {
    const int err = errno;
    ::close(fd);
    throw CameraError(Kind::not_capture, device_ + " is not a video device (" + errno_text(err) + "); cameras are " +
                                             "/dev/videoN (" + std::to_string(list_video_devices().size()) + " here)");
  }
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  name_ = reinterpret_cast<const char*>(cap.card);
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
    ::close(fd);
    throw CameraError(Kind::not_capture, device_ + " (" + name_ + ") is not a video capture device that streams (a "
                                             "camera's metadata node? try the other /dev/video numbers)");
  }
  fd_ = v4l2_fd_open(fd, 0);
  if (fd_ < 0) {
    const int err = errno;
    ::close(fd);
    throw CameraError(Kind::io, device_ + ": libv4l2 cannot use it: " + errno_text(err));
  }
}

// Every mode in every format, libv4l2's converted ones included; the largest
// within the options' limits at the highest rate.
void V4l2Camera::choose_mode(const V4l2Options& options) {
  std::vector<CaptureMode> modes;
  v4l2_fmtdesc desc{};
  desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (desc.index = 0; xioctl(fd_, VIDIOC_ENUM_FMT, &desc) == 0 && desc.index < 64; ++desc.index) {
    formats_ += (formats_.empty() ? "" : ", ") + fourcc_name(desc.pixelformat);
    enumerate_modes(fd_, desc.pixelformat, modes);
  }
  const auto chosen = choose_capture_mode(modes, options.max_width, options.max_height, options.max_fps);
  if (!chosen)
    throw CameraError(Kind::no_format, device_ + " (" + name_ + ") offers no size at or below " +
                                           std::to_string(options.max_width) + "x" + std::to_string(options.max_height) +
                                           (options.max_fps ? " at " + std::to_string(options.max_fps) + " fps or less" : "") +
                                           " (formats: " + (formats_.empty() ? "none" : formats_) + ")");
  mode_ = *chosen;
}

// Luma in the chosen size; libv4l2 converts when the camera sends something else.
void V4l2Camera::set_format() {
  v4l2_format f{};
  bool set = false;
  for (const std::uint32_t want : {V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_YUV420, V4L2_PIX_FMT_YUYV}) {
    f = {};
    f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    f.fmt.pix.width = static_cast<std::uint32_t>(mode_.width);
    f.fmt.pix.height = static_cast<std::uint32_t>(mode_.height);
    f.fmt.pix.pixelformat = want;
    f.fmt.pix.field = V4L2_FIELD_NONE;
    if (xioctl(fd_, VIDIOC_S_FMT, &f) != 0) {
      if (errno == EBUSY) throw camera_open_error(device_, EBUSY, {});
      continue;
    }
    if (f.fmt.pix.pixelformat == want) {
      set = true;
      break;
    }
  }
  if (!set)
    throw CameraError(Kind::no_format, device_ + " (" + name_ + "): no format libv4l2 turns into grey, YUV420 or YUYV (formats: " +
                                           formats_ + ")");
  format_ = f.fmt.pix.pixelformat;
  mode_.width = static_cast<int>(f.fmt.pix.width);
  mode_.height = static_cast<int>(f.fmt.pix.height);
  bytes_per_line_ = f.fmt.pix.bytesperline ? f.fmt.pix.bytesperline
                                           : static_cast<std::ptrdiff_t>(mode_.width) * (format_ == V4L2_PIX_FMT_YUYV ? 2 : 1);
}

// The chosen mode's frame interval, and what the driver made of it.
void V4l2Camera::set_frame_rate() {
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  parm.parm.capture.timeperframe.numerator = static_cast<std::uint32_t>(mode_.interval_num);
  parm.parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(mode_.interval_den);
  if (xioctl(fd_, VIDIOC_S_PARM, &parm) == 0 && parm.parm.capture.timeperframe.numerator > 0 &&
      parm.parm.capture.timeperframe.denominator > 0) {
    mode_.interval_num = static_cast<int>(parm.parm.capture.timeperframe.numerator);
    mode_.interval_den = static_cast<int>(parm.parm.capture.timeperframe.denominator);
  }
}

// Four mapped buffers queued, and the stream on.
void V4l2Camera::start_streaming() {
  v4l2_requestbuffers req{};
  req.count = 4;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_REQBUFS, &req) != 0) {
    if (errno == EBUSY) throw camera_open_error(device_, EBUSY, {});
    throw CameraError(Kind::io, device_ + ": cannot get capture buffers: " + errno_text(errno));
  }
  if (req.count < 2) throw CameraError(Kind::io, device_ + ": the driver gave fewer than two capture buffers");
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (xioctl(fd_, VIDIOC_QUERYBUF, &b) != 0)
      throw CameraError(Kind::io, device_ + ": cannot query capture buffer: " + errno_text(errno));
    void* p = v4l2_mmap(nullptr, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, b.m.offset);
    if (p == MAP_FAILED) throw CameraError(Kind::io, device_ + ": cannot map capture buffer: " + errno_text(errno));
    buffers_.push_back({p, b.length});
    if (xioctl(fd_, VIDIOC_QBUF, &b) != 0)
      throw CameraError(Kind::io, device_ + ": cannot queue capture buffer: " + errno_text(errno));
  }
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) != 0) {
    if (errno == EBUSY) throw camera_open_error(device_, EBUSY, {});
    throw CameraError(Kind::io, device_ + ": cannot start streaming: " + errno_text(errno));
  }
  streaming_ = true;
}

V4l2Camera::~V4l2Camera() { close(); }

void V4l2Camera::close() {
  if (fd_ < 0) return;
  if (streaming_) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    (void)xioctl(fd_, VIDIOC_STREAMOFF, &type);
    streaming_ = false;
  }
  for (const auto& b : buffers_) v4l2_munmap(b.start, b.length);
  buffers_.clear();
  v4l2_close(fd_);
  fd_ = -1;
}

void V4l2Camera::requeue() {
  if (queued_out_ < 0) return;
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  b.index = static_cast<std::uint32_t>(queued_out_);
  queued_out_ = -1;
  if (xioctl(fd_, VIDIOC_QBUF, &b) != 0)
    throw CameraError(Kind::disconnected, device_ + " stopped answering (" + errno_text(errno) + ")");
}

std::optional<V4l2Camera::Frame> V4l2Camera::next(std::chrono::milliseconds timeout) {
  requeue();
  pollfd p{fd_, POLLIN, 0};
  const int r = ::poll(&p, 1, static_cast<int>(std::max<long>(0, timeout.count())));
  if (r < 0 && errno != EINTR) throw CameraError(Kind::disconnected, device_ + ": " + errno_text(errno));
  if (r <= 0) return std::nullopt;
  // POLLERR may come with a buffer still waiting: DQBUF decides whether the camera is gone.
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &b) != 0) {
    if (errno == EAGAIN) return std::nullopt;
    throw CameraError(Kind::disconnected, device_ + " disconnected (" + errno_text(errno) + ")");
  }
  queued_out_ = static_cast<int>(b.index);
  if (b.index >= buffers_.size()) throw CameraError(Kind::io, device_ + ": the driver returned an unknown buffer");
  const auto* data = static_cast<const std::uint8_t*>(buffers_[b.index].start);
  const std::size_t used = std::min<std::size_t>(b.bytesused ? b.bytesused : buffers_[b.index].length,
                                                 buffers_[b.index].length);
  Frame f;
  f.width = mode_.width;
  f.height = mode_.height;
  f.sequence = b.sequence;
  f.t = (b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC
            ? static_cast<double>(b.timestamp.tv_sec) + 1e-6 * static_cast<double>(b.timestamp.tv_usec)
            : monotonic_now();
  const std::size_t w = static_cast<std::size_t>(f.width), h = static_cast<std::size_t>(f.height);
  const std::size_t bpl = static_cast<std::size_t>(bytes_per_line_);
  if (format_ == V4L2_PIX_FMT_YUYV) {
    if (used < bpl * (h - 1) + 2 * w) return std::nullopt;  // a short frame: skip it
    luma_.resize(w * h);
    for (std::size_t y = 0; y < h; ++y) {
      const std::uint8_t* row = data + y * bpl;
      std::uint8_t* out = luma_.data() + y * w;
      for (std::size_t x = 0; x < w; ++x) out[x] = row[2 * x];
    }
    f.pixels = luma_;
    f.stride = static_cast<std::ptrdiff_t>(w);
  } else {
    if (used < bpl * (h - 1) + w) return std::nullopt;
    f.pixels = std::span(data, used);
    f.stride = bytes_per_line_;
  }
  return f;
}

}  // namespace earshot::webcam
