// What the listener hears, scored per walk (tracker_motion --listener): for
// raw LM, the default (eskf), --smooth (eskf + RTS + vetting, offline) and
// a baseline that holds raw LM's last tracked pose through every frame it
// does not track:
//  - tracked: share of the frames with 3+ LEDs seen given out as tracking;
//  - RMS rotation and translation over the 4-LED frames both the row and
//    raw LM track, as a ratio to raw LM's over the same frames;
//  - still jitter: on still stretches (true speed < 5 deg/s), the RMS of the
//    frame-to-frame change of the rotation error (log(R_out R_true^T)) over
//    consecutive frames both the row and raw LM track, as a ratio to raw's;
//  - every row written (from the first pose on), scored against what the
//    camera could know: the truth while 3+ LEDs are seen, else the truth of
//    the last frame with 3+ LEDs; p99 and max of the rotation error.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/led_model.hpp"
#include "earshot/tracker/track/dot_tracker.hpp"

namespace earshot::tracker::bench {

enum ListenerRow { kLsRaw, kLsDefault, kLsSmooth, kLsHold, kLsRows };

struct RowScore {
  long frames3 = 0, tracked3 = 0;
  double rot2 = 0.0, trans2 = 0.0, raw_rot2 = 0.0, raw_trans2 = 0.0;  ///< sums over the common 4-LED frames
  long common = 0;
  double jitter2 = 0.0, raw_jitter2 = 0.0;
  long still = 0;
  std::vector<double> known_err_deg;  ///< every row written, against what the camera could know
  long flips = 0;                     ///< tracked frames > 20 deg off the truth
  [[nodiscard]] double tracked_pct() const;
  [[nodiscard]] double rms_rot_ratio() const;
  [[nodiscard]] double rms_trans_ratio() const;
  [[nodiscard]] double jitter_ratio() const;
  [[nodiscard]] double known_quantile(double q) const;
  void merge(const RowScore& o);
};

struct WalkScores {
  std::array<RowScore, kLsRows> rows;
  void merge(const WalkScores& o);
};

/// Runs the rows on one walk (frames with ground truth). `labelled`: the
/// dots come labelled (a tag's corners: slot k is corner k), through
/// LabelledTracker.
[[nodiscard]] WalkScores score_walk(const Camera& cam, const LedModel& model,
                                    const std::vector<DotFrame>& walk, bool labelled = false,
                                    const TrackerConfig& base = {});

/// One markdown row: name, then tracked % (default / smooth / raw), RMS
/// ratios, jitter ratios, known-error p99 / max for default, smooth, hold.
void print_header();
void print_row(const std::string& name, const WalkScores& s);

}  // namespace earshot::tracker::bench
