#include "earshot/tracker/track/labeller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "earshot/tracker/solve/lm_refine.hpp"
#include "earshot/tracker/solve/p3p.hpp"

namespace earshot::tracker {
namespace {


int visible_dots(const DotFrame& f, std::array<DotAt, kSlots>& out) {
  int n = 0;
  for (int s = 0; s < kSlots; ++s)
    if (const auto& d = f.slots[static_cast<size_t>(s)]) out[static_cast<size_t>(n++)] = {s, *d};
  return n;
}

double triangle_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 u = b - a, v = c - a;
  return 0.5 * std::abs(u.x() * v.y() - u.y() * v.x());
}

}  // namespace

bool leds_face_camera(const Pose& p, const LedModel& model, std::span<const Correspondence> dots,
                      double max_angle) {
  const Vec3 axis = p.R * model.axis;
  const double c = std::cos(std::min(max_angle, 3.14159));
  for (const auto& d : dots)
    if (axis.dot(-p.apply(model.leds_mm[static_cast<size_t>(d.led)]).normalized()) < c) return false;
  return true;
}

Labeller::Labeller(const Camera& cam, const LedModel& model, LabellerOptions opt)
    : cam_(cam), model_(model), opt_(opt) {}

void Labeller::try_triple(const std::array<int, 4>& order, const std::array<DotAt, kSlots>& dots,
                          std::vector<Labelling>& found) const {
  std::array<Vec3, 3> bearings;
  for (size_t i = 0; i < 3; ++i) bearings[i] = cam_.bearing(dots[static_cast<size_t>(order[i])].px);

  std::array<int, 4> perm{0, 1, 2, 3};  // perm[i] = LED of dot order[i]
  do {
    const std::array<Vec3, 3> pts{model_.leds_mm[static_cast<size_t>(perm[0])],
                                  model_.leds_mm[static_cast<size_t>(perm[1])],
                                  model_.leds_mm[static_cast<size_t>(perm[2])]};
    const P3PSolutions sols = p3p_lambda_twist(bearings, pts);
    for (int k = 0; k < sols.count; ++k) {
      const Pose& p = sols.poses[static_cast<size_t>(k)];
      const Vec3 P4 = p.apply(model_.leds_mm[static_cast<size_t>(perm[3])]);
      if (P4.z() <= 0.0) continue;
      // Cheap check first: the fourth LED must land near the fourth dot.
      if ((cam_.project(P4) - dots[static_cast<size_t>(order[3])].px).norm() > 4.0 * opt_.match_gate_px) continue;
      Labelling l;
      for (size_t i = 0; i < 4; ++i) {
        const DotAt& d = dots[static_cast<size_t>(order[i])];
        l.slot_led[static_cast<size_t>(d.slot)] = perm[i];
        l.dots.add(perm[i], d.px);
      }
      const LmResult r = refine_pose_lm(p, l.dots.view(), cam_, model_);
      l.pose = r.pose;
      l.rms_px = rms_reprojection_error(r.pose, l.dots.view(), cam_, model_);
      if (!(l.rms_px <= opt_.fit_gate_px) || !l.pose.finite()) continue;
      if (!leds_face_camera(l.pose, model_, l.dots.view(), model_.half_angle + opt_.beam_margin_rad)) continue;
      // The same labelling and pose can be reached from several P3P roots.
      const bool dup = std::any_of(found.begin(), found.end(), [&](const Labelling& o) {
        return o.slot_led == l.slot_led && rotation_angle_between(o.pose.R, l.pose.R) < 0.01 &&
               (o.pose.t - l.pose.t).norm() < 5.0;
      });
      if (!dup) found.push_back(l);
    }
  } while (std::next_permutation(perm.begin(), perm.end()));

}

