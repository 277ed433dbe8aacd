// test_quality_area.cpp — the exact area ground truth (quality/exact_area.hpp, exact_box_image)
// and the 64×64 supersampled one, against checks derived independently: whole and half pixels,
// partitions of pixels that must sum to exactly 1, and brute-force 1024×1024 point sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "quality/exact_area.hpp"
#include "quality/quality.hpp"

namespace mosaic::quality {
namespace {

/// 1/256 px: the snapped grid.
constexpr std::int64_t kOne = 256;

/// n / d in canonical form (GMP compares canonical rationals only).
mpq_class q(long n, long d) {
  mpq_class r(n, d);
  r.canonicalize();
  return r;
}

SnappedTriangle tri(std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1,
                    std::int64_t x2, std::int64_t y2) {
  SnappedTriangle t;
  t.x = {x0, x1, x2};
  t.y = {y0, y1, y2};
  return t;
}

TEST(QualityArea, TriangleCoveringThePixelIsExactlyOne) {
  const SnappedTriangle t =
      tri(-10 * kOne, -10 * kOne, 30 * kOne, -10 * kOne, -10 * kOne, 30 * kOne);
  EXPECT_EQ(exact_area(t, 3, 4), mpq_class(1));
  EXPECT_EQ(classify(t, 3, 4), PixelClass::kInside);
  EXPECT_EQ(coverage(t, 3, 4), 1.0);
  // Winding does not matter.
  const SnappedTriangle r =
      tri(-10 * kOne, -10 * kOne, -10 * kOne, 30 * kOne, 30 * kOne, -10 * kOne);
  EXPECT_EQ(exact_area(r, 3, 4), mpq_class(1));
}

TEST(QualityArea, DiagonalSplitIsExactlyHalf) {
  // Hypotenuse x + y = 1 through pixel (0, 0)'s corners (1, 0) and (0, 1).
  const SnappedTriangle t = tri(-5 * kOne, 6 * kOne, 6 * kOne, -5 * kOne, -5 * kOne, -5 * kOne);
  EXPECT_EQ(exact_area(t, 0, 0), q(1, 2));
  EXPECT_EQ(classify(t, 0, 0), PixelClass::kPartial);
  // Pixel (1, 1) lies beyond the hypotenuse (x + y >= 2 > 1).
  EXPECT_EQ(exact_area(t, 1, 1), mpq_class(0));
  EXPECT_EQ(classify(t, 1, 1), PixelClass::kOutside);
}

TEST(QualityArea, VerticalSplitAtEverySubpixelStep) {
  // An edge at x = 100 + k/256 leaves k/256 of pixel (100, 7) to its left.
  for (std::int64_t k = 0; k <= kOne; ++k) {
    const std::int64_t ex = 100 * kOne + k;
    const SnappedTriangle t = tri(ex, -50 * kOne, ex, 60 * kOne, -200 * kOne, 5 * kOne);
    EXPECT_EQ(exact_area(t, 100, 7), q(k, kOne)) << k;
  }
}

TEST(QualityArea, SmallTriangleInsideOnePixel) {
  // Legs of 10/256 and 20/256 px: area 100 / 65536 px².
  const SnappedTriangle t =
      tri(5 * kOne + 30, 9 * kOne + 40, 5 * kOne + 40, 9 * kOne + 40, 5 * kOne + 30, 9 * kOne + 60);
  EXPECT_EQ(exact_area(t, 5, 9), q(100, 65536));
  EXPECT_EQ(exact_area(t, 4, 9), mpq_class(0));
}

/// A fan around a random interior point P of a 2×2-pixel block, through random points on the
/// block's boundary and its four corners: the triangles partition the block, so in each of
/// the four pixels their exact areas must sum to exactly 1, whatever the slopes.
TEST(QualityArea, PixelPartitionsSumToExactlyOne) {
  std::mt19937_64 rng(7);
  const std::int64_t side = 2 * kOne;
  std::uniform_int_distribution<std::int64_t> inner(1, side - 1), along(0, 4 * side - 1);
  auto boundary = [&](std::int64_t s) -> std::pair<std::int64_t, std::int64_t> {
    // Walk the boundary clockwise (y down) from the top-left corner: top, right, bottom, left.
    if (s < side) return {s, 0};
    if (s < 2 * side) return {side, s - side};
    if (s < 3 * side) return {3 * side - s, side};
    return {0, 4 * side - s};
  };
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<std::int64_t> stops = {0, side, 2 * side, 3 * side};
    for (int k = 0; k < 5; ++k) stops.push_back(along(rng));
    std::sort(stops.begin(), stops.end());
    stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
    const std::int64_t ox = 40 * kOne, oy = 30 * kOne;  // the block is pixels 40..41 × 30..31
    const std::int64_t px = ox + inner(rng), py = oy + inner(rng);
    std::vector<SnappedTriangle> fan;
    for (std::size_t i = 0; i < stops.size(); ++i) {
      const auto [ax, ay] = boundary(stops[i]);
      const auto [bx, by] = boundary(stops[(i + 1) % stops.size()]);
      fan.push_back(tri(px, py, ox + ax, oy + ay, ox + bx, oy + by));
    }
    for (int y = 30; y <= 31; ++y) {
      for (int x = 40; x <= 41; ++x) {
        mpq_class sum;
        double sum_d = 0;
        for (const SnappedTriangle& t : fan) {
          sum += exact_area(t, x, y);
          sum_d += coverage(t, x, y);
        }
        EXPECT_EQ(sum, mpq_class(1)) << "trial " << trial << " pixel " << x << "," << y;
        // Each double is the exact value rounded once: the sum is 1 to a few ulps.
        EXPECT_NEAR(sum_d, 1.0, 1e-14);
      }
    }
  }
}

/// Brute force: 1024 × 1024 points per pixel at the centres of a regular grid, tested with
/// exact integer edge functions in 1/2048 px units. Independent of the clipping code.
double sampled_area(const SnappedTriangle& t, int px, int py) {
  constexpr int kN = 1024;
  // Vertices in 1/(8·256) px; sample i of the row sits at (2i + 1) / 2048 px.
  std::array<std::int64_t, 3> X, Y;
  for (int k = 0; k < 3; ++k) {
    X[k] = t.x[k] * 8 - std::int64_t{px} * 2048;
    Y[k] = t.y[k] * 8 - std::int64_t{py} * 2048;
  }
  const std::int64_t area2 = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
  if (area2 == 0) return 0.0;
  const std::int64_t sign = area2 > 0 ? 1 : -1;
  std::int64_t inside = 0;
  for (int j = 0; j < kN; ++j) {
    const std::int64_t sy = 2 * j + 1;
    for (int i = 0; i < kN; ++i) {
      const std::int64_t sx = 2 * i + 1;
      bool in = true;
      for (int e = 0; e < 3 && in; ++e) {
        const int f = (e + 1) % 3;
        in = sign * ((X[f] - X[e]) * (sy - Y[e]) - (Y[f] - Y[e]) * (sx - X[e])) >= 0;
      }
      inside += in ? 1 : 0;
    }
  }
  return static_cast<double>(inside) / (double{kN} * kN);
}

TEST(QualityArea, RandomTrianglesAgreeWithDenseSamplingWithinItsBound) {
  // A straight edge crosses at most 2n - 1 cells of an n × n grid, and only a crossed cell's
  // point sample can disagree with its true coverage, by at most one cell (1/n²): so the
  // sampled area is within 3 (2n - 1) / n² of the exact one for a triangle's three edges.
  constexpr double kN = 1024;
  constexpr double kBound = 3 * (2 * kN - 1) / (kN * kN);
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> coord(-2 * kOne, 3 * kOne);
  int partial = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const SnappedTriangle t =
        tri(coord(rng), coord(rng), coord(rng), coord(rng), coord(rng), coord(rng));
    const double exact = exact_area(t, 0, 0).get_d();
    EXPECT_NEAR(sampled_area(t, 0, 0), exact, kBound) << trial;
    EXPECT_EQ(coverage(t, 0, 0), exact);
    partial += exact > 0 && exact < 1;
  }
  EXPECT_GT(partial, 10);  // the draw really exercised the clipping
}

