// Camera calibration files (OpenCV's YAML) and undistortion, against
// OpenCV's own cv::undistortPoints and cv::projectPoints.
#include "earshot/webcam/camera_calibration.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <random>

#include "earshot/errors.hpp"
#include "../scratch_path.hpp"

namespace earshot::tracker {
namespace {
using namespace earshot::webcam;  // the webcam module: sources, capture, files, lens

std::string matrix_yaml(const char* name, int rows, int cols, const std::string& data) {
  return std::string(name) + ": !!opencv-matrix\n   rows: " + std::to_string(rows) + "\n   cols: " + std::to_string(cols) +
         "\n   dt: d\n   data: [ " + data + " ]\n";
}

/// What cv::FileStorage writes after a calibration.
std::string opencv_file(const std::string& dist = "-0.28, 0.11, 0.0012, -0.0007, -0.02", int n = 5, bool size = true) {
  std::string s = "%YAML:1.0\n---\n";
  if (size) s += "image_width: 640\nimage_height: 480\n";
  s += matrix_yaml("camera_matrix", 3, 3, "612.5, 0., 318.2, 0., 610.9, 243.7, 0., 0., 1.");
  s += matrix_yaml("distortion_coefficients", 1, n, dist);
  s += "avg_reprojection_error: 0.21\n";
  return s;
}

std::string error_of(const std::string& text) {
  try {
    (void)parse_camera_calibration(text, "cam.yml");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "parsed:\n" << text;
  return {};
}

TEST(CameraCalibration, ReadsOpenCvsFile) {
  const CameraCalibration c = parse_camera_calibration(opencv_file(), "cam.yml");
  EXPECT_DOUBLE_EQ(c.fx, 612.5);
  EXPECT_DOUBLE_EQ(c.fy, 610.9);
  EXPECT_DOUBLE_EQ(c.cx, 318.2);
  EXPECT_DOUBLE_EQ(c.cy, 243.7);
  EXPECT_DOUBLE_EQ(c.distortion[0], -0.28);
  EXPECT_DOUBLE_EQ(c.distortion[3], -0.0007);
  EXPECT_DOUBLE_EQ(c.distortion[4], -0.02);
  EXPECT_DOUBLE_EQ(c.distortion[5], 0.0);
  EXPECT_EQ(c.image_width, 640);
  EXPECT_EQ(c.image_height, 480);
  EXPECT_TRUE(c.distorted());
  // Four coefficients, a column of them, 14 with no tilt, and no size.
  EXPECT_DOUBLE_EQ(parse_camera_calibration(opencv_file("0.1, 0.2, 0.3, 0.4", 4), "x").distortion[3], 0.4);
  const std::string fourteen = "1,2,3,4,5,6,7,8,9,10,11,12,0,0";
  EXPECT_DOUBLE_EQ(parse_camera_calibration(opencv_file(fourteen, 14), "x").distortion[11], 12.0);
  const CameraCalibration nosize = parse_camera_calibration(opencv_file("0,0,0,0,0", 5, false), "x");
  EXPECT_EQ(nosize.image_width, 0);
  EXPECT_FALSE(nosize.distorted());
}

TEST(CameraCalibration, ReadsAFileAndNamesItInErrors) {
  const auto path = earshot::test::scratch_path("calib.yml");
  {
    std::ofstream(path) << opencv_file();
  }
  EXPECT_DOUBLE_EQ(load_camera_calibration(path).fx, 612.5);
  {
    std::ofstream(path) << "%YAML:1.0\ncamera_matrix: 3\n";
  }
  try {
    (void)load_camera_calibration(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ":2: field 'camera_matrix': not an opencv-matrix map: '3'");
  }
  std::filesystem::remove(path);
  EXPECT_THROW((void)load_camera_calibration("/nonexistent/cam.yml"), InputError);
}

TEST(CameraCalibration, BadFilesNameTheField) {
  EXPECT_EQ(error_of("%YAML:1.0\nimage_width: 640\n"), "cam.yml: field 'camera_matrix': missing");
  EXPECT_EQ(error_of("- 1\n- 2\n"), "cam.yml: not a calibration file (expected a YAML map with camera_matrix)");
  const std::pair<std::string, const char*> bad[] = {
      {opencv_file("1,2,3", 3), "field 'distortion_coefficients': 3 coefficients (OpenCV writes 4, 5, 8, 12 or 14)"},
      {opencv_file("1,2,3,4,5,6,7,8,9,10,11,12,0.1,0", 14), "tilted-sensor terms"},
      {opencv_file("1,2,x,4,5", 5), "field 'distortion_coefficients.data[2]': not a finite number: 'x'"},
      {opencv_file("1,2,.nan,4,5", 5), "field 'distortion_coefficients.data[2]': not a finite number"},
      {"%YAML:1.0\n" + matrix_yaml("camera_matrix", 3, 3, "1,0,1,0,1,1,0,0"), "field 'camera_matrix.data': 8 values for 3x3"},
      {"%YAML:1.0\n" + matrix_yaml("camera_matrix", 2, 2, "1,0,0,1"), "field 'camera_matrix': not 3x3"},
      {"%YAML:1.0\n" + matrix_yaml("camera_matrix", 3, 3, "-5,0,1,0,5,1,0,0,1"), "positive focal lengths"},
      {"%YAML:1.0\n" + matrix_yaml("camera_matrix", 3, 3, "5,0,1,0,5,1,0,1,1"), "not a camera matrix"},
      {"%YAML:1.0\n" + matrix_yaml("camera_matrix", 3, 3, "5,1,1,0,5,1,0,0,1"), "skewed pixels"},
      {"%YAML:1.0\n" + matrix_yaml("camera_matrix", 3, 3, "612.5,0,999999999999999318.2,0,610.9,243.7,0,0,1"),
       "principal point beyond 1e5 px"},
      {"%YAML:1.0\n" + matrix_yaml("camera_matrix", 3, 3, "1e9,0,320,0,1e9,240,0,0,1"), "focal length beyond 1e6 px"},
      {"%YAML:1.0\ncamera_matrix: {rows: 3, cols: 3}\n", "field 'camera_matrix.data': missing"},
      {"%YAML:1.0\ncamera_matrix: {rows: 3, data: []}\n", "field 'camera_matrix.cols': missing"},
      {"%YAML:1.0\ncamera_matrix: {rows: 3.5, cols: 3, data: []}\n", "field 'camera_matrix.rows': not a count 1-64"},
      {"%YAML:1.0\ncamera_matrix: {rows: 3, cols: 3, dt: u, data: []}\n", "field 'camera_matrix.dt'"},
      {"%YAML:1.0\ncamera_matrix: {rows: 3, cols: 3, data: 7}\n", "field 'camera_matrix.data': not a list: '7'"},
      {"%YAML:1.0\nimage_width: 640\n" + matrix_yaml("camera_matrix", 3, 3, "5,0,1,0,5,1,0,0,1"),
       "field 'image_height': missing (give both or neither)"},
      {"%YAML:1.0\nimage_width: 6\nimage_height: 480\n" + matrix_yaml("camera_matrix", 3, 3, "5,0,1,0,5,1,0,0,1"),
       "field 'image_width': not a width 16-16384"},
      {"%YAML:1.0\ncamera_matrix: [1, 2\n", "not valid YAML"},
      {std::string(100, '[') + "1" + std::string(100, ']'), "brackets nested deeper than 64"},
      {std::string(2000, '-') + " x\n", "indented or nested deeper"},
  };
  for (const auto& [text, why] : bad) {
    const std::string e = error_of(text);
    EXPECT_EQ(e.rfind("cam.yml", 0), 0u) << e;
    EXPECT_NE(e.find(why), std::string::npos) << e;
  }
}

TEST(CameraCalibration, ScalesToAnotherCaptureSizeOfTheSameAspect) {
  const CameraCalibration c = parse_camera_calibration(opencv_file(), "cam.yml");
  const CameraCalibration s = c.scaled_to(1280, 960, "cam.yml");
  EXPECT_DOUBLE_EQ(s.fx, 2 * 612.5);
  EXPECT_DOUBLE_EQ(s.fy, 2 * 610.9);
  EXPECT_DOUBLE_EQ(s.cx, 2 * 318.2 + 0.5);  // pixel centres: (cx + 0.5) * 2 - 0.5
  EXPECT_DOUBLE_EQ(s.cy, 2 * 243.7 + 0.5);
  EXPECT_EQ(s.distortion, c.distortion);  // normalised coordinates do not change
  // A point and its image both scaled: undistortion commutes with the scaling.
  const Vec2 p(500.0, 100.0);
  const Vec2 u = c.undistort(p).value(), us = s.undistort(Vec2((p.x() + 0.5) * 2 - 0.5, (p.y() + 0.5) * 2 - 0.5)).value();
  EXPECT_NEAR(us.x(), (u.x() + 0.5) * 2 - 0.5, 1e-9);
  EXPECT_NEAR(us.y(), (u.y() + 0.5) * 2 - 0.5, 1e-9);
  try {
    (void)c.scaled_to(1280, 720, "cam.yml");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "cam.yml: field 'image_width': calibrated at 640x480 but capturing 1280x720 (another aspect ratio: the "
                 "camera crops; calibrate at this resolution)");
  }
  const Camera cam = s.camera(1280, 960);
  EXPECT_EQ(cam.width, 1280);
  EXPECT_DOUBLE_EQ(cam.fx, s.fx);
  EXPECT_DOUBLE_EQ(cam.cy, s.cy);
}

/// The same points through OpenCV and through us, for each model size.
TEST(CameraCalibration, UndistortionAgreesWithOpenCv) {
  const std::vector<std::vector<double>> models = {
      {-0.28, 0.11, 0.0012, -0.0007},
      {-0.28, 0.11, 0.0012, -0.0007, -0.02},
      {0.1, -0.05, 0.001, 0.002, 0.01, 0.05, -0.01, 0.002},
      {0.1, -0.05, 0.001, 0.002, 0.01, 0.05, -0.01, 0.002, 0.001, -0.0005, 0.0008, 0.0003},
      {0.1, -0.05, 0.001, 0.002, 0.01, 0.05, -0.01, 0.002, 0.001, -0.0005, 0.0008, 0.0003, 0.0, 0.0},
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(0.0, 639.0), uy(0.0, 479.0);
  std::vector<cv::Point2d> pts;
  for (int i = 0; i < 200; ++i) pts.emplace_back(ux(rng), uy(rng));
  const cv::Matx33d K(612.5, 0, 318.2, 0, 610.9, 243.7, 0, 0, 1);
  for (const auto& d : models) {
    std::string text;
    for (const double v : d) text += (text.empty() ? "" : ", ") + std::to_string(v);
    const CameraCalibration c = parse_camera_calibration(opencv_file(text, static_cast<int>(d.size())), "m");
    const cv::Mat D(d, true);
    // OpenCV's default (5 iterations) and a converged run (many iterations).
    std::vector<cv::Point2d> cv5, cvmany;
    cv::undistortPoints(pts, cv5, K, D, cv::noArray(), K);
    cv::undistortPoints(pts, cvmany, K, D, cv::noArray(), K,
                        cv::TermCriteria(cv::TermCriteria::COUNT, 100, 0.0));
    double worst5 = 0.0, worst = 0.0, worst_round_trip = 0.0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec2 p(pts[i].x, pts[i].y);
      const Vec2 a5 = c.undistort_fixed_point(p, 5), a = c.undistort_fixed_point(p, 100);
      worst5 = std::max(worst5, (a5 - Vec2(cv5[i].x, cv5[i].y)).norm());
      worst = std::max(worst, (a - Vec2(cvmany[i].x, cvmany[i].y)).norm());
      worst_round_trip = std::max(worst_round_trip, (c.distort(a) - p).norm());
    }
    EXPECT_LT(worst5, 1e-9) << d.size() << " coefficients";
    EXPECT_LT(worst, 1e-9) << d.size() << " coefficients";
    std::printf("%zu coefficients: |ours - cv::undistortPoints| <= %.2g px (5 iterations), %.2g px (100); "
                "distort(undistort(p)) - p <= %.2g px\n",
                d.size(), worst5, worst, worst_round_trip);
  }
}

/// Our forward model against cv::projectPoints: the model undistortion inverts.
TEST(CameraCalibration, DistortionAgreesWithOpenCvsProjection) {
  const std::vector<double> d = {0.1, -0.05, 0.001, 0.002, 0.01, 0.05, -0.01, 0.002, 0.001, -0.0005, 0.0008, 0.0003};
  std::string text;
  for (const double v : d) text += (text.empty() ? "" : ", ") + std::to_string(v);
  const CameraCalibration c = parse_camera_calibration(opencv_file(text, 12), "m");
  const cv::Matx33d K(612.5, 0, 318.2, 0, 610.9, 243.7, 0, 0, 1);
  std::vector<cv::Point3d> obj;
  for (double x = -0.4; x <= 0.4; x += 0.1)
    for (double y = -0.3; y <= 0.3; y += 0.1) obj.emplace_back(x, y, 1.0);
  std::vector<cv::Point2d> img;
  cv::projectPoints(obj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, cv::Mat(d, true), img);
  for (std::size_t i = 0; i < obj.size(); ++i) {
    const Vec2 ideal(612.5 * obj[i].x + 318.2, 610.9 * obj[i].y + 243.7);
    const Vec2 ours = c.distort(ideal);
    EXPECT_NEAR(ours.x(), img[i].x, 1e-9);
    EXPECT_NEAR(ours.y(), img[i].y, 1e-9);
  }
}

TEST(CameraCalibration, UndistortionStaysFiniteAndIdentityWithoutDistortion) {
  CameraCalibration c;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  EXPECT_EQ(c.undistort(Vec2(10, 20)), Vec2(10, 20));
  EXPECT_FALSE(c.undistort(Vec2(std::nan(""), 1.0)));
  c.distortion[0] = -2.0;  // folds over not far from the centre
  for (const Vec2& p : {Vec2(1e6, 1e6), Vec2(-1e6, 5), Vec2(std::nan(""), 1.0), Vec2(320, 240)}) {
    EXPECT_TRUE(c.undistort_fixed_point(p, 20).allFinite() || !p.allFinite());
    if (const auto u = c.undistort(p)) {
      EXPECT_LT((c.distort(*u) - p).norm(), kUndistortTolerancePx);
    }
  }
  EXPECT_EQ(c.undistort(Vec2(320, 240)), Vec2(320, 240));
  // Beyond the fold (r_d = r (1 - 2 r^2) peaks at 0.27): no ideal pixel.
  EXPECT_FALSE(c.undistort(Vec2(320 + 500 * 0.35, 240)));
}

// Wide webcam lenses (k1 = -0.44: the barrel of the photos in issue 31,
// with a k2 that keeps the lens unfolded over its image; the second close
// to folding in its corners): OpenCV's cv::undistortPoints run to
// convergence and ours agree within 0.01 px over the whole 640x480 image,
// corners included; our point distorts back to the measured one within
// 1e-6 px. The old fixed 20 iterations are measured too: pixels off in the
// corners of the second lens.
TEST(CameraCalibration, WideLensUndistortionConvergesAndAgreesWithOpenCvEverywhere) {
  struct Lens {
    double f, k1, k2, p1, p2;
  };
  for (const Lens& lens : {Lens{600, -0.44, 0.2, 0.001, -0.0008}, Lens{620, -0.44, 0.085, 0.0, 0.0}}) {
    const std::vector<double> d = {lens.k1, lens.k2, lens.p1, lens.p2, 0.0};
    std::string text;
    for (const double v : d) text += (text.empty() ? "" : ", ") + std::to_string(v);
    const std::string f = std::to_string(lens.f);
    const std::string yaml = "%YAML:1.0\n---\n" +
                             matrix_yaml("camera_matrix", 3, 3, f + ", 0., 319.5, 0., " + f + ", 239.5, 0., 0., 1.") +
                             matrix_yaml("distortion_coefficients", 1, 5, text);
    const CameraCalibration c = parse_camera_calibration(yaml, "wide.yml");
    const cv::Matx33d K(lens.f, 0, 319.5, 0, lens.f, 239.5, 0, 0, 1);
    std::vector<cv::Point2d> pts;
    for (int y = 0; y < 480; y += 8)
      for (int x = 0; x < 640; x += 8) pts.emplace_back(x, y);
    for (const auto& p : {cv::Point2d(0, 0), cv::Point2d(639, 0), cv::Point2d(0, 479), cv::Point2d(639, 479)})
      pts.push_back(p);
    std::vector<cv::Point2d> cv_converged;
    cv::undistortPoints(pts, cv_converged, K, cv::Mat(d, true), cv::noArray(), K,
                        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 3000, 1e-14));
    double worst = 0.0, worst_back = 0.0, worst_20 = 0.0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec2 p(pts[i].x, pts[i].y);
      const auto u = c.undistort(p);
      ASSERT_TRUE(u) << "no ideal pixel for " << p.transpose();
      worst = std::max(worst, (*u - Vec2(cv_converged[i].x, cv_converged[i].y)).norm());
      worst_back = std::max(worst_back, (c.distort(*u) - p).norm());
      worst_20 = std::max(worst_20, (c.undistort_fixed_point(p, 20) - *u).norm());
    }
    std::printf("k1 = %g, k2 = %g, f = %g px, 640x480: |ours - converged cv::undistortPoints| <= %.2g px; "
                "distort(undistort(p)) - p <= %.2g px; 20 fixed-point steps were %.2g px off\n",
                lens.k1, lens.k2, lens.f, worst, worst_back, worst_20);
    EXPECT_LT(worst, 0.01);
    EXPECT_LE(worst_back, kUndistortTolerancePx);
    // The far corner moves ~100 px or more outwards: beyond the raw image.
    const Vec2 corner = c.undistort(Vec2(0, 0)).value();
    EXPECT_LT(corner.x(), -50.0);
    EXPECT_LT(corner.y(), -30.0);
  }
}

TEST(CameraCalibration, FocalFromFieldOfView) {
  EXPECT_NEAR(focal_from_fov(640, 60.0), 320.0 / std::tan(M_PI / 6), 1e-9);
  EXPECT_NEAR(focal_from_fov(1280, 90.0), 640.0, 1e-9);
}

}  // namespace
}  // namespace earshot::tracker
