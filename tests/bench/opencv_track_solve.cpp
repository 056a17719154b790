// opencv_track_solve: the reference for `earshot track solve`'s whole-process
// cost (issue 18, part 6). It does what a tracker built on OpenCV would do
// with the same file: read the Dots CSV, solve each frame with cv::solvePnP
// (SOLVEPNP_ITERATIVE from the previous pose; SQPNP for the first frame and
// after a failure) and write a Poses CSV.
//
//   opencv_track_solve --dots DOTS.csv --out POSES.csv [--focal F]
//
// It is handed the TRUE labels (the gt_led columns the simulator writes), so
// it does no labelling at all: less work than Earshot's tracker, which labels
// the dots itself. It reads and writes with Earshot's own CSV code, so the
// two programs differ only in what happens between reading and writing.
// Frames with fewer than four labelled dots (ITERATIVE needs four) are
// written as lost, holding the last pose.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/poses_csv.hpp"
#include "opencv_pnp.hpp"

using namespace earshot::tracker;
using earshot::PoseState;

int main(int argc, char** argv) {
  std::string dots_path, out_path;
  double focal = 1280.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "opencv_track_solve: %s needs a value\n", a.c_str());
      return 2;
    }
    if (a == "--dots") dots_path = argv[++i];
    else if (a == "--out") out_path = argv[++i];
    else if (a == "--focal") focal = std::atof(argv[++i]);
    else {
      std::fprintf(stderr, "usage: opencv_track_solve --dots DOTS.csv --out POSES.csv [--focal F]\n");
      return 2;
    }
  }
  if (dots_path.empty() || out_path.empty() || !(focal > 0.0)) {
    std::fprintf(stderr, "usage: opencv_track_solve --dots DOTS.csv --out POSES.csv [--focal F]\n");
    return 2;
  }
  try {
    std::ifstream in(dots_path);
    if (!in) throw earshot::InputError::at(dots_path, 0, "", "cannot open file");
    std::ofstream out(out_path);
    if (!out) throw earshot::InputError::at(out_path, 0, "", "cannot create file");
    DotsCsvReader reader(in, dots_path);
    PosesCsvWriter writer(out);
    earshot::bench::OpenCvPnp cv(Camera::with_focal(focal), LedModel::thesis(), earshot::bench::CvMethod::iterative);
    long frames = 0, four = 0, solved = 0, flips = 0;
    double rot2 = 0.0;
    Pose last;
    while (auto f = reader.next()) {
      ++frames;
      if (!f->truth) throw earshot::InputError::at(dots_path, 0, "gt_led1", "needs the ground-truth labels (a file from track simulate)");
      LabelledDots d;
      for (size_t s = 0; s < kSlots; ++s)
        if (f->truth->slot_led[s] > 0 && f->slots[s]) d.add(f->truth->slot_led[s] - 1, *f->slots[s]);
      PoseState state = PoseState::lost;
      if (d.count == 4) {
        ++four;
        if (const auto p = cv.solve(d.view())) {
          last = *p;
          state = PoseState::tracking;
          ++solved;
          const double e = rotation_angle_between(p->R, f->truth->pose.R) * 180.0 / std::numbers::pi;
          rot2 += e * e;
          flips += e > 20.0 ? 1 : 0;
        }
      }
      writer.write({f->t, state, last});
    }
    out.flush();
    if (!out) throw earshot::InputError::at(out_path, 0, "", "write failed");
    std::printf("frames %ld, 4-dot frames %ld, solved %ld, rotation RMS %.3f deg, flipped (> 20 deg) %ld\n", frames, four,
                solved, solved ? std::sqrt(rot2 / static_cast<double>(solved)) : 0.0, flips);
  } catch (const earshot::InputError& e) {
    std::fprintf(stderr, "opencv_track_solve: %s\n", e.what());
    return 2;
  }
  return 0;
}
