#include "earshot/tracker/core/dots_csv.hpp"

#include <cstdint>
#include <fstream>
#include <iomanip>
#include <istream>
#include <ostream>

#include "earshot/csv_fields.hpp"

namespace earshot::tracker {
namespace {

constexpr std::array<const char*, 9> kDotColumns{"t_s", "x1", "y1", "x2", "y2",
                                                 "x3", "y3", "x4", "y4"};
constexpr std::array<const char*, 11> kTruthColumns{
    "gt_tx_mm", "gt_ty_mm", "gt_tz_mm", "gt_qw", "gt_qx", "gt_qy",
    "gt_qz",    "gt_led1",  "gt_led2",  "gt_led3", "gt_led4"};

/// Plain decimals ([-]digits[.digits], at most 15 digits: every pixel and
/// most truth fields) without std::from_chars: the digits as an integer m
/// (< 10^15 < 2^53, exact) over 10^k (k <= 15, exact), and one IEEE
/// division of two exact doubles is correctly rounded, so the value is the
/// one from_chars gives (Clinger's fast path). Anything else (exponents,
/// more digits, spaces, signs other than '-', bad text) goes to
/// csv::optional_number, which also reports errors.
std::optional<double> number_or_empty(std::string_view field, std::string_view origin, long line, std::string_view name) {
  static constexpr double kPow10[16] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                        1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  const char* p = field.data();
  const char* const end = p + field.size();
  const bool negative = p != end && *p == '-';
  if (negative) ++p;
  std::uint64_t m = 0;
  int digits = 0, fraction = 0;
  bool point = false;
  for (; p != end; ++p) {
    const char c = *p;
    if (c >= '0' && c <= '9') {
      m = m * 10 + static_cast<std::uint64_t>(c - '0');
      ++digits;
      fraction += point ? 1 : 0;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      break;
    }
  }
  if (p != end || digits == 0 || digits > 15) return csv::optional_number(field, origin, line, name);
  const double v = static_cast<double>(m) / kPow10[fraction];
  return negative ? -v : v;
}

double number(std::string_view field, std::string_view origin, long line, std::string_view name) {
  const auto v = number_or_empty(field, origin, line, name);
  if (!v) throw InputError::at(origin, line, name, "missing value");
  return *v;
}

}  // namespace

int DotFrame::visible() const {
  int n = 0;
  for (const auto& s : slots) n += s.has_value() ? 1 : 0;
  return n;
}

DotFrame parse_dots_line(std::string_view line, bool with_truth, std::string_view origin,
                         long line_number) {
  std::array<std::string_view, kDotColumns.size() + kTruthColumns.size()> fields;
  const size_t found = csv::split_into(line, fields);
  const size_t need = kDotColumns.size() + (with_truth ? kTruthColumns.size() : 0);
  if (found < need)
    throw InputError::at(origin, line_number, "",
                         "expected at least " + std::to_string(need) + " fields, found " +
                             std::to_string(found));
  DotFrame f;
  f.t = number(fields[0], origin, line_number, "t_s");
  for (size_t s = 0; s < kSlots; ++s) {
    const auto x = number_or_empty(fields[1 + 2 * s], origin, line_number, kDotColumns[1 + 2 * s]);
    const auto y = number_or_empty(fields[2 + 2 * s], origin, line_number, kDotColumns[2 + 2 * s]);
    if (x.has_value() != y.has_value())
      throw InputError::at(origin, line_number, x ? kDotColumns[2 + 2 * s] : kDotColumns[1 + 2 * s],
                           "a dot needs both x and y (or neither)");
    if (x) {
      if (std::abs(*x) > 1e6 || std::abs(*y) > 1e6)
        throw InputError::at(origin, line_number, kDotColumns[1 + 2 * s], "pixel out of range");
      f.slots[s] = Vec2(*x, *y);
    }
  }
  if (with_truth) {
    const size_t b = kDotColumns.size();
    double v[7];
    for (size_t i = 0; i < 7; ++i) v[i] = number(fields[b + i], origin, line_number, kTruthColumns[i]);
    GroundTruth gt;
    const Quat q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw InputError::at(origin, line_number, "gt_qw", "quaternion is not unit length");
    gt.pose = Pose::from(q, Vec3(v[0], v[1], v[2]));
    for (size_t s = 0; s < kSlots; ++s) {
      const double l = number(fields[b + 7 + s], origin, line_number, kTruthColumns[7 + s]);
      if (l != std::floor(l) || l < -1 || l > 4)
        throw InputError::at(origin, line_number, kTruthColumns[7 + s], "expected -1..4");
      gt.slot_led[s] = static_cast<int>(l);
    }
    f.truth = gt;
  }
  return f;
}

DotsCsvReader::DotsCsvReader(std::istream& in, std::string origin)
    : in_(in), origin_(std::move(origin)) {}

std::optional<DotFrame> DotsCsvReader::next() {
  std::string& line = line_buf_;  // reused: no allocation per line
  while (std::getline(in_, line)) {
    ++line_;
    if (csv::trim(line).empty() || line == "\r") continue;
    if (line_ == 1 || header_.empty()) {
      if (header_.empty()) {
        const auto cols = csv::split(line);
        for (auto c : cols) header_.emplace_back(csv::trim(c));
        if (header_.size() < kDotColumns.size())
          throw InputError::at(origin_, line_, "", "header needs the columns t_s,x1,y1,...,x4,y4");
        for (size_t i = 0; i < kDotColumns.size(); ++i)
          if (header_[i] != kDotColumns[i])
            throw InputError::at(origin_, line_, kDotColumns[i],
                                 "header column " + std::to_string(i + 1) + " is '" + header_[i] +
                                     "'");
        has_truth_ = header_.size() >= kDotColumns.size() + kTruthColumns.size() &&
                     header_[kDotColumns.size()] == kTruthColumns[0];
        continue;
      }
    }
    return parse_dots_line(line, has_truth_, origin_, line_);
  }
  if (header_.empty()) throw InputError::at(origin_, 0, "", "empty file: no header line");
  return std::nullopt;
}

std::vector<DotFrame> read_dots_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError::at(path, 0, "", "cannot open file");
  DotsCsvReader r(in, path);
  std::vector<DotFrame> frames;
  while (auto f = r.next()) frames.push_back(*f);
  return frames;
}

DotsCsvWriter::DotsCsvWriter(std::ostream& out, bool with_truth)
    : out_(out), with_truth_(with_truth) {
  for (size_t i = 0; i < kDotColumns.size(); ++i) out_ << (i ? "," : "") << kDotColumns[i];
  if (with_truth_)
    for (auto c : kTruthColumns) out_ << ',' << c;
  out_ << '\n';
}

void DotsCsvWriter::write(const DotFrame& f) {
  out_ << std::setprecision(10) << f.t;
  out_ << std::setprecision(8);
  for (const auto& s : f.slots) {
    if (s)
      out_ << ',' << s->x() << ',' << s->y();
    else
      out_ << ",,";
  }
  if (with_truth_) {
    const GroundTruth gt = f.truth.value_or(GroundTruth{});
    const Quat q = gt.pose.quaternion();
    out_ << std::setprecision(10) << ',' << gt.pose.t.x() << ',' << gt.pose.t.y() << ','
         << gt.pose.t.z() << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z();
    for (int l : gt.slot_led) out_ << ',' << l;
  }
  out_ << '\n';
}

}  // namespace earshot::tracker
