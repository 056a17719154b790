#include "earshot/tracker/sources/wiimote_source.hpp"

#include <thread>
#include <utility>


namespace earshot::tracker {
namespace {

namespace w = wiimote;
constexpr std::array<std::uint16_t, 2> kProducts{w::kProductWiimote, w::kProductWiimotePlus};

double steady_seconds() {
  static const auto start = std::chrono::steady_clock::now();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Typical factory values, used only when the remote's own cannot be read.
w::AccelCalibration default_calibration() {
  w::AccelCalibration c;
  c.zero = {512.0, 512.0, 512.0};
  c.one_g = {616.0, 616.0, 616.0};
  return c;
}

}  // namespace

Vec3 remote_accel_to_camera(const Vec3& a) {
  // Camera +x (right) = remote -x, +y (down) = remote -z, +z (where the
  // camera looks, the remote's front) = remote -y.
  return {-a.x(), -a.z(), -a.y()};
}

std::string no_wiimote_message() {
  return "no Wii Remote found (057e:0306 or 057e:0330). Pair it once with BlueZ: run `bluetoothctl`, "
         "then `scan on`, press the red SYNC button under the battery cover, and `pair`, `trust`, "
         "`connect` the address shown as 'Nintendo RVL-CNT-01'; afterwards pressing 1+2 reconnects it";
}

WiimoteSource::WiimoteSource(std::unique_ptr<HidTransport> transport, WiimoteOptions opt)
    : hid_(std::move(transport)), opt_(std::move(opt)), cal_(default_calibration()) {
  if (!opt_.clock) opt_.clock = steady_seconds;
}

WiimoteSource::~WiimoteSource() {
  if (connected_) hid_->close();
}

SourceEvent WiimoteSource::next(std::chrono::milliseconds timeout) {
  if (!connected_) {
    const double wait = next_attempt_ - opt_.clock();
    if (wait > 0.0) {
      std::this_thread::sleep_for(std::min<std::chrono::milliseconds>(
          timeout, std::chrono::milliseconds(static_cast<long>(wait * 1000.0) + 1)));
      return make_note(SourceNote::Kind::timeout);
    }
    return connect();
  }
  std::array<std::uint8_t, 64> buf{};
  const int n = hid_->read(buf, timeout);
  if (n < 0) return lose("Wii Remote disconnected; reconnecting (press 1+2 on the remote)");
  if (n == 0) return make_note(SourceNote::Kind::timeout);
  if (auto e = on_report(std::span(buf.data(), static_cast<std::size_t>(n)))) return *e;
  return make_note(SourceNote::Kind::timeout);
}

SourceEvent WiimoteSource::connect() {
  next_attempt_ = opt_.clock() + opt_.retry_s;
  std::vector<HidDeviceInfo> found;
  for (auto& d : hid_->enumerate(w::kVendorNintendo, kProducts))
    if (d.product_name.find("-UC") == std::string::npos) found.push_back(d);  // the Wii U Pro (RVL-CNT-01-UC) shares 0330
  // Before the first connection a failure is the person's to fix: thrown, or
  // (waiting for the remote) said in a searching note on every attempt.
  const auto not_yet = [&](const std::string& why) -> SourceEvent {
    if (!opt_.wait_for_remote) throw WiimoteError(why);
    return make_note(SourceNote::Kind::searching, why);
  };
  if (found.empty()) {
    if (!ever_connected_) return not_yet(no_wiimote_message());
    return make_note(SourceNote::Kind::timeout);
  }
  const HidDeviceInfo& dev = found.front();
  try {
    hid_->open(dev);
  } catch (const HidOpenError& e) {
    if (!ever_connected_) return not_yet(e.what());
    return make_note(SourceNote::Kind::timeout);
  }
  std::string why;
  if (!initialise(why)) {
    hid_->close();
    if (!ever_connected_) return not_yet("Wii Remote at " + dev.path + " did not initialise: " + why);
    return make_note(SourceNote::Kind::timeout);
  }
  connected_ = ever_connected_ = true;
  std::string msg = "Wii Remote connected (" + dev.path + ")";
  if (dev.driver == "wiimote")
    msg += "; warning: the kernel's hid-wiimote driver is bound to it and may reconfigure it "
           "(unbind it, or blacklist hid_wiimote in /etc/modprobe.d)";
  return make_note(SourceNote::Kind::connected, msg);
}

bool WiimoteSource::await(const std::function<bool(const w::InputReport&)>& want) {
  const double deadline = opt_.clock() + std::chrono::duration<double>(opt_.reply_timeout).count();
  std::array<std::uint8_t, 64> buf{};
  while (opt_.clock() < deadline) {
    const int n = hid_->read(buf, std::chrono::milliseconds(50));
    if (n < 0) return false;
    if (n == 0) continue;
    const auto r = w::decode(std::span(buf.data(), static_cast<std::size_t>(n)));
    if (!r) {
      ++dropped_;
      continue;
    }
    if (want(*r)) return true;
  }
  return false;
}

bool WiimoteSource::initialise(std::string& why) {
  const auto fail = [&](const char* message) {
    why = message;
    return false;
  };
  if (!send(w::set_leds(0x01), why)) return false;
  // Accelerometer calibration: 10 bytes at EEPROM 0x16 (the last is the checksum).
  if (!send(w::read_memory(w::kAccelCalibrationAddress, w::kAccelCalibrationSize), why)) return false;
  std::optional<w::AccelCalibration> cal;
  const bool replied = await([&](const w::InputReport& r) {
    const auto* rr = std::get_if<w::ReadReply>(&r);
    if (!rr || rr->address_low != w::kAccelCalibrationAddress) return false;
    if (rr->error == 0) cal = w::parse_accel_calibration(std::span(rr->data.data(), rr->size));
    return true;
  });
  if (!replied) return fail("no reply to the calibration read");
  cal_ = cal.value_or(default_calibration());
  for (const auto& report : w::ir_init_sequence(opt_.mode, opt_.sensitivity))
    if (!send(report, why)) return false;
  return true;
}

bool WiimoteSource::send(const w::OutputReport& report, std::string& why) {
  constexpr int kAttempts = 2;  // a lost report or acknowledgement is sent again once
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    if (!hid_->write(report.view())) {
      why = "write of output report " + w::describe(report) + " failed";
      return false;
    }
    if (!w::expects_acknowledgement(report)) return true;
    std::uint8_t error = 0;
    const bool acked = await([&](const w::InputReport& r) {
      const auto* a = std::get_if<w::Acknowledge>(&r);
      if (!a || a->report != report.id()) return false;
      error = a->error;
      return true;
    });
    if (!acked) continue;
    if (error == 0) return true;
    why = "output report " + w::describe(report) + " refused with error code " + std::to_string(error);
    return false;
  }
  why = "no acknowledgement of output report " + w::describe(report) + " after " + std::to_string(kAttempts) +
        " attempts";
  return false;
}

SourceEvent WiimoteSource::lose(const std::string& why) {
  hid_->close();
  connected_ = false;
  next_attempt_ = opt_.clock() + opt_.retry_s;
  first_half_.reset();
  return make_note(SourceNote::Kind::disconnected, why);
}

std::optional<SourceEvent> WiimoteSource::on_report(std::span<const std::uint8_t> bytes) {
  // A 0x3E pairs with the report right after it only: whatever comes next
  // takes the waiting half away.
  const auto first_half = std::exchange(first_half_, std::nullopt);
  const auto r = w::decode(bytes);
  if (!r) {
    ++dropped_;  // never trusted
    return std::nullopt;
  }
  if (std::holds_alternative<w::StatusReport>(*r)) {
    // The remote sends a status report on its own (e.g. an extension
    // plugged in) and then stops streaming until the mode is set again.
    if (!hid_->write(w::set_reporting_mode(w::reporting_mode_for(opt_.mode), true).view()))
      return lose("Wii Remote disconnected; reconnecting (press 1+2 on the remote)");
    return std::nullopt;
  }
  const auto* d = std::get_if<w::DataReport>(&*r);
  if (!d || !d->buttons) return std::nullopt;  // 0x3D: extension bytes only
  std::array<std::optional<w::IrDot>, 4> ir = d->ir;
  if (d->ir_slot_count == 2) {  // full format: a 0x3E and the 0x3F right after it make one frame
    if (d->ir_first_slot == 0) {
      first_half_ = std::array{d->ir[0], d->ir[1]};
      return std::nullopt;
    }
    if (!first_half) return std::nullopt;  // its 0x3E was lost: half a frame is no frame
    ir[0] = (*first_half)[0];
    ir[1] = (*first_half)[1];
  }
  CameraFrame f;
  f.dots.t = opt_.clock();
  for (std::size_t s = 0; s < 4; ++s)
    if (ir[s]) {
      f.dots.slots[s] = Vec2(ir[s]->x, ir[s]->y);
      if (opt_.mode != w::IrMode::basic) f.dot_size[s] = ir[s]->size;  // basic mode has no sizes
    }
  if (d->accel) {
    const auto g = cal_.apply(*d->accel);
    f.accel_g = remote_accel_to_camera(Vec3(g[0], g[1], g[2]));
  }
  f.buttons = d->buttons->bits;
  return f;
}

}  // namespace earshot::tracker
