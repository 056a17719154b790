// The whole chain without a camera: a synthetic webcam video (the LED beacon
// or a printed tag on a seated head walk, rendered by webcam/sim) written as
// Y4M, played through make_frame_source(parse_source_spec("webcam:FILE,..."))
// and the live pipeline. Poses against the ground truth within the limit the
// measured dot noise allows (the pose covariance of each frame and of the
// recenter frame), the states searching -> tracking -> lost -> tracking
// when the beacon disappears for a while and comes back, recentering, and
// the same file through the LiveTracker thread.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "earshot/pose_slot.hpp"
#include "earshot/tracker/live/live_tracker.hpp"
#include "earshot/tracker/live/source_spec.hpp"
#include "earshot/webcam/y4m_reader.hpp"
#include "earshot/webcam/y4m_writer.hpp"
#include "earshot/webcam/video_sim.hpp"

namespace earshot::tracker {
namespace {
using namespace earshot::webcam;  // the webcam module: sources, capture, files, lens

constexpr int kFrames = 120;
constexpr int kBlankFrom = 60, kBlankTo = 80;  // the beacon is covered for [60, 80)

struct Truth {
  Pose pose;
  std::array<std::optional<Vec2>, 4> points;
};

/// Renders the video; frames in [kBlankFrom, kBlankTo) show the scene
/// without the beacon (a frame of its own background level).
std::vector<Truth> render(const std::filesystem::path& path, webcam::BeaconKind beacon) {
  webcam::VideoSimConfig cfg;
  cfg.beacon = beacon;
  cfg.seed = 7;
  // Fewer sub-renders than the defaults keep each test under 10 s; the
  // detectors' own accuracy at full fidelity is webcam_tests' business.
  cfg.motion_samples = 3;
  cfg.supersample = 2;
  webcam::VideoSimulator sim(cfg);
  std::ofstream out(path, std::ios::binary);
  Y4mWriter writer(out, cfg.width, cfg.height, 30);
  std::vector<Truth> truth;
  webcam::VideoFrame f;
  std::vector<std::uint8_t> blank;
  for (int i = 0; i < kFrames; ++i) {
    sim.next(f);
    if (i == 0) {
      blank = f.pixels;  // a flat frame at the median level: nothing to find
      std::vector<std::uint8_t> sorted = f.pixels;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
      std::fill(blank.begin(), blank.end(), sorted[sorted.size() / 2]);
    }
    const bool covered = i >= kBlankFrom && i < kBlankTo;
    writer.write(covered ? blank : f.pixels);
    truth.push_back({f.truth, covered ? std::array<std::optional<Vec2>, 4>{} : f.points});
  }
  return truth;
}

double angle_of(const Mat3& R) { return rotation_angle_between(R, Mat3::Identity()); }

struct Result {
  std::vector<PoseState> states;
  std::vector<std::optional<HeadPose>> poses;
  double dot_rms_px = 0.0;  ///< detected dots against the projected truth
  int dots = 0;
  double source_ms = 0.0, pipeline_ms = 0.0;  ///< per frame: read + detect + undistort + thumbnail; solve
};

/// Plays `spec` through a pipeline (filter none: the raw solve, so the
/// error is the measurement's own); recenters at `recenter_at` (-1: never).
Result play(const std::string& spec, const std::vector<Truth>& truth, int recenter_at) {
  SourceOptions o;
  o.pacing = Pacing::as_fast_as_possible;
  auto src = make_frame_source(parse_source_spec(spec, "test"), o);
  LiveConfig cfg;
  cfg.tracker.filter = FilterKind::none;
  LivePipeline pipe(with_source_model(cfg, *src));
  Result r;
  double sum_sq = 0.0;
  int frame = 0;
  using Clock = std::chrono::steady_clock;
  for (;;) {
    const auto t0 = Clock::now();
    const SourceEvent e = src->next(std::chrono::milliseconds(100));
    const auto t1 = Clock::now();
    if (const auto* n = std::get_if<SourceNote>(&e)) {
      if (n->kind == SourceNote::Kind::ended) break;
      EXPECT_NE(n->kind, SourceNote::Kind::timeout);
      continue;
    }
    const auto& f = std::get<CameraFrame>(e);
    for (const auto& d : f.dots.slots) {
      if (!d) continue;
      double best = 1e300;  // nearest projected point (LED dots come unlabelled)
      for (const auto& p : truth[static_cast<std::size_t>(frame)].points)
        if (p) best = std::min(best, (*p - *d).squaredNorm());
      if (best < 25.0) {
        sum_sq += best;
        ++r.dots;
      }
    }
    if (frame == recenter_at) pipe.request_recenter();
    r.poses.push_back(pipe.process(e, f.dots.t));
    r.states.push_back(pipe.state());
    r.source_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
    r.pipeline_ms += std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
    ++frame;
  }
  EXPECT_EQ(frame, kFrames);
  r.dot_rms_px = r.dots ? std::sqrt(sum_sq / r.dots) : 0.0;
  r.source_ms /= frame;
  r.pipeline_ms /= frame;
  return r;
}

/// One axis-free measure of how well frame i's pose is determined: the
/// rotation (rad) and translation (mm) standard deviations from the pose
/// covariance at the truth, with the measured dot noise.
std::pair<double, double> sigma(const Truth& t, const Camera& cam, const LedModel& model, double px) {
  LabelledDots dots;
  for (int k = 0; k < 4; ++k)
    if (t.points[static_cast<std::size_t>(k)]) dots.add(k, *t.points[static_cast<std::size_t>(k)]);
  const Mat6 c = pose_covariance(t.pose, dots.view(), cam, model, px * px);
  return {std::sqrt(c.topLeftCorner<3, 3>().trace()), std::sqrt(c.bottomRightCorner<3, 3>().trace())};
}

void check_chain(webcam::BeaconKind beacon, const std::string& options) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("earshot_e2e_" + std::to_string(::getpid()) + (beacon == webcam::BeaconKind::leds ? "_leds" : "_tag") + ".y4m");
  const auto truth = render(path, beacon);
  webcam::VideoSimConfig vc;
  vc.beacon = beacon;
  const Camera cam = webcam::video_camera(vc);
  const LedModel model = webcam::video_model(vc);
  const std::string spec = "webcam:" + path.string() + options;
  constexpr int kRecenter = 100;
  const Result r = play(spec, truth, kRecenter);
  ASSERT_EQ(r.states.size(), static_cast<std::size_t>(kFrames));