std::vector<Labelling> Labeller::acquire(const DotFrame& frame, size_t max_hypotheses) const {
  std::vector<Labelling> found;
  std::array<DotAt, kSlots> dots{};
  if (visible_dots(frame, dots) < 4) return found;

  // Solve P3P on triples of dots, best-conditioned (largest image triangle)
  // first; the fourth dot checks each hypothesis. A symmetric triple seen
  // head-on puts P3P on a double root that rounding can lose, so when one
  // triple explains nothing the next is tried.
  std::array<std::array<int, 4>, 4> orders{};
  std::array<double, 4> areas{};
  for (int skip = 0; skip < 4; ++skip) {
    std::array<int, 4> o{};
    int k = 0;
    for (int i = 0; i < 4; ++i)
      if (i != skip) o[static_cast<size_t>(k++)] = i;
    o[3] = skip;
    orders[static_cast<size_t>(skip)] = o;
    areas[static_cast<size_t>(skip)] = triangle_area(dots[static_cast<size_t>(o[0])].px,
                                                     dots[static_cast<size_t>(o[1])].px,
                                                     dots[static_cast<size_t>(o[2])].px);
  }
  std::array<int, 4> rank{0, 1, 2, 3};
  std::sort(rank.begin(), rank.end(), [&](int a, int b) { return areas[static_cast<size_t>(a)] > areas[static_cast<size_t>(b)]; });
  for (int r = 0; r < 4 && found.empty(); ++r) {
    const std::array<int, 4>& order = orders[static_cast<size_t>(rank[static_cast<size_t>(r)])];
    try_triple(order, dots, found);
  }
  std::sort(found.begin(), found.end(),
            [](const Labelling& a, const Labelling& b) { return a.rms_px < b.rms_px; });
  if (found.size() > max_hypotheses) found.resize(max_hypotheses);
  return found;
}

