// Fuzzes a whole Wii Remote session: the remote's side is fuzz input, read
// as [length byte][report bytes] records (length 0: the remote disconnects,
// 0xFF: a read timeout). The source must never hand out a dot outside the
// image, a non-finite accelerometer value, or throw after its first connection.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "earshot/tracker/sources/wiimote_source.hpp"

namespace {

using namespace earshot::tracker;

class FuzzedHid final : public HidTransport {
 public:
  explicit FuzzedHid(std::span<const std::uint8_t> data) : data_(data) {}
  std::vector<HidDeviceInfo> enumerate(std::uint16_t, std::span<const std::uint16_t>) override {
    return {{"/dev/hidraw0", 0x057E, 0x0306, "Nintendo RVL-CNT-01", ""}};
  }
  void open(const HidDeviceInfo&) override {}
  void close() override {}
  bool write(std::span<const std::uint8_t>) override { return true; }
  int read(std::span<std::uint8_t> buf, std::chrono::milliseconds) override {
    if (data_.empty()) return 0;
    const std::size_t n = data_[0];
    data_ = data_.subspan(1);
    if (n == 0) return -1;
    if (n == 0xFF) return 0;
    const std::size_t k = std::min({n, data_.size(), buf.size()});
    std::copy_n(data_.begin(), k, buf.begin());
    data_ = data_.subspan(k);
    return static_cast<int>(k);
  }
  [[nodiscard]] bool exhausted() const { return data_.empty(); }

 private:
  std::span<const std::uint8_t> data_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto hid = std::make_unique<FuzzedHid>(std::span(data, size));
  const FuzzedHid& feed = *hid;
  double now = 0.0;
  WiimoteOptions opt;
  opt.retry_s = 0.0;
  opt.clock = [&now] { return now += 0.01; };
  WiimoteSource src(std::move(hid), opt);
  bool connected_once = false;
  for (int i = 0; i < 400 && !feed.exhausted(); ++i) {
    SourceEvent e;
    try {
      e = src.next(std::chrono::milliseconds(0));
    } catch (const WiimoteError&) {
      if (connected_once) std::abort();  // after a connection it reconnects, never throws
      return 0;
    }
    connected_once = connected_once || src.connected();
    if (const auto* f = std::get_if<CameraFrame>(&e)) {
      for (const auto& d : f->dots.slots)
        if (d && (!d->allFinite() || d->x() < 0 || d->x() > 1023 || d->y() < 0 || d->y() > 767)) std::abort();
      if (f->accel_g && !f->accel_g->allFinite()) std::abort();
    }
  }
  return 0;
}
