#include "earshot/tracker/osc_pose.hpp"

#include <lo/lo.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>

#include "earshot/tracker/live_pipeline.hpp"

namespace earshot::tracker {
namespace {

struct MessageFree {
  void operator()(lo_message m) const { lo_message_free(m); }
};
using Message = std::unique_ptr<std::remove_pointer_t<lo_message>, MessageFree>;

/// Records why a message is dropped.
std::nullopt_t drop(std::string* why, const std::string& msg) {
  if (why) *why = msg;
  return std::nullopt;
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

std::optional<PoseMessage> handle(std::string_view path, std::string_view types, lo_arg** argv, std::string* why) {
  const std::string where = "OSC " + std::string(path);
  if (path == "/earshot/recenter") {
    if (!types.empty()) return drop(why, where + ": takes no arguments");
    return PoseMessage{std::nullopt, true};
  }
  std::size_t want = 0, pos = 0;
  bool quat = false;
  if (path == "/earshot/pose/ypr") want = 6, pos = 3;
  else if (path == "/earshot/pose/quat") want = 7, pos = 3, quat = true;
  else if (path == "/earshot/ypr") want = 3;
  else if (path == "/earshot/quat") want = 4, quat = true;
  else return drop(why, "OSC address " + std::string(path) + " is not one of ours");

  const auto v = numbers(types, argv);
  if (!v || v->size() != want)
    return drop(why, where + ": expected " + std::to_string(want) + " numbers, got type tags '" + std::string(types) + "'");
  for (double x : *v)
    if (!std::isfinite(x)) return drop(why, where + ": a value is not finite");
  DirectPose d;
  if (pos) d.position_m = Vec3((*v)[0], (*v)[1], (*v)[2]);
  if (d.position_m.norm() > kMaxPositionM)
    return drop(why, where + ": position beyond " + std::to_string(kMaxPositionM) + " m");
  if (quat) {
    const Quat q((*v)[pos], (*v)[pos + 1], (*v)[pos + 2], (*v)[pos + 3]);
    if (std::abs(q.norm() - 1.0) > 0.01) return drop(why, where + ": quaternion is not unit length");
    d.orientation = q.normalized();
  } else {
    constexpr double deg = std::numbers::pi / 180.0;
    for (std::size_t i = pos; i < pos + 3; ++i)
      if (std::abs((*v)[i]) > 720.0) return drop(why, where + ": angle beyond 720 degrees");
    d.orientation = to_eigen(quat_from_ypr((*v)[pos] * deg, (*v)[pos + 1] * deg, (*v)[pos + 2] * deg));
  }
  return PoseMessage{d, false};
}

}  // namespace

std::optional<PoseMessage> decode_osc(std::span<const std::uint8_t> bytes, std::string* why) {
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), "#bundle", 8) == 0)
    return drop(why, "OSC bundles are not supported; send plain messages");
  // liblo wants writable memory and checks the whole message (path, type
  // tags, argument sizes) before it gives one back.
  std::vector<std::uint8_t> copy(bytes.begin(), bytes.end());
  int result = 0;
  const Message m(copy.empty() ? nullptr : lo_message_deserialise(copy.data(), copy.size(), &result));
  if (!m) return drop(why, "malformed OSC message (liblo error " + std::to_string(result) + ")");
  const auto* path = reinterpret_cast<const char*>(copy.data());
  const std::string_view p(path, strnlen(path, copy.size()));
  const char* types = lo_message_get_types(m.get());
  return handle(p, types ? std::string_view(types) : std::string_view(), lo_message_get_argv(m.get()), why);
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

}  // namespace earshot::tracker
