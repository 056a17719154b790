// A HidTransport that plays a script instead of a Wii Remote: every write
// must match the next expected report byte for byte; reads return the
// scripted input reports, a disconnect, or a timeout while the script waits
// for the host. Mismatches are collected for the test to show.
#pragma once

#include <algorithm>
#include <cstdio>
#include <deque>
#include <string>
#include <vector>

#include "earshot/tracker/sources/hid_transport.hpp"

namespace earshot::tracker::testing {

using Bytes = std::vector<std::uint8_t>;

struct Step {
  enum class Kind {
    expect_write,  ///< the host must send exactly `bytes`
    reply,         ///< the remote sends `bytes`
    gone,          ///< the remote disconnects (reads fail, it leaves the bus)
    absent_once,   ///< one enumeration finds nothing
    plug,          ///< the remote is back on the bus
  };
  Kind kind;
  Bytes bytes;
};

inline std::string hex(const Bytes& b) {
  std::string s;
  char buf[4];
  for (auto v : b) {
    std::snprintf(buf, sizeof buf, "%02X ", v);
    s += buf;
  }
  return s;
}

class ScriptedHid final : public HidTransport {
 public:
  explicit ScriptedHid(std::deque<Step> script, HidDeviceInfo device = {"/dev/hidraw7", 0x057E, 0x0306, "Nintendo RVL-CNT-01", "hid-generic"})
      : script_(std::move(script)), device_(std::move(device)) {}

  std::vector<HidDeviceInfo> enumerate(std::uint16_t vendor, std::span<const std::uint16_t> products) override {
    ++enumerations;
    if (front(Step::Kind::absent_once)) {
      script_.pop_front();
      return {};
    }
    if (front(Step::Kind::plug)) {
      script_.pop_front();
      present_ = true;
    }
    const bool match = vendor == device_.vendor &&
                       std::find(products.begin(), products.end(), device_.product) != products.end();
    if (!present_ || !match) return {};
    return {device_};
  }
  void open(const HidDeviceInfo& d) override {
    if (open_error) throw *open_error;
    if (d.path != device_.path) errors.push_back("open of unknown path " + d.path);
    open_ = true;
    ++opens;
  }
  void close() override { open_ = false; }
  bool write(std::span<const std::uint8_t> report) override {
    const Bytes got(report.begin(), report.end());
    written.push_back(got);
    if (!open_) {
      errors.push_back("write while closed: " + hex(got));
      return false;
    }
    if (!front(Step::Kind::expect_write)) {
      errors.push_back("unexpected write: " + hex(got));
      return true;
    }
    if (script_.front().bytes != got)
      errors.push_back("write " + std::to_string(written.size()) + ": expected " + hex(script_.front().bytes) + "got " + hex(got));
    script_.pop_front();
    return true;
  }
  int read(std::span<std::uint8_t> buf, std::chrono::milliseconds) override {
    if (!open_) return -1;
    if (front(Step::Kind::gone)) {
      script_.pop_front();
      open_ = present_ = false;
      return -1;
    }
    if (!front(Step::Kind::reply)) return 0;  // the remote waits for the host
    const Bytes b = script_.front().bytes;
    script_.pop_front();
    const std::size_t n = std::min(b.size(), buf.size());
    std::copy_n(b.begin(), n, buf.begin());
    return static_cast<int>(n);
  }

  [[nodiscard]] std::size_t remaining() const { return script_.size(); }

  std::vector<std::string> errors;
  std::vector<Bytes> written;
  int opens = 0, enumerations = 0;
  std::optional<HidOpenError> open_error;

 private:
  bool front(Step::Kind k) const { return !script_.empty() && script_.front().kind == k; }

  std::deque<Step> script_;
  HidDeviceInfo device_;
  bool present_ = true, open_ = false;
};

}  // namespace earshot::tracker::testing