std::optional<Labelling> Labeller::reacquire3(const DotFrame& frame, const Pose& last,
                                              double max_angle_rad, double max_shift_mm) const {
  std::array<DotAt, kSlots> dots{};
  if (visible_dots(frame, dots) != 3) return std::nullopt;
  std::array<Vec3, 3> bearings;
  for (size_t i = 0; i < 3; ++i) bearings[i] = cam_.bearing(dots[i].px);
  const double cos_half = std::cos(model_.half_angle);
  // Distance to the last pose: radians plus translation at 100 mm per radian.
  double best = std::numeric_limits<double>::infinity(), second = best;
  std::optional<Labelling> out;
  std::array<int, 4> perm{0, 1, 2, 3};  // perm[0..2]: LEDs of the dots, perm[3]: unseen
  do {
    const std::array<Vec3, 3> pts{model_.leds_mm[static_cast<size_t>(perm[0])],
                                  model_.leds_mm[static_cast<size_t>(perm[1])],
                                  model_.leds_mm[static_cast<size_t>(perm[2])]};
    const P3PSolutions sols = p3p_lambda_twist(bearings, pts);
    for (int k = 0; k < sols.count; ++k) {
      const Pose& p = sols.poses[static_cast<size_t>(k)];
      // The LED we do not see must be one the camera could not see.
      const Vec3 P4 = p.apply(model_.leds_mm[static_cast<size_t>(perm[3])]);
      const bool beam_ok = (p.R * model_.axis).dot(-P4.normalized()) >= cos_half;
      if (P4.z() > 0.0 && beam_ok && cam_.inside(cam_.project(P4))) continue;
      // The LEDs we see must face the camera.
      bool facing = true;
      for (size_t i = 0; i < 3; ++i) {
        const Vec3 P = p.apply(pts[i]);
        facing = facing && (p.R * model_.axis).dot(-P.normalized()) >= cos_half - 0.05;
      }
      if (!facing) continue;
      const double ang = rotation_angle_between(p.R, last.R);
      const double shift = (p.t - last.t).norm();
      if (ang > max_angle_rad || shift > max_shift_mm) continue;
      const double d = ang + shift / 100.0;
      if (d < best) {
        second = best;
        best = d;
        Labelling l;
        for (size_t i = 0; i < 3; ++i) {
          l.slot_led[static_cast<size_t>(dots[i].slot)] = perm[i];
          l.dots.add(perm[i], dots[i].px);
        }
        l.pose = p;
        out = l;
      } else if (d < second) {
        second = d;
      }
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  if (!out || second < 2.0 * best) return std::nullopt;  // not clearly one answer
  return out;
}

std::optional<Labelling> Labeller::follow(const DotFrame& frame, const Pose& predicted) const {
  std::array<DotAt, kSlots> dots{};
  const int n = visible_dots(frame, dots);
  if (n < 3) return std::nullopt;
  std::array<Vec2, 4> proj;
  std::array<bool, 4> in_front{};
  for (size_t l = 0; l < 4; ++l) {
    const Vec3 P = predicted.apply(model_.leds_mm[l]);
    in_front[l] = P.z() > 0.0;
    proj[l] = in_front[l] ? cam_.project(P) : Vec2(1e9, 1e9);
  }
  // Best assignment of dots to LEDs: most matches within the gate, then the
  // smallest total squared distance. 24 permutations cover every case.
  const double gate2 = opt_.match_gate_px * opt_.match_gate_px;
  int best_matches = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  std::array<int, 4> best{-1, -1, -1, -1};
  std::array<int, 4> perm{0, 1, 2, 3};
  do {
    int matches = 0;
    double cost = 0.0;
    std::array<int, 4> assign{-1, -1, -1, -1};
    for (int i = 0; i < n; ++i) {
      const int led = perm[static_cast<size_t>(i)];
      const double d2 = (proj[static_cast<size_t>(led)] - dots[static_cast<size_t>(i)].px).squaredNorm();
      if (d2 <= gate2) {
        ++matches;
        cost += d2;
        assign[static_cast<size_t>(i)] = led;
      } else {
        cost += gate2;  // an unmatched dot costs the gate
      }
    }
    if (matches > best_matches || (matches == best_matches && cost < best_cost)) {
      best_matches = matches;
      best_cost = cost;
      best = assign;
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  if (best_matches < 3) return std::nullopt;

  Labelling l;
  for (int i = 0; i < n; ++i) {
    const int led = best[static_cast<size_t>(i)];
    if (led < 0) continue;
    l.slot_led[static_cast<size_t>(dots[static_cast<size_t>(i)].slot)] = led;
    l.dots.add(led, dots[static_cast<size_t>(i)].px);
  }
  l.pose = predicted;
  l.rms_px = rms_reprojection_error(predicted, l.dots.view(), cam_, model_);
  return l;
}

std::optional<LabelledDots> ThesisLabeller::label(const DotFrame& frame) {
  std::array<Vec2, 4> pts;
  int n = 0;
  for (const auto& s : frame.slots)
    if (s) pts[static_cast<size_t>(n++)] = *s;
  if (n < 4) {
    have_prev_ = false;  // the thesis drops the frame and starts over
    return std::nullopt;
  }
  std::array<Vec2, 4> labelled;
  if (!have_prev_) {
    // Two rows by y, each row split by x (fig. 45). With the beacon upright,
    // LEDs 1 and 2 (model +y) appear lower in the image (+y down), LED 1 right.
    std::array<int, 4> idx{0, 1, 2, 3};
    std::sort(idx.begin(), idx.end(), [&](int a, int b) {
      return pts[static_cast<size_t>(a)].y() < pts[static_cast<size_t>(b)].y();
    });
    auto split = [&](int a, int b, int right_led, int left_led) {
      const bool a_right = pts[static_cast<size_t>(a)].x() >= pts[static_cast<size_t>(b)].x();
      labelled[static_cast<size_t>(right_led)] = pts[static_cast<size_t>(a_right ? a : b)];
      labelled[static_cast<size_t>(left_led)] = pts[static_cast<size_t>(a_right ? b : a)];
    };
    split(idx[0], idx[1], 2, 3);  // top row: LED 3 right, LED 4 left
    split(idx[2], idx[3], 0, 1);  // bottom row: LED 1 right, LED 2 left
  } else {
    // Nearest dot to each LED's previous position (fig. 46).
    std::array<bool, 4> used{};
    for (size_t l = 0; l < 4; ++l) {
      int best = -1;
      double bd = std::numeric_limits<double>::infinity();
      for (int i = 0; i < 4; ++i) {
        if (used[static_cast<size_t>(i)]) continue;
        const double d = (pts[static_cast<size_t>(i)] - prev_[l]).squaredNorm();
        if (d < bd) {
          bd = d;
          best = i;
        }
      }
      used[static_cast<size_t>(best)] = true;
      labelled[l] = pts[static_cast<size_t>(best)];
    }
  }
  prev_ = labelled;
  have_prev_ = true;
  LabelledDots out;
  for (int l = 0; l < 4; ++l) out.add(l, labelled[static_cast<size_t>(l)]);
  return out;
}

}  // namespace earshot::tracker