TEST(QualityArea, SnapIsTheEnginesSnap) {
  const SnappedTriangle t = snap_triangle(
      {1.5f, 2.25f, 0, 1}, {3.0f + 1.0f / 512, 3.0f + 3.0f / 512, 0, 1}, {0.001f, 7.0f, 0, 1});
  EXPECT_EQ(t.x[0], 384);
  EXPECT_EQ(t.y[0], 576);
  EXPECT_EQ(t.x[1], 3 * 256);      // the tie 768.5 goes to the even step
  EXPECT_EQ(t.y[1], 3 * 256 + 2);  // and 769.5 too
  EXPECT_EQ(t.x[2], 0);            // 0.256 units rounds to 0
}

Scene two_triangle_square() {
  // The square [1.25, 3.75]² split along a diagonal, white on black.
  Scene s;
  s.width = 5;
  s.height = 5;
  Mesh m;
  m.space = Space::kScreen;
  m.color = {255, 255, 255, 255};
  m.positions = {{1.25f, 1.25f, 0.5f, 1}, {3.75f, 1.25f, 0.5f, 1}, {3.75f, 3.75f, 0.5f, 1},
                 {1.25f, 1.25f, 0.5f, 1}, {3.75f, 3.75f, 0.5f, 1}, {1.25f, 3.75f, 0.5f, 1}};
  s.meshes.push_back(m);
  return s;
}

