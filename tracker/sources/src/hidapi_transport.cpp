// HidTransport over hidapi's hidraw backend (Debian libhidapi-dev).
#include <hidapi/hidapi.h>

#include <cerrno>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "earshot/tracker/sources/hid_transport.hpp"

namespace earshot::tracker {
namespace {

std::string narrow(const wchar_t* w) {
  std::string s;
  for (; w && *w; ++w) s += (*w < 128) ? static_cast<char>(*w) : '?';
  return s;
}

/// The kernel driver bound to a hidraw node: /sys/class/hidraw/NAME/device/driver.
std::string driver_of(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path link = fs::path("/sys/class/hidraw") / fs::path(path).filename() / "device" / "driver";
  const fs::path target = fs::read_symlink(link, ec);
  return ec ? std::string() : target.filename().string();
}

class HidapiTransport final : public HidTransport {
 public:
  HidapiTransport() {
    if (hid_init() != 0) throw std::runtime_error("hidapi: hid_init failed");
  }
  ~HidapiTransport() override {
    close();
    hid_exit();
  }
  HidapiTransport(const HidapiTransport&) = delete;
  HidapiTransport& operator=(const HidapiTransport&) = delete;

  std::vector<HidDeviceInfo> enumerate(std::uint16_t vendor, std::span<const std::uint16_t> products) override {
    std::vector<HidDeviceInfo> out;
    hid_device_info* list = hid_enumerate(vendor, 0);
    for (const hid_device_info* d = list; d; d = d->next) {
      bool wanted = false;
      for (auto p : products) wanted = wanted || d->product_id == p;
      if (!wanted || !d->path) continue;
      out.push_back({d->path, d->vendor_id, d->product_id, narrow(d->product_string), driver_of(d->path)});
    }
    hid_free_enumeration(list);
    return out;
  }

  void open(const HidDeviceInfo& device) override {
    close();
    errno = 0;
    dev_ = hid_open_path(device.path.c_str());
    if (dev_) return;
    // hidapi does not say why; the node's permissions do.
    if (::access(device.path.c_str(), R_OK | W_OK) != 0 && errno == EACCES)
      throw HidOpenError(HidOpenError::Reason::permission_denied,
                         "permission denied opening " + device.path +
                             ": install the udev rule (sudo cp tracker/udev/99-earshot-wiimote.rules "
                             "/etc/udev/rules.d/ && sudo udevadm control --reload && sudo udevadm trigger), "
                             "then reconnect the remote");
    if (errno == EBUSY)
      throw HidOpenError(HidOpenError::Reason::busy, device.path + " is busy: another program holds the remote");
    throw HidOpenError(HidOpenError::Reason::other, "cannot open " + device.path + ": " + narrow(hid_error(nullptr)));
  }

  void close() override {
    if (dev_) hid_close(dev_);
    dev_ = nullptr;
  }

  bool write(std::span<const std::uint8_t> report) override {
    return dev_ && hid_write(dev_, report.data(), report.size()) >= 0;
  }

  int read(std::span<std::uint8_t> buf, std::chrono::milliseconds timeout) override {
    if (!dev_) return -1;
    const int n = hid_read_timeout(dev_, buf.data(), buf.size(), static_cast<int>(timeout.count()));
    return n < 0 ? -1 : n;
  }

 private:
  hid_device* dev_ = nullptr;
};

}  // namespace

std::unique_ptr<HidTransport> make_hidapi_transport() { return std::make_unique<HidapiTransport>(); }

}  // namespace earshot::tracker
