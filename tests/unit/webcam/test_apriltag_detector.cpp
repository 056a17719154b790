// The AprilTag detector on tags libapriltag itself renders, scaled up by
// whole pixels: the corner order and the pixel-centre convention measured,
// rotations, ids, families, degenerate frames.
#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagStandard41h12.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "earshot/webcam/dot_detector.hpp"
#include "earshot/webcam/tag_pattern.hpp"

namespace earshot::webcam {
namespace {

constexpr std::uint8_t kWhite = 230, kBlack = 20, kPaper = 160;
// Corners of whole-pixel (unblurred) tags: libapriltag's edge refinement
// (quarter-pixel gradient steps, truncated to whole pixels) leaves
// per-corner biases up to about 0.22 px around its mean offset.
constexpr double kSharpTol = 0.25;

/// A frame with tag `id` of tag36h11 drawn from libapriltag's own image,
/// `scale` pixels per cell, its top-left cell's first pixel at (ox, oy).
/// libapriltag's image_u8_destroy is not exported by Debian's library:
/// apriltag_to_image's image is two calloc'd blocks, freed as it would.
void destroy_image(image_u8_t* im) {
  std::free(im->buf);
  std::free(im);
}

struct Frame {
  int w, h;
  std::vector<std::uint8_t> px;
  Frame(int width, int height) : w(width), h(height), px(static_cast<size_t>(width) * height, kPaper) {}
  GrayView view() const { return {px, w, h, w}; }
  std::uint8_t& at(int x, int y) { return px[static_cast<size_t>(y) * w + x]; }
};

void draw_tag(Frame& f, apriltag_family_t* fam, int id, int scale, int ox, int oy) {
  image_u8_t* im = apriltag_to_image(fam, id);
  for (int y = 0; y < im->height * scale; ++y)
    for (int x = 0; x < im->width * scale; ++x)
      f.at(ox + x, oy + y) = im->buf[(y / scale) * im->stride + x / scale] ? kWhite : kBlack;
  destroy_image(im);
}

/// The printed corners (label order) of a tag36h11 drawn as above, in our
/// convention: the border square's outer edges lie half a pixel before its
/// first pixel's centre.
std::array<std::array<double, 2>, 4> printed_corners(int scale, int ox, int oy) {
  const int start = 1, width = 8;  // tag36h11: border square cells 1..8 of 10
  const double a0x = ox + start * scale - 0.5, a0y = oy + start * scale - 0.5;
  const double s = width * scale;
  return {{{a0x, a0y}, {a0x + s, a0y}, {a0x + s, a0y + s}, {a0x, a0y + s}}};
}

struct FamilyDel {
  void operator()(apriltag_family_t* f) const { tag36h11_destroy(f); }
};

TEST(TagPattern, MatchesLibapriltagsOwnRendering) {
  struct F {
    const char* name;
    apriltag_family_t* (*create)();
    void (*destroy)(apriltag_family_t*);
  };
  for (const F& f : {F{"tag36h11", tag36h11_create, tag36h11_destroy}, F{"tag25h9", tag25h9_create, tag25h9_destroy},
                     F{"tag16h5", tag16h5_create, tag16h5_destroy},
                     F{"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
                     F{"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy}}) {
    apriltag_family_t* fam = f.create();
    for (const int id : {0, 1, 7, static_cast<int>(fam->ncodes) - 1}) {
      const TagPattern p = tag_pattern(f.name, id);
      image_u8_t* im = apriltag_to_image(fam, id);
      ASSERT_EQ(p.total_width, im->width) << f.name;
      int white = 0;
      for (int y = 0; y < im->height; ++y)
        for (int x = 0; x < im->width; ++x) {
          EXPECT_EQ(p.white(x, y), im->buf[y * im->stride + x] != 0) << f.name << " id " << id << " cell " << x << "," << y;
          white += p.white(x, y);
        }
      EXPECT_GT(white, 0);
      EXPECT_LT(white, p.total_width * p.total_width);
      destroy_image(im);
    }
    f.destroy(fam);
  }
  EXPECT_THROW((void)tag_pattern("tag99h1", 0), std::invalid_argument);
  EXPECT_THROW((void)tag_pattern("tag36h11", 587), std::invalid_argument);  // ids 0..586
  EXPECT_THROW((void)tag_pattern("tag36h11", -1), std::invalid_argument);
}

// What size_mm measures, per family (the table in README.md, "Tracking
// with a webcam"): the side of the square whose corners libapriltag finds,
// width_at_border cells of the printed total_width. For the classic
// families that square is the outside of the black border (a white ring
// around it); for the reversed-border ones (tagStandard*, tagCircle*,
// tagCustom48h12) it is the inside edge of the black ring (a white ring
// just within it), so the printed tag is total/border times size_mm wide.
TEST(TagPattern, SizeMmIsTheSideOfTheSquareTheDetectorFinds) {
  struct Family {
    const char* name;
    int border, total;
    bool reversed;
  };
  for (const Family& f : {Family{"tag36h11", 8, 10, false}, Family{"tag25h9", 7, 9, false}, Family{"tag16h5", 6, 8, false},
                          Family{"tag36h10", 8, 10, false}, Family{"tagStandard41h12", 5, 9, true},
                          Family{"tagStandard52h13", 6, 10, true}, Family{"tagCircle21h7", 5, 9, true},
                          Family{"tagCircle49h12", 5, 11, true}, Family{"tagCustom48h12", 6, 10, true}}) {
    const TagPattern p = tag_pattern(f.name, 0);
    EXPECT_EQ(p.width_at_border, f.border) << f.name;
    EXPECT_EQ(p.total_width, f.total) << f.name;
    const int a = p.border_start, b = p.border_start + p.width_at_border - 1;  // the square's first and last cells
    // The square's own outermost cells and the cells just outside it.
    int inside_white = 0, outside_white = 0, cells = 0;
    for (int i = a; i <= b; ++i) {
      for (const auto& [x, y] : {std::pair{i, a}, std::pair{i, b}, std::pair{a, i}, std::pair{b, i}}) inside_white += p.white(x, y);
      for (const auto& [x, y] : {std::pair{i, a - 1}, std::pair{i, b + 1}, std::pair{a - 1, i}, std::pair{b + 1, i}})
        outside_white += p.white(x, y);
      cells += 4;
    }
    if (f.reversed) {
      EXPECT_EQ(inside_white, cells) << f.name << ": a white ring just inside the square";
      EXPECT_EQ(outside_white, 0) << f.name << ": the black ring just outside it";
    } else {
      EXPECT_EQ(inside_white, 0) << f.name << ": the black border is the square's outermost cells";
      EXPECT_EQ(outside_white, cells) << f.name << ": white just outside it";
    }
  }
}

TEST(AprilTagDetector, CornerOrderAndPixelCentresMeasured) {
  // Sharp, axis-aligned edges at known half-pixel positions. libapriltag's
  // raw corners are measured here (p[] order, pixel-centre offset); the
  // detector's, after its mapping, must land on the printed corners.
  std::unique_ptr<apriltag_family_t, FamilyDel> fam(tag36h11_create());
  Frame f(320, 240);
  const int scale = 12, ox = 97, oy = 53;
  draw_tag(f, fam.get(), 0, scale, ox, oy);
  const auto truth = printed_corners(scale, ox, oy);

  apriltag_detector_t* td = apriltag_detector_create();
  apriltag_detector_add_family(td, fam.get());
  td->nthreads = 1;
  td->refine_edges = true;  // as the detector runs it
  image_u8_t im{f.w, f.h, f.w, f.px.data()};
  zarray_t* found = apriltag_detector_detect(td, &im);
  ASSERT_EQ(zarray_size(found), 1);
  apriltag_detection_t* d = nullptr;
  zarray_get(found, 0, &d);
  // p[0] bottom-left, p[1] bottom-right, p[2] top-right, p[3] top-left as printed.
  const int printed_of_p[4] = {3, 2, 1, 0};
  double dx = 0.0, dy = 0.0;
  for (int k = 0; k < 4; ++k) {
    dx += (d->p[k][0] - truth[static_cast<size_t>(printed_of_p[k])][0]) / 4.0;
    dy += (d->p[k][1] - truth[static_cast<size_t>(printed_of_p[k])][1]) / 4.0;
  }
  std::printf("libapriltag's corners - ours: (%+.4f, %+.4f) px\n", dx, dy);
  // Not a clean half pixel: the line fit puts edges a whole pixel late and
  // the edge refinement pulls them back by sampling the gradient in quarter-
  // pixel steps (about +0.4 here, +0.38 to +0.49 per corner).
  EXPECT_GT(dx, 0.3);
  EXPECT_LT(dx, 0.55);
  EXPECT_GT(dy, 0.3);
  EXPECT_LT(dy, 0.55);
  apriltag_detections_destroy(found);
  apriltag_detector_destroy(td);

  auto det = make_apriltag_detector();
  const Detection out = det->detect(f.view());
  ASSERT_EQ(out.count, 4);
  EXPECT_TRUE(out.labelled);
  EXPECT_EQ(out.tag_id, 0);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(out.points[k].x, truth[k][0], kSharpTol) << "corner " << k;
    EXPECT_NEAR(out.points[k].y, truth[k][1], kSharpTol) << "corner " << k;
    EXPECT_NEAR(out.points[k].size, 8.0 * scale, 0.1);
  }
}

/// The frame turned by quarter turns clockwise (as the image is seen).
Frame rotate_cw(const Frame& f, int quarters) {
  Frame out = f;
  for (int q = 0; q < quarters; ++q) {
    Frame r(out.h, out.w);
    for (int y = 0; y < out.h; ++y)
      for (int x = 0; x < out.w; ++x) r.at(out.h - 1 - y, x) = out.px[static_cast<size_t>(y) * out.w + x];
    out = r;
  }
  return out;
}

TEST(AprilTagDetector, LabelsStayWithThePrintedCornersUnderRotation) {
  std::unique_ptr<apriltag_family_t, FamilyDel> fam(tag36h11_create());
  Frame f(300, 240);
  const int scale = 10, ox = 61, oy = 47;
  draw_tag(f, fam.get(), 3, scale, ox, oy);
  const auto truth = printed_corners(scale, ox, oy);
  auto det = make_apriltag_detector();
  for (int q = 0; q < 4; ++q) {
    const Frame r = rotate_cw(f, q);
    const Detection d = det->detect(r.view());
    ASSERT_EQ(d.count, 4) << q * 90 << " deg";
    EXPECT_EQ(d.tag_id, 3);
    for (size_t k = 0; k < 4; ++k) {
      // A point (x, y) turned clockwise q times in a frame that turns too:
      // (x, y) -> (H - 1 - y, x), H the height before that turn.
      double x = truth[k][0], y = truth[k][1];
      int hh = f.h, ww = f.w;
      for (int i = 0; i < q; ++i) {
        const double nx = hh - 1 - y, ny = x;
        x = nx;
        y = ny;
        std::swap(hh, ww);
      }
      EXPECT_NEAR(d.points[k].x, x, kSharpTol) << q * 90 << " deg, corner " << k;
      EXPECT_NEAR(d.points[k].y, y, kSharpTol) << q * 90 << " deg, corner " << k;
    }
  }
}

TEST(AprilTagDetector, IdAndFamilyFilters) {
  std::unique_ptr<apriltag_family_t, FamilyDel> fam(tag36h11_create());
  Frame f(400, 200);
  draw_tag(f, fam.get(), 0, 10, 40, 30);
  draw_tag(f, fam.get(), 7, 12, 230, 40);
  AprilTagOptions o;
  o.id = 7;
  Detection d = make_apriltag_detector(o)->detect(f.view());
  ASSERT_EQ(d.count, 4);
  EXPECT_EQ(d.tag_id, 7);
  EXPECT_NEAR(d.points[0].x, 230 + 12 - 0.5, kSharpTol);
  o.id = 0;
  d = make_apriltag_detector(o)->detect(f.view());
  ASSERT_EQ(d.count, 4);
  EXPECT_EQ(d.tag_id, 0);
  EXPECT_NEAR(d.points[0].x, 40 + 10 - 0.5, kSharpTol);
  o.id = -1;
  d = make_apriltag_detector(o)->detect(f.view());
  ASSERT_EQ(d.count, 4);
  EXPECT_TRUE(d.tag_id == 0 || d.tag_id == 7);
  o.id = 5;  // not in the frame
  EXPECT_EQ(make_apriltag_detector(o)->detect(f.view()).count, 0);
  o.id = -1;
  o.family = "tag25h9";  // another family's detector sees no tag
  const auto other = make_apriltag_detector(o);
  EXPECT_EQ(other->detect(f.view()).count, 0);
  EXPECT_EQ(other->describe(), "apriltag tag25h9 any id");
}

TEST(AprilTagDetector, DecimatedStillFindsTheCorners) {
  std::unique_ptr<apriltag_family_t, FamilyDel> fam(tag36h11_create());
  Frame f(640, 480);
  const int scale = 9, ox = 211, oy = 163;
  draw_tag(f, fam.get(), 0, scale, ox, oy);
  AprilTagOptions o;
  o.decimate = 2.0f;
  const Detection d = make_apriltag_detector(o)->detect(f.view());
  ASSERT_EQ(d.count, 4);
  const auto truth = printed_corners(scale, ox, oy);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(d.points[k].x, truth[k][0], 0.3);
    EXPECT_NEAR(d.points[k].y, truth[k][1], 0.3);
  }
}

TEST(AprilTagDetector, BadOptionsAreRefusedByName) {
  AprilTagOptions o;
  o.family = "tag99h1";
  try {
    (void)make_apriltag_detector(o);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tag99h1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("tag36h11"), std::string::npos) << e.what();
  }
  o.family = "tag16h5";
  o.id = 30;  // ids 0..29
  EXPECT_THROW((void)make_apriltag_detector(o), std::invalid_argument);
  o.id = -2;
  EXPECT_THROW((void)make_apriltag_detector(o), std::invalid_argument);
  o.id = 0;
  o.decimate = 0.5f;
  EXPECT_THROW((void)make_apriltag_detector(o), std::invalid_argument);
  o.decimate = 1.0f;
  EXPECT_EQ(make_apriltag_detector(o)->describe(), "apriltag tag16h5 id 0");
}

TEST(AprilTagDetector, DegenerateFramesAndBadViews) {
  auto det = make_apriltag_detector();
  EXPECT_EQ(det->detect(GrayView{}).count, 0);
  for (const std::uint8_t level : {std::uint8_t{0}, std::uint8_t{255}})
    for (const auto& size : std::vector<std::array<int, 2>>{{1, 1}, {2, 3}, {7, 9}, {16, 16}, {640, 480}}) {
      std::vector<std::uint8_t> px(static_cast<size_t>(size[0] * size[1]), level);
      const Detection d = det->detect(GrayView{px, size[0], size[1], size[0]});
      EXPECT_EQ(d.count, 0);
      EXPECT_EQ(d.tag_id, -1);
    }
  std::vector<std::uint8_t> px(100, 0);
  EXPECT_THROW((void)det->detect(GrayView{px, 10, 10, 5}), std::invalid_argument);
  EXPECT_THROW((void)det->detect(GrayView{px, 10, 11, 10}), std::invalid_argument);
  EXPECT_THROW((void)det->detect(GrayView{px, -3, 10, 10}), std::invalid_argument);
}

}  // namespace
}  // namespace earshot::webcam
