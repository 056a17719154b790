#include "earshot/tracker/sources/osc_pose.hpp"

#include <lo/lo.h>

#include <algorithm>
#include <array>
#include <bit>
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

/// ASCII lower case: addresses match whatever their case, as IEM's plug-ins
/// match theirs (equalsIgnoreCase).
std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

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

/// An angle as Earshot and SPARTA take it: any finite number of degrees,
/// periodic (SAF turns by its sine and cosine), brought into [-180, 180].
double wrapped(double deg) { return std::remainder(deg, 360.0); }

/// An angle as the IEM SceneRotator takes it: its parameters are -180..180
/// and a value beyond is clamped to the end of the range (juce's
/// NormalisableRange::convertTo0to1 in OSCParameterInterface::setValue).
double clamped_iem(double deg) { return std::clamp(deg, -180.0, 180.0); }

/// A quaternion from four numbers, normalised; only one too short to have a
/// direction (or not finite) is refused, with the reason.
std::optional<Quat> normalised_quat(double w, double x, double y, double z, std::string_view path, std::string* why) {
  const Quat q(w, x, y, z);
  const double n = q.norm();
  if (!std::isfinite(n) || n < kOscMinQuaternionNorm) {
    drop(why, where(path) + ": quaternion (w x y z) of length " + std::to_string(n) + " has no direction");
    return std::nullopt;
  }
  return Quat(q.coeffs() / n);
}

/// Quaternion components sent one message at a time make a pose once the
/// four are this close to unit length (a mix of two orientations far apart,
/// half sent, is not one: it waits for the rest).
constexpr double kComponentsUnitTolerance = 0.1;

PoseMessage pose(const Vec3& position_m, const Quat& orientation) {
  HeadPose d;
  d.position = to_common(position_m);
  d.orientation = to_common(orientation);
  d.state = PoseState::tracking;
  return PoseMessage{d, false};
}

/// Angles (degrees) of an Euler triple for the decoder's state.
std::array<double, 3> as_array(double yaw, double pitch, double roll) { return {yaw, pitch, roll}; }

}  // namespace

Vec3 saf_to_earshot(double x, double y, double z) { return {-y, z, -x}; }
Vec3 earshot_to_saf(const Vec3& v) { return {-v.z(), -v.x(), v.y()}; }

// SAF turns by Rz(yaw) Ry(pitch) Rx(roll) about its own axes; Ry about +y
// (left) is Earshot's pitch about -x, so pitch changes sign.
Quat sparta_head(double yaw, double pitch, double roll) {
  return to_eigen(quat_from_ypr(yaw * kDeg, -pitch * kDeg, roll * kDeg));
}
std::array<double, 3> sparta_ypr(const Quat& head) {
  const YawPitchRoll a = ypr_from_quat(to_common(head.normalized()));
  return {a.yaw / kDeg, -a.pitch / kDeg, a.roll / kDeg};
}
std::array<double, 4> sparta_quaternion(const Quat& head) {
  const Quat h = head.normalized();
  const Vec3 v = earshot_to_saf(h.vec());
  return {h.w(), v.x(), v.y(), v.z()};
}

// The head is the scene's rotation inverted: Rz(-yaw) Ry(-pitch) Rx(-roll)
// about SAF's axes.
Quat scene_rotator_head(double yaw, double pitch, double roll) {
  return to_eigen(quat_from_ypr(-yaw * kDeg, pitch * kDeg, -roll * kDeg));
}
std::array<double, 3> scene_rotator_ypr(const Quat& head) {
  const YawPitchRoll a = ypr_from_quat(to_common(head.normalized()));
  return {-a.yaw / kDeg, a.pitch / kDeg, -a.roll / kDeg};
}
std::array<double, 4> scene_rotator_quaternions(const Quat& head) {
  // The scene's rotation is the head's inverse: (w, -v) about SAF's axes.
  const Quat h = head.normalized();
  const Vec3 v = earshot_to_saf(h.vec());
  return {h.w(), -v.x(), -v.y(), -v.z()};
}

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

