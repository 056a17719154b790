// A V4L2 webcam through libv4l2, grey frames out.
//
// libv4l2 converts what the camera sends (MJPEG, YUYV, Bayer...) into the
// format asked for; this asks for GREY, YUV420 or YUYV and keeps the luma.
// The mode: the highest frame rate the camera offers at a size no larger
// than the requested one (default 1280x720), largest size among those.
// Frames stream through mmap buffers; timestamps come from the buffers.
//
// Every way a camera can be unusable has its own error kind and a message
// that says what to do: no such device (listing the cameras there are),
// busy, no permission, not a capture device, no format libv4l2 can turn
// into grey. A camera unplugged while streaming throws CameraError with
// kind `disconnected` from next().
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace earshot::webcam {

class CameraError : public std::runtime_error {
 public:
  enum class Kind { no_device, busy, permission, not_capture, no_format, disconnected, io };
  CameraError(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  [[nodiscard]] Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

/// The message and kind for an errno from opening (or first using) `device`
/// (ENOENT/ENODEV/ENXIO: no camera, EBUSY, EACCES/EPERM, others as strerror).
/// `cameras` are the video devices there are, for the no-camera message.
[[nodiscard]] CameraError camera_open_error(const std::string& device, int err, const std::vector<std::string>& cameras);

/// /dev/video* (or `dir`/video*), sorted by number.
[[nodiscard]] std::vector<std::string> list_video_devices(const std::filesystem::path& dir = "/dev");

/// One size and rate a camera offers in one pixel format.
struct CaptureMode {
  std::uint32_t fourcc = 0;
  int width = 0, height = 0;
  int interval_num = 1, interval_den = 30;  ///< seconds per frame, num / den

  [[nodiscard]] double fps() const { return static_cast<double>(interval_den) / interval_num; }
};

/// The mode to use: sizes at most max_width x max_height, rates at most
/// max_fps (0: any); the highest rate, then the largest area. nullopt when
/// nothing fits.
[[nodiscard]] std::optional<CaptureMode> choose_capture_mode(std::span<const CaptureMode> offered, int max_width,
                                                             int max_height, int max_fps);

/// "YUYV", "MJPG", ... for messages.
[[nodiscard]] std::string fourcc_name(std::uint32_t fourcc);

struct V4l2Options {
  int max_width = 1280;
  int max_height = 720;
  int max_fps = 0;  ///< 0: the highest offered
};

class V4l2Camera {
 public:
  /// One frame's luma, valid until the next call of next() or destruction.
  struct Frame {
    std::span<const std::uint8_t> pixels;
    int width = 0, height = 0;
    std::ptrdiff_t stride = 0;
    double t = 0.0;              ///< seconds, CLOCK_MONOTONIC (the buffer's timestamp)
    std::uint32_t sequence = 0;  ///< the driver's frame counter (gaps: dropped frames)
  };

  /// Opens, chooses the mode and starts streaming. Throws CameraError.
  V4l2Camera(std::string device, const V4l2Options& options = {});
  ~V4l2Camera();
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  /// The next frame, waiting at most `timeout`; nullopt when none came.
  /// Throws CameraError (kind disconnected) when the camera went away.
  std::optional<Frame> next(std::chrono::milliseconds timeout);

  [[nodiscard]] const std::string& device() const { return device_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const CaptureMode& mode() const { return mode_; }

 private:
  // The steps of opening the camera, in order.
  void open_device();                          // the device, checked to capture and stream
  void choose_mode(const V4l2Options& options);  // size and rate among all it offers
  void set_format();                           // luma (grey, YUV420 or YUYV) in that size
  void set_frame_rate();
  void start_streaming();                      // buffers mapped and queued, stream on
  void close();
  void requeue();

  std::string device_;
  std::string name_;  ///< the driver's card name
  int fd_ = -1;
  std::string formats_;  // the formats it offers, for messages
  CaptureMode mode_;
  std::uint32_t format_ = 0;   ///< the format frames arrive in (GREY, YU12, YUYV)
  std::ptrdiff_t bytes_per_line_ = 0;
  struct Buffer {
    void* start = nullptr;
    std::size_t length = 0;
  };
  std::vector<Buffer> buffers_;
  int queued_out_ = -1;  ///< the buffer handed out last, requeued at the next call
  std::vector<std::uint8_t> luma_;  ///< YUYV: the luma gathered into a plane
  bool streaming_ = false;
};

}  // namespace earshot::webcam