  // States: tracking from the first frames, lost while covered (after the
  // short predicted bridge), tracking again once the beacon is back.
  int first_tracking = -1;
  for (int i = 0; i < kFrames && first_tracking < 0; ++i)
    if (r.states[static_cast<std::size_t>(i)] == PoseState::tracking) first_tracking = i;
  ASSERT_GE(first_tracking, 0);
  EXPECT_LE(first_tracking, 2);
  for (int i = 0; i < first_tracking; ++i) EXPECT_EQ(r.states[static_cast<std::size_t>(i)], PoseState::searching);
  int tracked_before = 0, tracked_after = 0;
  for (int i = first_tracking; i < kBlankFrom; ++i) tracked_before += r.states[static_cast<std::size_t>(i)] == PoseState::tracking;
  for (int i = kBlankFrom + 5; i < kBlankTo; ++i) EXPECT_EQ(r.states[static_cast<std::size_t>(i)], PoseState::lost) << i;
  for (int i = kBlankTo + 2; i < kFrames; ++i) tracked_after += r.states[static_cast<std::size_t>(i)] == PoseState::tracking;
  EXPECT_EQ(tracked_before, kBlankFrom - first_tracking);
  EXPECT_EQ(tracked_after, kFrames - kBlankTo - 2);

  // Poses: relative to the frame the reference was taken at (the first
  // tracked one, then kRecenter), in the audio frame.
  const Mat3 A = camera_to_audio();
  double worst_ratio_rot = 0.0, worst_ratio_pos = 0.0, sum_rot = 0.0, sum_pos = 0.0, sum_ml_rot = 0.0;
  int n = 0;
  int ref = first_tracking;
  for (int i = first_tracking; i < kFrames; ++i) {
    if (i == kRecenter) ref = kRecenter;
    const auto& p = r.poses[static_cast<std::size_t>(i)];
    if (!p || r.states[static_cast<std::size_t>(i)] != PoseState::tracking) continue;
    if (i >= kBlankTo && i < kBlankTo + 6) continue;  // resuming: blended in over resume_s (0.15 s)
    const Truth& tr = truth[static_cast<std::size_t>(i)];
    const Truth& tref = truth[static_cast<std::size_t>(ref)];
    const Mat3 want_R = A * (tr.pose.R * tref.pose.R.transpose()) * A.transpose();
    const Vec3 want_p = A * (tr.pose.t - tref.pose.t) * 1e-3;
    const Mat3 got_R = to_eigen(p->orientation).normalized().toRotationMatrix();
    const Vec3 got_p = to_eigen(p->position);
    const double e_rot = rotation_angle_between(got_R, want_R);
    const double e_pos = (got_p - want_p).norm() * 1e3;
    const auto [si, ti] = sigma(tr, cam, model, r.dot_rms_px);
    const auto [sr, trf] = sigma(tref, cam, model, r.dot_rms_px);
    const double s_rot = std::hypot(si, sr), s_pos = std::hypot(ti, trf);
    if (i == ref) {
      EXPECT_LT(angle_of(got_R), 1e-9) << "frame " << i << ": the reference frame is neutral";
      EXPECT_LT(got_p.norm(), 1e-12);
      continue;
    }
    // Six standard deviations of the ML limit at the measured dot noise.
    EXPECT_LT(e_rot, 6.0 * s_rot) << "frame " << i;
    EXPECT_LT(e_pos, 6.0 * s_pos) << "frame " << i;
    worst_ratio_rot = std::max(worst_ratio_rot, e_rot / s_rot);
    worst_ratio_pos = std::max(worst_ratio_pos, e_pos / s_pos);
    sum_rot += e_rot * e_rot;
    sum_pos += e_pos * e_pos;
    sum_ml_rot += s_rot * s_rot;
    ++n;
  }
  ASSERT_GT(n, 60);
  std::printf("%s: dots %.3f px RMS against the truth (%d); relative pose RMS %.3f deg / %.2f mm over %d frames "
              "(ML limit %.3f deg); worst %.1f / %.1f sigma; per frame %.2f ms source (read, detect, thumbnail), "
              "%.3f ms pipeline\n",
              spec.c_str(), r.dot_rms_px, r.dots, std::sqrt(sum_rot / n) * 180.0 / M_PI, std::sqrt(sum_pos / n), n,
              std::sqrt(sum_ml_rot / n) * 180.0 / M_PI, worst_ratio_rot, worst_ratio_pos, r.source_ms, r.pipeline_ms);
  std::filesystem::remove(path);
}

TEST(WebcamEndToEnd, LedsFromAVideoThroughTheLivePipeline) {
  check_chain(webcam::BeaconKind::leds, "");  // the focal guess (60 deg) is the video's camera
}

TEST(WebcamEndToEnd, AprilTagFromAVideoThroughTheLivePipeline) {
  check_chain(webcam::BeaconKind::apriltag, ",beacon=apriltag,size_mm=80,focal=554.2562584220407");
}

TEST(WebcamEndToEnd, LiveTrackerThreadPlaysTheVideoAndRecenters) {
  const auto path = std::filesystem::temp_directory_path() / ("earshot_e2e_thread_" + std::to_string(::getpid()) + ".y4m");
  (void)render(path, webcam::BeaconKind::leds);
  SourceOptions o;
  o.pacing = Pacing::as_fast_as_possible;
  PoseSlot slot;
  std::atomic<int> tracking{0}, lost{0};
  std::atomic<bool> recentered{false};
  LiveTracker tracker(make_frame_source(parse_source_spec("webcam:" + path.string()), o),
                      slot, LiveConfig{}, [&](const HeadPose& p) {
                        if (p.state == PoseState::tracking) ++tracking;
                        if (p.state == PoseState::lost) ++lost;
                      });
  while (tracker.running()) {
    if (!recentered && tracking.load() > 10) {
      tracker.recenter();
      recentered = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const auto st = tracker.status();
  EXPECT_TRUE(st.error.empty()) << st.error;
  EXPECT_TRUE(st.ended);
  EXPECT_EQ(st.frames, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(st.link, LiveTracker::Link::connected);
  EXPECT_NE(st.source.find("(640x480 @ 30 fps, leds"), std::string::npos) << st.source;
  EXPECT_GT(tracking.load(), 80);
  EXPECT_GT(lost.load(), 5);
  Thumbnail th;
  ASSERT_TRUE(tracker.thumbnail(th));
  EXPECT_EQ(th.frame, static_cast<std::uint64_t>(kFrames));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace earshot::tracker