namespace {

enum class Convention { earshot, sparta, scene_rotator };

/// Every address we take, lower case, with its argument count.
struct Address {
  std::string_view path;
  Convention convention;
  std::size_t count;
};
constexpr std::array<Address, 23> kAddresses{{
    {"/earshot/pose/ypr", Convention::earshot, 6},
    {"/earshot/pose/quat", Convention::earshot, 7},
    {"/earshot/ypr", Convention::earshot, 3},
    {"/earshot/quat", Convention::earshot, 4},
    {"/earshot/recenter", Convention::earshot, 0},
    // SPARTA's rotator and binaural plug-ins
    {"/ypr", Convention::sparta, 3},
    {"/yaw", Convention::sparta, 1},
    {"/pitch", Convention::sparta, 1},
    {"/roll", Convention::sparta, 1},
    {"/quaternion", Convention::sparta, 4},
    {"/qw", Convention::sparta, 1},
    {"/qx", Convention::sparta, 1},
    {"/qy", Convention::sparta, 1},
    {"/qz", Convention::sparta, 1},
    {"/xyz", Convention::sparta, 3},
    // SPARTA's 6DoFconv
    {"/quat", Convention::sparta, 4},
    {"/xyzquat", Convention::sparta, 7},
    {"/xyzypr", Convention::sparta, 6},
    // IEM SceneRotator (the rest of /scenerotator/... below)
    {"/scenerotator/ypr", Convention::scene_rotator, 3},
    {"/scenerotator/quaternions", Convention::scene_rotator, 4},
    {"/scenerotator/yaw", Convention::scene_rotator, 1},
    {"/scenerotator/pitch", Convention::scene_rotator, 1},
    {"/scenerotator/roll", Convention::scene_rotator, 1},
}};
constexpr std::array<std::string_view, 4> kSceneRotatorComponents{"/scenerotator/qw", "/scenerotator/qx",
                                                                    "/scenerotator/qy", "/scenerotator/qz"};

/// The component index (0 w .. 3 x y z) a single-component address sets, or -1.
int component_of(std::string_view p) {
  for (std::size_t i = 0; i < 4; ++i) {
    if (p == kSceneRotatorComponents[i]) return static_cast<int>(i);
    if (p == kSceneRotatorComponents[i].substr(std::string_view("/scenerotator").size())) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace

std::optional<PoseMessage> OscPoseDecoder::handle(std::string_view path, std::string_view types,
                                                  const std::vector<double>* v, std::string* why) {
  const std::string p = lower(path);
  std::optional<Address> a;
  for (const Address& x : kAddresses)
    if (p == x.path) a = x;
  if (!a && (component_of(p) >= 0)) a = Address{"", p.starts_with("/scenerotator/") ? Convention::scene_rotator : Convention::sparta, 1};
  if (!a) {
    if (p.starts_with("/scenerotator/"))
      return drop(why, "OSC address " + std::string(path) + " is not one of ours (SceneRotator: ypr, yaw, pitch, roll, "
                                                             "quaternions, qw, qx, qy, qz)");
    return drop(why, "OSC address " + std::string(path) + " is not one of ours");
  }
  if (a->count == 0) {
    if (!types.empty()) return drop(why, where(path) + ": takes no arguments");
    return PoseMessage{std::nullopt, true};
  }
  if (const auto e = check_count(path, types, v, a->count)) return drop(why, *e);
  switch (a->convention) {
    case Convention::sparta: return sparta(p, path, *v, why);
    case Convention::scene_rotator: return scene_rotator(p, path, *v, why);
    case Convention::earshot: break;
  }

  // Earshot's own: stateless, metres and degrees in the audio world frame.
  const std::vector<double>& n = *v;
  const bool with_position = p.starts_with("/earshot/pose/");
  const std::size_t at = with_position ? 3 : 0;
  const Vec3 position = with_position ? Vec3(n[0], n[1], n[2]) : Vec3::Zero();
  if (position.norm() > kMaxPositionM)
    return drop(why, where(path) + ": position beyond " + std::to_string(kMaxPositionM) + " m");
  if (p.ends_with("quat")) {
    const auto q = normalised_quat(n[at], n[at + 1], n[at + 2], n[at + 3], path, why);
    if (!q) return std::nullopt;
    return pose(position, *q);
  }
  return pose(position, to_eigen(quat_from_ypr(wrapped(n[at]) * kDeg, wrapped(n[at + 1]) * kDeg, wrapped(n[at + 2]) * kDeg)));
}

std::optional<PoseMessage> OscPoseDecoder::sparta(const std::string& p, std::string_view path, const std::vector<double>& v,
                                                  std::string* why) {
  // Position first (/xyz, /xyzquat, /xyzypr), then the orientation the message carries.
  std::size_t at = 0;
  Vec3 position = sparta_position_m_;
  if (p.starts_with("/xyz")) {
    position = saf_to_earshot(v[0], v[1], v[2]);
    if (position.norm() > kMaxPositionM)
      return drop(why, where(path) + ": position beyond " + std::to_string(kMaxPositionM) + " m");
    at = 3;
  }
  std::optional<Quat> head;
  std::array<double, 4> q = sparta_q_;
  if (p == "/quaternion" || p == "/quat" || p == "/xyzquat") {
    q = {v[at], v[at + 1], v[at + 2], v[at + 3]};
    head = normalised_quat(q[0], -q[2], q[3], -q[1], path, why);  // SAF (w x y z) in Earshot's axes
    if (!head) return std::nullopt;
  } else if (const int c = component_of(p); c >= 0) {
    q[static_cast<std::size_t>(c)] = v[0];
    const Quat h(q[0], -q[2], q[3], -q[1]);
    if (std::abs(h.norm() - 1.0) > kComponentsUnitTolerance) {
      sparta_q_ = q;  // one component of several: wait for the rest
      return drop(why, where(path) + ": quaternion (w x y z) is not unit length yet; waiting for the other components");
    }
    head = Quat(h.coeffs() / h.norm());
  } else if (p == "/xyz") {
    head = sparta_head(sparta_[0], sparta_[1], sparta_[2]);
  } else {
    std::array<double, 3> next = sparta_;
    if (p == "/ypr" || p == "/xyzypr") next = as_array(wrapped(v[at]), wrapped(v[at + 1]), wrapped(v[at + 2]));
    else next[p == "/yaw" ? 0 : p == "/pitch" ? 1 : 2] = wrapped(v[0]);
    sparta_ = next;
    head = sparta_head(next[0], next[1], next[2]);
    q = sparta_quaternion(*head);
  }
  if (!(p == "/ypr" || p == "/xyzypr" || p == "/yaw" || p == "/pitch" || p == "/roll" || p == "/xyz")) {
    // Keep the angles in step, so a later /yaw keeps this pitch and roll.
    const YawPitchRoll e = ypr_from_quat(to_common(*head));
    sparta_ = as_array(e.yaw / kDeg, -e.pitch / kDeg, e.roll / kDeg);
  }
  sparta_q_ = q;
  sparta_position_m_ = position;
  return pose(position, *head);
}

std::optional<PoseMessage> OscPoseDecoder::scene_rotator(const std::string& p, std::string_view path,
                                                         const std::vector<double>& v, std::string* why) {
  // The scene's rotation q = (w x y z) about SAF's axes; the head is its
  // inverse (w -x -y -z), which in Earshot's axes is (w, y, -z, x).
  auto head_from_q = [](const std::array<double, 4>& q) { return Quat(q[0], q[2], -q[3], q[1]); };
  auto angles_from_head = [](const Quat& h) {
    const YawPitchRoll a = ypr_from_quat(to_common(h));
    return as_array(-a.yaw / kDeg, a.pitch / kDeg, -a.roll / kDeg);
  };
  const std::string_view leaf = std::string_view(p).substr(std::string_view("/scenerotator/").size());
  const int component = component_of(p);
  if (leaf == "quaternions" || component >= 0) {
    // SceneRotator's qw..qz parameters are -1..1 (a value beyond is clamped,
    // as its OSC interface does); it normalises the four before use.
    std::array<double, 4> q = scene_rotator_q_;
    if (leaf == "quaternions") q = {v[0], v[1], v[2], v[3]};
    else q[static_cast<std::size_t>(component)] = v[0];
    for (double& c : q) c = std::clamp(c, -1.0, 1.0);
    const Quat h = head_from_q(q);
    if (component >= 0 && std::abs(h.norm() - 1.0) > kComponentsUnitTolerance) {
      scene_rotator_q_ = q;  // one component of several: wait for the rest
      return drop(why, where(path) + ": quaternion (w x y z) is not unit length yet; waiting for the other components");
    }
    const auto head = normalised_quat(h.w(), h.x(), h.y(), h.z(), path, why);
    if (!head) return std::nullopt;
    scene_rotator_q_ = q;
    scene_rotator_ = angles_from_head(*head);
    return pose(Vec3::Zero(), *head);
  }
  std::array<double, 3> next = scene_rotator_;
  if (leaf == "ypr") next = as_array(clamped_iem(v[0]), clamped_iem(v[1]), clamped_iem(v[2]));
  else next[leaf == "yaw" ? 0 : leaf == "pitch" ? 1 : 2] = clamped_iem(v[0]);
  scene_rotator_ = next;
  const Quat h = scene_rotator_head(next[0], next[1], next[2]);
  const std::array<double, 4> q = scene_rotator_quaternions(h);
  scene_rotator_q_ = q;
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

std::size_t write_osc_floats(std::span<std::uint8_t> out, std::string_view address, std::span<const float> args) {
  const auto padded = [](std::size_t n) { return (n + 4) & ~std::size_t{3}; };  // n bytes and a NUL, to 4
  const std::size_t a = padded(address.size()), t = padded(1 + args.size());
  const std::size_t size = a + t + 4 * args.size();
  if (address.empty() || address.front() != '/' || address.find('\0') != std::string_view::npos || size > out.size())
    return 0;
  std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(size), std::uint8_t{0});
  std::memcpy(out.data(), address.data(), address.size());
  out[a] = ',';
  for (std::size_t i = 0; i < args.size(); ++i) out[a + 1 + i] = 'f';
  for (std::size_t i = 0; i < args.size(); ++i) {
    const auto u = std::bit_cast<std::uint32_t>(args[i]);
    for (std::size_t k = 0; k < 4; ++k) out[a + t + 4 * i + k] = static_cast<std::uint8_t>(u >> (24 - 8 * k));
  }
  return size;
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