TEST(QualityImage, ExactImageOfASquareByHand) {
  const Image img = exact_box_image(two_triangle_square(), {0, 0, 5, 5});
  // Corner pixels see 0.75 × 0.75, edge pixels 0.75 × 1, the middle pixel all of it.
  EXPECT_DOUBLE_EQ(img.at(1, 1, 0), 0.5625);
  EXPECT_DOUBLE_EQ(img.at(3, 3, 1), 0.5625);
  EXPECT_DOUBLE_EQ(img.at(2, 1, 2), 0.75);
  EXPECT_DOUBLE_EQ(img.at(2, 2, 0), 1.0);
  EXPECT_DOUBLE_EQ(img.at(0, 0, 0), 0.0);
  EXPECT_DOUBLE_EQ(img.at(4, 2, 0), 0.0);
  // A crop gives the same pixels.
  const Image crop = exact_box_image(two_triangle_square(), {1, 1, 2, 2});
  EXPECT_DOUBLE_EQ(crop.at(0, 0, 0), 0.5625);
  EXPECT_DOUBLE_EQ(crop.at(1, 1, 0), 1.0);
}

TEST(QualityImage, ExactImageRejectsOverlapAndClipSpace) {
  Scene s = two_triangle_square();
  s.meshes.push_back(s.meshes[0]);  // drawn twice: every covered pixel is covered twice
  EXPECT_THROW(exact_box_image(s, {0, 0, 5, 5}), Error);
  Scene c = two_triangle_square();
  c.meshes[0].space = Space::kClip;
  EXPECT_THROW(exact_box_image(c, {0, 0, 5, 5}), Error);
  EXPECT_THROW(exact_box_image(two_triangle_square(), {3, 3, 5, 5}), Error);
}

TEST(QualityImage, QualityScenesArePartitions) {
  // The exact path throws on overlap: the zone plate and the mesh must go through.
  EXPECT_NO_THROW(exact_box_image(zone_plate_scene(96, 64), {0, 0, 96, 64}));
  EXPECT_NO_THROW(exact_box_image(mesh_scene(96, 64), {0, 0, 96, 64}));
  EXPECT_THROW(exact_box_image(overlap_scene(96, 64), {0, 0, 96, 64}), Error);
}

TEST(QualityImage, SupersampledTruthIsWithinItsBoundOfTheExactOne) {
  const int w = 128, h = 96;
  const Scene star = builtin_scene("star", w, h);
  const Image exact = exact_box_image(star, {0, 0, w, h});
  Renderer renderer;
  const Image sampled = supersampled_image(star, {0, 0, w, h}, renderer);
  // Away from the centre (where many wedges meet) a pixel holds at most two boundaries (a
  // radial edge and the rim), each with a colour step of at most 1.
  double worst = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (std::hypot(x + 0.5 - w / 2.0, y + 0.5 - h / 2.0) < 16) continue;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::fabs(exact.at(x, y, c) - sampled.at(x, y, c)));
    }
  }
  EXPECT_LE(worst, 2 * kSupersampleBoundPerEdge);
  EXPECT_GT(worst, 0.0);  // the two really are different estimates
}

}  // namespace
}  // namespace mosaic::quality
