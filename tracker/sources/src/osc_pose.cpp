#include "earshot/tracker/sources/osc_pose.hpp"

#include <lo/lo.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>


namespace earshot::tracker {
namespace {

struct MessageFree {
  void operator()(lo_message m) const { lo_message_free(m); }
};
using Message = std::unique_ptr<std::remove_pointer_t<lo_message>, MessageFree>;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kMaxAngleDeg = 720.0;
constexpr std::uint8_t kBundleTag[8] = {'#', 'b', 'u', 'n', 'd', 'l', 'e', 0};
constexpr std::size_t kBundleHeader = 16;  // the tag and the timetag

/// Records why a message is dropped.
std::nullopt_t drop(std::string* why, const std::string& msg) {
  if (why) *why = msg;
  return std::nullopt;
}

bool is_bundle(std::span<const std::uint8_t> b) {
  return b.size() >= sizeof kBundleTag && std::memcmp(b.data(), kBundleTag, sizeof kBundleTag) == 0;
}

/// The arguments as doubles, when every one is a number.
/// liblo's arguments sit on 4-byte boundaries inside the message, so a
/// double may be misaligned for lo_arg: copy the bytes out, never dereference.
template <class T>
T arg_as(const lo_arg* a) {
  T v;
  std::memcpy(&v, static_cast<const void*>(a), sizeof v);
  return v;
}

std::optional<std::vector<double>> numbers(std::string_view types, lo_arg** argv) {
  std::vector<double> v;
  for (std::size_t i = 0; i < types.size(); ++i) {
    switch (types[i]) {
      case LO_FLOAT: v.push_back(static_cast<double>(arg_as<float>(argv[i]))); break;
      case LO_DOUBLE: v.push_back(arg_as<double>(argv[i])); break;
      case LO_INT32: v.push_back(static_cast<double>(arg_as<std::int32_t>(argv[i]))); break;
      default: return std::nullopt;
    }
  }
  return v;
}

std::string where(std::string_view path) { return "OSC " + std::string(path); }

/// nullopt when `v` holds `want` finite numbers; the reason otherwise.
std::optional<std::string> check_count(std::string_view path, std::string_view types, const std::vector<double>* v,
                                       std::size_t want) {
  if (!v || v->size() != want)
    return where(path) + ": expected " + std::to_string(want) + " number" + (want == 1 ? "" : "s") + ", got type tags '" +
           std::string(types) + "'";
  for (double x : *v)
    if (!std::isfinite(x)) return where(path) + ": a value is not finite";
  return std::nullopt;
}

std::optional<std::string> check_angles(std::string_view path, std::span<const double> deg) {
  for (double a : deg)
    if (std::abs(a) > kMaxAngleDeg) return where(path) + ": angle beyond 720 degrees";
  return std::nullopt;
}

/// A unit quaternion from four numbers, or the reason it is not one.
std::optional<Quat> unit_quat(double w, double x, double y, double z, std::string_view path, std::string* why) {
  const Quat q(w, x, y, z);
  if (std::abs(q.norm() - 1.0) > 0.01) {
    drop(why, where(path) + ": quaternion (w x y z) is not unit length");
    return std::nullopt;
  }
  return q.normalized();
}

PoseMessage pose(const Vec3& position_m, const Quat& orientation) {
  HeadPose d;
  d.position = to_common(position_m);
  d.orientation = to_common(orientation);
  d.state = PoseState::tracking;
  return PoseMessage{d, false};
}

// The Spatial Audio Framework's axes (x ahead, y left, z up) in Earshot's
// (+x right, +y up, -z ahead): a proper rotation, so quaternion vector parts
// map like positions.
Vec3 saf_to_earshot(double x, double y, double z) { return {-y, z, -x}; }

/// Earshot's head orientation for SPARTA's yaw, pitch, roll (degrees): SAF
/// turns by Rz(yaw) Ry(pitch) Rx(roll) about its own axes; Ry about +y (left)
/// is Earshot's pitch about -x, so pitch changes sign.
Quat sparta_head(double yaw, double pitch, double roll) {
  return to_eigen(quat_from_ypr(yaw * kDeg, -pitch * kDeg, roll * kDeg));
}

/// Earshot's head orientation for SceneRotator's scene rotation Rx(roll)
/// Ry(pitch) Rz(yaw) (degrees, extrinsic yaw then pitch then roll): the head
/// is its inverse, Rz(-yaw) Ry(-pitch) Rx(-roll) about SAF's axes.
Quat scene_rotator_head(double yaw, double pitch, double roll) {
  return to_eigen(quat_from_ypr(-yaw * kDeg, pitch * kDeg, -roll * kDeg));
}

}  // namespace

std::optional<PoseMessage> OscPoseDecoder::decode(std::span<const std::uint8_t> bytes, std::string* why) {
  return is_bundle(bytes) ? bundle(bytes, why) : message(bytes, why);
}

PacketDecoder OscPoseDecoder::packet_decoder() {
  // The lambda owns the decoder; std::function copies it only when the
  // PacketDecoder itself is copied, before any packet arrives.
  return [d = OscPoseDecoder()](std::span<const std::uint8_t> b, std::string* why) mutable { return d.decode(b, why); };
}

std::optional<PoseMessage> OscPoseDecoder::message(std::span<const std::uint8_t> bytes, std::string* why) {
  // liblo wants writable memory and checks the whole message (path, type
  // tags, argument sizes) before it gives one back.
  std::vector<std::uint8_t> copy(bytes.begin(), bytes.end());
  int result = 0;
  const Message m(copy.empty() ? nullptr : lo_message_deserialise(copy.data(), copy.size(), &result));
  if (!m) return drop(why, "malformed OSC message (liblo error " + std::to_string(result) + ")");
  const auto* path = reinterpret_cast<const char*>(copy.data());
  const std::string_view p(path, strnlen(path, copy.size()));
  const char* t = lo_message_get_types(m.get());
  const std::string_view types = t ? std::string_view(t) : std::string_view();
  const auto v = numbers(types, lo_message_get_argv(m.get()));
  return handle(p, types, v ? &*v : nullptr, why);
}

std::optional<PoseMessage> OscPoseDecoder::bundle(std::span<const std::uint8_t> bytes, std::string* why) {
  // First the structure, whole, so a malformed bundle changes no state.
  struct Element {
    std::span<const std::uint8_t> bytes;
    std::string name;  // "2" or, nested, "2.1"
  };
  std::vector<Element> messages;
  int count = 0;
  std::string error;
  auto walk = [&](auto&& self, std::span<const std::uint8_t> b, int depth, const std::string& prefix) -> bool {
    const std::string here = prefix.empty() ? "OSC bundle" : "OSC bundle element " + prefix.substr(0, prefix.size() - 1);
    if (depth > kOscMaxBundleDepth) {
      error = here + ": bundles nested deeper than " + std::to_string(kOscMaxBundleDepth) + " levels";
      return false;
    }
    if (b.size() < kBundleHeader) {
      error = here + ": " + std::to_string(b.size()) + " bytes, shorter than the 16-byte bundle header";
      return false;
    }
    std::size_t pos = kBundleHeader;
    for (int index = 1; pos < b.size(); ++index) {
      const std::string name = prefix + std::to_string(index);
      const std::size_t left = b.size() - pos;
      if (left < 4) {
        error = "OSC bundle element " + name + ": size field cut off (" + std::to_string(left) + " bytes left)";
        return false;
      }
      const std::uint32_t n = (std::uint32_t{b[pos]} << 24) | (std::uint32_t{b[pos + 1]} << 16) |
                              (std::uint32_t{b[pos + 2]} << 8) | std::uint32_t{b[pos + 3]};
      if (++count > kOscMaxBundleElements) {
        error = "OSC bundle element " + name + ": more than " + std::to_string(kOscMaxBundleElements) +
                " elements in one packet";
        return false;
      }
      if (n == 0 || n % 4 != 0 || n > 0x7fffffffu) {
        error = "OSC bundle element " + name + ": size " + std::to_string(n) + " is not a positive multiple of 4";
        return false;
      }
      if (n > left - 4) {
        error = "OSC bundle element " + name + ": size " + std::to_string(n) + " runs beyond the packet (" +
                std::to_string(left - 4) + " bytes left)";
        return false;
      }
      const auto content = b.subspan(pos + 4, n);
      if (is_bundle(content)) {
        if (!self(self, content, depth + 1, name + ".")) return false;
      } else if (content[0] == '/') {
        messages.push_back({content, name});
      } else {
        error = "OSC bundle element " + name + ": neither a message ('/...') nor a bundle ('#bundle')";
        return false;
      }
      pos += 4 + n;
    }
    return true;
  };
  if (!walk(walk, bytes, 1, "")) return drop(why, error);
  if (messages.empty()) return drop(why, "OSC bundle holds no messages");

  // Then each message in order; timetags are ignored: everything applies now.
  PoseMessage out;
  bool any = false;
  std::string first_reason;
  for (const Element& e : messages) {
    std::string w;
    const auto m = message(e.bytes, &w);
    if (!m) {
      if (first_reason.empty()) first_reason = "OSC bundle element " + e.name + ": " + w;
      continue;
    }
    any = true;
    if (m->pose) out.pose = m->pose;  // the last pose wins
    out.recenter = out.recenter || m->recenter;
  }
  if (!any) return drop(why, first_reason);
  return out;
}

std::optional<PoseMessage> OscPoseDecoder::handle(std::string_view path, std::string_view types,
                                                  const std::vector<double>* v, std::string* why) {
  if (path == "/earshot/recenter") {
    if (!types.empty()) return drop(why, where(path) + ": takes no arguments");
    return PoseMessage{std::nullopt, true};
  }
  std::size_t want = 0, pos = 0;
  bool quat = false;
  if (path == "/earshot/pose/ypr") want = 6, pos = 3;
  else if (path == "/earshot/pose/quat") want = 7, pos = 3, quat = true;
  else if (path == "/earshot/ypr") want = 3;
  else if (path == "/earshot/quat") want = 4, quat = true;
  else if (path == "/ypr" || path == "/yaw" || path == "/pitch" || path == "/roll" || path == "/quaternion" ||
           path == "/xyz") {
    const std::size_t n = path == "/quaternion" ? 4 : (path == "/ypr" || path == "/xyz") ? 3 : 1;
    if (const auto e = check_count(path, types, v, n)) return drop(why, *e);
    return sparta(path, *v, why);
  } else if (path.starts_with("/SceneRotator/")) {
    const std::string_view leaf = path.substr(std::strlen("/SceneRotator/"));
    const std::size_t n = leaf == "quaternions" ? 4 : leaf == "ypr" ? 3 : 1;
    if (n == 1 && leaf != "yaw" && leaf != "pitch" && leaf != "roll" && leaf != "qw" && leaf != "qx" && leaf != "qy" &&
        leaf != "qz")
      return drop(why, "OSC address " + std::string(path) + " is not one of ours (SceneRotator: ypr, yaw, pitch, roll, "
                                                             "quaternions, qw, qx, qy, qz)");
    if (const auto e = check_count(path, types, v, n)) return drop(why, *e);
    return scene_rotator(leaf, *v, why);
  } else {
    return drop(why, "OSC address " + std::string(path) + " is not one of ours");
  }

  if (const auto e = check_count(path, types, v, want)) return drop(why, *e);
  const std::vector<double>& a = *v;
  Vec3 position = Vec3::Zero();
  if (pos) position = Vec3(a[0], a[1], a[2]);
  if (position.norm() > kMaxPositionM)
    return drop(why, where(path) + ": position beyond " + std::to_string(kMaxPositionM) + " m");
  if (quat) {
    const auto q = unit_quat(a[pos], a[pos + 1], a[pos + 2], a[pos + 3], path, why);
    if (!q) return std::nullopt;
    return pose(position, *q);
  }
  if (const auto e = check_angles(path, std::span(a).subspan(pos, 3))) return drop(why, *e);
  return pose(position, to_eigen(quat_from_ypr(a[pos] * kDeg, a[pos + 1] * kDeg, a[pos + 2] * kDeg)));
}

std::optional<PoseMessage> OscPoseDecoder::sparta(std::string_view path, const std::vector<double>& v, std::string* why) {
  if (path == "/xyz") {
    const Vec3 p = saf_to_earshot(v[0], v[1], v[2]);
    if (p.norm() > kMaxPositionM)
      return drop(why, where(path) + ": position beyond " + std::to_string(kMaxPositionM) + " m");
    sparta_position_m_ = p;
    return pose(p, sparta_head(sparta_.yaw, sparta_.pitch, sparta_.roll));
  }
  if (path == "/quaternion") {
    const auto q = unit_quat(v[0], -v[2], v[3], -v[1], path, why);  // SAF (w x y z) in Earshot's axes
    if (!q) return std::nullopt;
    // Keep the angles in step, so a later /yaw keeps this pitch and roll.
    const YawPitchRoll a = ypr_from_quat(to_common(*q));
    sparta_ = {a.yaw / kDeg, -a.pitch / kDeg, a.roll / kDeg};
    return pose(sparta_position_m_, *q);
  }
  if (const auto e = check_angles(path, v)) return drop(why, *e);
  Euler next = sparta_;
  if (path == "/ypr") next = {v[0], v[1], v[2]};
  else if (path == "/yaw") next.yaw = v[0];
  else if (path == "/pitch") next.pitch = v[0];
  else next.roll = v[0];
  sparta_ = next;
  return pose(sparta_position_m_, sparta_head(next.yaw, next.pitch, next.roll));
}

std::optional<PoseMessage> OscPoseDecoder::scene_rotator(std::string_view leaf, const std::vector<double>& v,
                                                         std::string* why) {
  const std::string path = "/SceneRotator/" + std::string(leaf);
  // The scene's rotation q = (w x y z) about SAF's axes; the head is its
  // inverse (w -x -y -z), which in Earshot's axes is (w, y, -z, x).
  auto head_from_q = [](const std::array<double, 4>& q) { return Quat(q[0], q[2], -q[3], q[1]); };
  auto q_from_head = [](const Quat& h) { return std::array<double, 4>{h.w(), h.z(), h.x(), -h.y()}; };
  auto angles_from_head = [](const Quat& h) {
    const YawPitchRoll a = ypr_from_quat(to_common(h));
    return Euler{-a.yaw / kDeg, a.pitch / kDeg, -a.roll / kDeg};
  };

  if (leaf == "quaternions" || leaf == "qw" || leaf == "qx" || leaf == "qy" || leaf == "qz") {
    std::array<double, 4> q = scene_rotator_q_;
    if (leaf == "quaternions") q = {v[0], v[1], v[2], v[3]};
    else if (std::abs(v[0]) > 1.0 + 1e-6) return drop(why, where(path) + ": a quaternion component beyond -1..1");
    else q[leaf == "qw" ? 0 : leaf == "qx" ? 1 : leaf == "qy" ? 2 : 3] = v[0];
    const Quat h = head_from_q(q);
    if (std::abs(h.norm() - 1.0) > 0.01) {
      if (leaf == "quaternions") return drop(why, where(path) + ": quaternion (w x y z) is not unit length");
      scene_rotator_q_ = q;  // one component of several: wait for the rest
      return drop(why, where(path) + ": quaternion (w x y z) is not unit length yet; waiting for the other components");
    }
    scene_rotator_q_ = q;
    scene_rotator_ = angles_from_head(h.normalized());
    return pose(Vec3::Zero(), h.normalized());
  }
  if (const auto e = check_angles(path, v)) return drop(why, *e);
  Euler next = scene_rotator_;
  if (leaf == "ypr") next = {v[0], v[1], v[2]};
  else if (leaf == "yaw") next.yaw = v[0];
  else if (leaf == "pitch") next.pitch = v[0];
  else next.roll = v[0];
  scene_rotator_ = next;
  const Quat h = scene_rotator_head(next.yaw, next.pitch, next.roll);
  scene_rotator_q_ = q_from_head(h);
  return pose(Vec3::Zero(), h);
}

std::vector<std::uint8_t> encode_osc(const std::string& path, std::span<const double> args) {
  const Message m(lo_message_new());
  for (double a : args) lo_message_add_double(m.get(), a);
  std::size_t size = lo_message_length(m.get(), path.c_str());
  std::vector<std::uint8_t> out(size);
  lo_message_serialise(m.get(), path.c_str(), out.data(), &size);
  out.resize(size);
  return out;
}

std::vector<std::uint8_t> encode_osc_float(const std::string& path, std::span<const float> args) {
  const Message m(lo_message_new());
  for (float a : args) lo_message_add_float(m.get(), a);
  std::size_t size = lo_message_length(m.get(), path.c_str());
  std::vector<std::uint8_t> out(size);
  lo_message_serialise(m.get(), path.c_str(), out.data(), &size);
  out.resize(size);
  return out;
}

std::vector<std::uint8_t> encode_osc_bundle(std::span<const std::vector<std::uint8_t>> elements) {
  std::size_t size = kBundleHeader;
  for (const auto& e : elements) size += 4 + e.size();
  std::vector<std::uint8_t> out(size, 0);
  std::memcpy(out.data(), kBundleTag, sizeof kBundleTag);
  out[kBundleHeader - 1] = 1;  // timetag 1: "immediately"
  std::size_t pos = kBundleHeader;
  for (const auto& e : elements) {
    const auto n = static_cast<std::uint32_t>(e.size());
    for (int i = 0; i < 4; ++i) out[pos + i] = static_cast<std::uint8_t>(n >> (24 - 8 * i));
    if (!e.empty()) std::memcpy(out.data() + pos + 4, e.data(), e.size());
    pos += 4 + e.size();
  }
  return out;
}

}  // namespace earshot::tracker
