// Labelling: which image dot is which LED, for any roll and any slot order.
//
// Acquisition tests hypotheses geometrically: three dots are given three LEDs
// (every ordered choice), Lambda Twist P3P gives up to four poses each, and a
// hypothesis must reproject the remaining LED onto the remaining dot. The
// survivors are refined by LM on all dots and must fit within the pixel gate,
// and every LED they claim to see must face the camera (within its beam):
// that rules out the mirror pose that fits a small beacon almost as well.
// While tracking, the predicted pose's projections are matched to the dots
// (best of all assignments, gated), so slot swaps and re-appearing dots are
// labelled too. A labelling that does not fit the model is rejected.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "earshot/tracker/core/correspondence.hpp"
#include "earshot/tracker/core/dots_csv.hpp"

namespace earshot::tracker {

struct LabellerOptions {
  /// Largest RMS reprojection error (px) of an accepted labelling.
  double fit_gate_px = 4.0;
  /// Largest distance (px) between a predicted LED projection and its dot.
  double match_gate_px = 40.0;
  /// A seen LED must face the camera: a hypothesis that turns one further
  /// than its beam half-angle plus this margin (radians) is impossible.
  double beam_margin_rad = 0.26;
};

/// True when every listed LED shines toward the camera within `max_angle`
/// (radians) of its axis: the camera cannot see an LED that faces away.
[[nodiscard]] bool leds_face_camera(const Pose& p, const LedModel& model,
                                    std::span<const Correspondence> dots, double max_angle);

/// One labelling hypothesis with its refined pose.
struct Labelling {
  std::array<int, kSlots> slot_led{-1, -1, -1, -1};  ///< LED 0-3 per slot, -1 none
  LabelledDots dots;
  Pose pose;
  double rms_px = 0.0;
};

/// A dot seen in a camera slot.
struct DotAt {
  int slot = 0;
  Vec2 px;
};

class Labeller {
 public:
  Labeller(const Camera& cam, const LedModel& model, LabellerOptions opt = {});

  /// Every labelling of a frame with four or more dots that fits the model,
  /// best first (at most `max_hypotheses`). Empty when nothing fits.
  [[nodiscard]] std::vector<Labelling> acquire(const DotFrame& frame, size_t max_hypotheses = 4) const;

  /// Re-acquires from exactly three dots after a loss, near the last known
  /// pose: every ordered LED triple's P3P solutions are candidates; the
  /// unseen LED must be hidden (outside the image or turned beyond its beam),
  /// and the candidate nearest `last` must be within the limits and clearly
  /// nearer than any rival. nullopt when that is not so.
  [[nodiscard]] std::optional<Labelling> reacquire3(const DotFrame& frame, const Pose& last,
                                                    double max_angle_rad = 1.2,
                                                    double max_shift_mm = 400.0) const;

  /// Labels a frame near a predicted pose (3 or 4 dots). nullopt when fewer
  /// than three dots match within the gate.
  [[nodiscard]] std::optional<Labelling> follow(const DotFrame& frame, const Pose& predicted) const;

  [[nodiscard]] const LabellerOptions& options() const { return opt_; }
  /// The fit gate of acquisition (the tracker widens it for coarse pixels).
  void set_fit_gate_px(double gate) { opt_.fit_gate_px = gate; }

 private:
  /// Hypotheses from P3P on dots order[0..2], checked against dot order[3].
  void try_triple(const std::array<int, 4>& order, const std::array<DotAt, kSlots>& dots,
                  std::vector<Labelling>& found) const;

  Camera cam_;
  LedModel model_;
  LabellerOptions opt_;
};

/// The thesis's labelling (section 3.2.6): at the start, split the dots into
/// two rows by y and each row by x (valid only while the head is upright);
/// afterwards, each LED takes the nearest dot of the next frame.
class ThesisLabeller {
 public:
  /// Labelled dots (all four) or nullopt when fewer than four are visible.
  std::optional<LabelledDots> label(const DotFrame& frame);
  void reset() { have_prev_ = false; }

 private:
  std::array<Vec2, 4> prev_{};
  bool have_prev_ = false;
};

}  // namespace earshot::tracker
