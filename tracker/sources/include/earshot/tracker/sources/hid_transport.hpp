// The HID calls the Wii Remote needs, behind a small interface: hidapi's
// hidraw backend in the program, a scripted fake in tests (a whole session
// replayed byte for byte without a remote).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace earshot::tracker {

struct HidDeviceInfo {
  std::string path;          ///< e.g. /dev/hidraw3
  std::uint16_t vendor = 0, product = 0;
  std::string product_name;  ///< "Nintendo RVL-CNT-01", ...
  std::string driver;        ///< kernel driver bound to the HID device ("wiimote", "hid-generic"), if known
};

/// Opening a device failed. what() says why and what to do about it.
class HidOpenError : public std::runtime_error {
 public:
  enum class Reason { permission_denied, busy, other };
  HidOpenError(Reason reason, const std::string& message) : std::runtime_error(message), reason_(reason) {}
  [[nodiscard]] Reason reason() const { return reason_; }

 private:
  Reason reason_;
};

class HidTransport {
 public:
  virtual ~HidTransport() = default;
  /// Every HID device with this vendor and one of these products.
  [[nodiscard]] virtual std::vector<HidDeviceInfo> enumerate(std::uint16_t vendor,
                                                             std::span<const std::uint16_t> products) = 0;
  /// Opens a device (closing any open one). Throws HidOpenError.
  virtual void open(const HidDeviceInfo& device) = 0;
  virtual void close() = 0;
  /// Sends one output report (report ID first). False when the device is gone.
  virtual bool write(std::span<const std::uint8_t> report) = 0;
  /// Reads one input report into `buf`: its size, 0 on timeout, -1 when the device is gone.
  virtual int read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) = 0;
};

/// hidapi (hidraw backend). Throws std::runtime_error if hidapi cannot start.
[[nodiscard]] std::unique_ptr<HidTransport> make_hidapi_transport();

}  // namespace earshot::tracker
