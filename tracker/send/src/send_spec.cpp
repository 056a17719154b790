#include "earshot/tracker/send/send_spec.hpp"

#include <charconv>
#include <cmath>
#include <optional>

#include "earshot/errors.hpp"

namespace earshot::tracker {
namespace {

constexpr std::uint16_t kOscPort = 9000;        // SPARTA's default, and our OSC input's
constexpr std::uint16_t kOpentrackPort = 4242;  // opentrack's
constexpr double kMinRateHz = 1.0, kMaxRateHz = 1000.0;

/// "FIELD: send 'SPEC': WHY".
InputError spec_error(std::string_view field, std::string_view spec, const std::string& why) {
  return InputError::at(field, 0, "", "send '" + std::string(spec) + "': " + why);
}

bool all_digits(std::string_view s) {
  if (s.empty()) return false;
  for (const char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

/// A host name or IPv4 address as getaddrinfo takes it: letters, digits,
/// '-' and '.', labels of 1-63, 253 at most. (IPv6 literals hold ':', which
/// separates the port here: not taken.)
bool host_name(std::string_view s) {
  if (s.empty() || s.size() > 253 || s.front() == '.' || s.back() == '.' || s.front() == '-') return false;
  std::size_t label = 0;
  for (const char c : s) {
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    if (c == '.') {
      if (label == 0) return false;
      label = 0;
    } else if (alnum || c == '-') {
      if (++label > 63) return false;
    } else {
      return false;
    }
  }
  return true;
}

std::uint16_t port_of(std::string_view spec, std::string_view field, std::string_view arg) {
  unsigned v = 0;
  const auto [end, ec] = std::from_chars(arg.data(), arg.data() + arg.size(), v);
  if (!all_digits(arg) || ec != std::errc{} || end != arg.data() + arg.size() || v < 1 || v > 65535)
    throw spec_error(field, spec, "bad UDP port '" + std::string(arg) + "' (1-65535)");
  return static_cast<std::uint16_t>(v);
}

}  // namespace

std::string_view send_format_name(SendSpec::Format f) {
  switch (f) {
    case SendSpec::Format::earshot: return "earshot";
    case SendSpec::Format::sparta: return "sparta";
    case SendSpec::Format::iem: return "iem";
    case SendSpec::Format::iem_ypr: return "iem-ypr";
  }
  return "?";
}

SendSpec parse_send_spec(std::string_view spec, std::string_view field) {
  SendSpec s;
  s.text = std::string(spec);
  const std::size_t comma = spec.find(',');
  const std::string_view head = spec.substr(0, comma);
  const std::string_view options = comma == std::string_view::npos ? std::string_view() : spec.substr(comma + 1);

  // KIND[:HOST][:PORT]
  const std::size_t colon = head.find(':');
  const std::string_view kind = head.substr(0, colon);
  if (kind == "osc") s.kind = SendSpec::Kind::osc;
  else if (kind == "opentrack") s.kind = SendSpec::Kind::opentrack;
  else throw InputError::at(field, 0, "", "unknown send '" + std::string(spec) + "' (" + std::string(kSendSpecs) + ")");
  s.port = s.kind == SendSpec::Kind::osc ? kOscPort : kOpentrackPort;
  if (colon != std::string_view::npos) {
    const std::string_view rest = head.substr(colon + 1);
    const std::size_t second = rest.find(':');
    std::optional<std::string_view> host, port;
    if (second != std::string_view::npos) {
      host = rest.substr(0, second);
      port = rest.substr(second + 1);
      if (port->find(':') != std::string_view::npos)
        throw spec_error(field, spec, "too many ':' (KIND[:HOST][:PORT]; IPv6 addresses are not supported)");
    } else if (all_digits(rest)) {
      port = rest;
    } else {
      host = rest;
    }
    if (host) {
      if (!host_name(*host))
        throw spec_error(field, spec, "bad host '" + std::string(*host) + "' (an IPv4 address such as 127.0.0.1 or a host name)");
      s.host = std::string(*host);
    }
    if (port) s.port = port_of(spec, field, *port);
  }

  // ,OPTION=VALUE...
  bool have_format = false, have_rate = false;
  std::string_view rest = options;
  while (comma != std::string_view::npos) {
    const std::size_t next = rest.find(',');
    const std::string_view option = rest.substr(0, next);
    const std::size_t eq = option.find('=');
    const std::string_view name = option.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? std::string_view() : option.substr(eq + 1);
    if (option.empty()) throw spec_error(field, spec, "empty option (a ',' too many)");
    if (eq == std::string_view::npos || value.empty())
      throw spec_error(field, spec, "option '" + std::string(option) + "' needs a value (NAME=VALUE)");
    if (name == "format") {
      if (have_format) throw spec_error(field, spec, "format given twice");
      have_format = true;
      if (s.kind != SendSpec::Kind::osc)
        throw spec_error(field, spec, "format= is for osc (opentrack has one packet format)");
      if (value == "earshot") s.format = SendSpec::Format::earshot;
      else if (value == "sparta") s.format = SendSpec::Format::sparta;
      else if (value == "iem") s.format = SendSpec::Format::iem;
      else if (value == "iem-ypr") s.format = SendSpec::Format::iem_ypr;
      else throw spec_error(field, spec, "unknown format '" + std::string(value) + "' (earshot, sparta, iem, iem-ypr)");
    } else if (name == "rate") {
      if (have_rate) throw spec_error(field, spec, "rate given twice");
      have_rate = true;
      double v = 0.0;
      const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
      if (ec != std::errc{} || end != value.data() + value.size() || !std::isfinite(v) || v < kMinRateHz || v > kMaxRateHz)
        throw spec_error(field, spec, "bad rate '" + std::string(value) + "' (poses per second, 1-1000)");
      s.rate_hz = v;
    } else {
      throw spec_error(field, spec, "unknown option '" + std::string(name) + "' (format, rate)");
    }
    if (next == std::string_view::npos) break;
    rest = rest.substr(next + 1);
  }
  return s;
}

std::vector<SendSpec> parse_send_list(std::string_view text, std::string_view field) {
  std::vector<SendSpec> out;
  while (!text.empty()) {
    const std::size_t semi = text.find(';');
    std::string_view one = text.substr(0, semi);
    while (!one.empty() && (one.front() == ' ' || one.front() == '\t')) one.remove_prefix(1);
    while (!one.empty() && (one.back() == ' ' || one.back() == '\t')) one.remove_suffix(1);
    if (!one.empty()) out.push_back(parse_send_spec(one, field));
    if (semi == std::string_view::npos) break;
    text.remove_prefix(semi + 1);
  }
  return out;
}

std::string send_list_text(const std::vector<SendSpec>& specs) {
  std::string s;
  for (const SendSpec& spec : specs) {
    if (!s.empty()) s += ';';
    s += spec.text;
  }
  return s;
}

}  // namespace earshot::tracker
