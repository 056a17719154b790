#include "earshot/tracker/dots_csv.hpp"

#include <fstream>
#include <iomanip>
#include <istream>
#include <ostream>

#include "csv_fields.hpp"

namespace earshot::tracker {
namespace {

constexpr std::array<const char*, 9> kDotColumns{"t_s", "x1", "y1", "x2", "y2",
                                                 "x3", "y3", "x4", "y4"};
constexpr std::array<const char*, 11> kTruthColumns{
    "gt_tx_mm", "gt_ty_mm", "gt_tz_mm", "gt_qw", "gt_qx", "gt_qy",
    "gt_qz",    "gt_led1",  "gt_led2",  "gt_led3", "gt_led4"};

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
  f.t = csv::number(fields[0], origin, line_number, "t_s");
  for (size_t s = 0; s < kSlots; ++s) {
    const auto x = csv::optional_number(fields[1 + 2 * s], origin, line_number, kDotColumns[1 + 2 * s]);
    const auto y = csv::optional_number(fields[2 + 2 * s], origin, line_number, kDotColumns[2 + 2 * s]);
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
    for (size_t i = 0; i < 7; ++i) v[i] = csv::number(fields[b + i], origin, line_number, kTruthColumns[i]);
    GroundTruth gt;
    const Quat q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw InputError::at(origin, line_number, "gt_qw", "quaternion is not unit length");
    gt.pose = Pose::from(q, Vec3(v[0], v[1], v[2]));
    for (size_t s = 0; s < kSlots; ++s) {
      const double l = csv::number(fields[b + 7 + s], origin, line_number, kTruthColumns[7 + s]);
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
