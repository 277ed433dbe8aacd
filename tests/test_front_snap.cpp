// Snapping to 16.8 fixed point (front::snap) and the viewport transform of clip-space draws.
//
// Expectations are derived by hand from the specification: round to the nearest 1/256 px with a
// tie going to the even step, and NDC [-1, 1]² mapped to [0, W] × [0, H] with y down and pixel (x,
// y) centred at (x + 0.5, y + 0.5).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "front/fixed_point.hpp"
#include "front/setup.hpp"
#include "reference_test_util.hpp"

namespace mosaic {
namespace {

using test::kUnits;

TEST(FrontSnap, ValuesOnTheGridAreExact) {
  for (int k = -5000; k <= 5000; ++k) EXPECT_EQ(front::snap(k / 256.0), k) << k;
  // The ends of the guard band: 2^15 px is 2^23 units.
  EXPECT_EQ(front::snap(32768.0), 1 << 23);
  EXPECT_EQ(front::snap(-32768.0), -(1 << 23));
  EXPECT_EQ(front::snap(32767.99609375), (1 << 23) - 1);  // 32768 - 1/256
  // Beyond the guard band (clipping rounding on extreme input) it saturates instead of wrapping.
  EXPECT_EQ(front::snap(4.4e8), 1 << 23);
  EXPECT_EQ(front::snap(-1e300), -(1 << 23));
}

TEST(FrontSnap, ValuesBetweenStepsRoundToNearest) {
  // (k + f) / 256 lies f of a step above k/256; below half a step it rounds down, above it up.
  const double fractions_down[] = {0.001, 0.1, 0.25, 0.4999};
  const double fractions_up[] = {0.5001, 0.75, 0.9, 0.999};
  for (int k = -700; k <= 700; k += 7) {
    for (double f : fractions_down) EXPECT_EQ(front::snap((k + f) / 256.0), k) << k << " " << f;
    for (double f : fractions_up) EXPECT_EQ(front::snap((k + f) / 256.0), k + 1) << k << " " << f;
  }
  // Pixel-sized examples written out: 10.3 px = 2636.8 units -> 2637; -10.3 px -> -2637.
  EXPECT_EQ(front::snap(10.3), 2637);
  EXPECT_EQ(front::snap(-10.3), -2637);
  EXPECT_EQ(front::snap(0.001), 0);   // 0.256 units
  EXPECT_EQ(front::snap(-0.001), 0);  // -0.256 units
  EXPECT_EQ(front::snap(0.003), 1);   // 0.768 units
  EXPECT_EQ(front::snap(-0.003), -1);
}

TEST(FrontSnap, HalvesGoToTheEvenStepOnBothSidesOfZero) {
  // A tie rounds to the even step (IEEE's default rounding, and llvmpipe's), on either side of
  // zero; a shape moved by whole pixels (an even number of steps) still snaps to the same shape
  // moved by whole pixels.
  EXPECT_EQ(front::snap(0.5 / 256), 0);
  EXPECT_EQ(front::snap(-0.5 / 256), 0);
  EXPECT_EQ(front::snap(1.5 / 256), 2);
  EXPECT_EQ(front::snap(-1.5 / 256), -2);
  EXPECT_EQ(front::snap(2.5 / 256), 2);
  EXPECT_EQ(front::snap(-2.5 / 256), -2);
  EXPECT_EQ(front::snap(10.5 + 1.0 / 512), 10 * 256 + 128);  // 2688.5 units -> 2688
  EXPECT_EQ(front::snap(10.5 + 3.0 / 512), 10 * 256 + 130);  // 2689.5 units -> 2690
  for (int k = -1000; k <= 1000; ++k) {
    const double half = (k + 0.5) / 256.0;  // exact in double
    const int even = k % 2 == 0 ? k : k + 1;
    EXPECT_EQ(front::snap(half), even) << k;
    // Either side of the tie rounds to its own nearest step.
    EXPECT_EQ(front::snap(std::nextafter(half, -1e9)), k) << k;
    EXPECT_EQ(front::snap(std::nextafter(half, 1e9)), k + 1) << k;
  }
}

TEST(FrontSnap, WholePixelTranslationMovesTheSnappedPointByWholePixels) {
  test::Rng rng(7);
  for (int i = 0; i < 2000; ++i) {
    // Points on the half-step grid (every other one a tie) and arbitrary ones.
    const double x =
        i % 2 ? static_cast<double>(rng.range(-20000, 20000)) / 512.0 : rng.uniform(-100.0, 100.0);
    const int shift = static_cast<int>(rng.range(-3000, 3000));
    EXPECT_EQ(front::snap(x + shift), front::snap(x) + shift * kUnits) << x << " " << shift;
  }
}

// --- Viewport ------------------------------------------------------------------------------------

// A clip-space mesh of one constant colour; each corner (ndc x, ndc y) becomes (x w, y w, z w, w).
Mesh clip_rect(double x0, double y0, double x1, double y1, float w, float z_ndc, Rgba8 color) {
  Mesh m;
  m.space = Space::kClip;
  m.color = color;
  m.state.depth_test = DepthTest::kAlways;
  auto v = [&](double x, double y) {
    m.positions.emplace_back(static_cast<float>(x) * w, static_cast<float>(y) * w, z_ndc * w, w);
  };
  v(x0, y0);
  v(x1, y0);
  v(x1, y1);
  v(x0, y0);
  v(x1, y1);
  v(x0, y1);
  return m;
}

// Pixel (px, py) is covered by an NDC rectangle whose window-space edges miss every pixel centre
// iff its centre lies strictly inside the window-space rectangle.
void expect_rect_coverage(const RenderTarget& t, double x0, double y0, double x1, double y1) {
  const double W = t.width(), H = t.height();
  const double left = (x0 + 1) * W / 2, right = (x1 + 1) * W / 2;
  const double top = (1 - y1) * H / 2, bottom = (1 - y0) * H / 2;  // y flips: NDC +1 is row 0
  int covered = 0;
  for (int y = 0; y < t.height(); ++y) {
    for (int x = 0; x < t.width(); ++x) {
      const bool expect = left < x + 0.5 && x + 0.5 < right && top < y + 0.5 && y + 0.5 < bottom;
      const bool got = !(t.sample_color()[test::sample_index(t, x, y, 0)] == test::kClear);
      EXPECT_EQ(got, expect) << "pixel " << x << "," << y;
      covered += got;
    }
  }
  EXPECT_GT(covered, 0);
}

TEST(FrontViewport, NdcRectanglesLandOnTheExpectedPixels) {
  struct Case {
    double x0, y0, x1, y1;
  };
  // Square target: the middle half; the top-left corner (NDC y = +1 is the top row); a
  // rectangle whose edges fall on quarter pixels.
  const Case cases[] = {
      {-0.5, -0.5, 0.5, 0.5}, {-1.0, 0.5, -0.5, 1.0}, {-0.3125, -0.8125, 0.90625, 0.0390625}};
  for (const Case& c : cases) {
    for (float w : {1.0f, 2.0f, 0.25f}) {
      for (auto [W, H] : {std::pair{64, 64}, std::pair{64, 32}, std::pair{24, 40}}) {
        SCOPED_TRACE(testing::Message() << c.x0 << "," << c.y0 << " " << c.x1 << "," << c.y1
                                        << " w=" << w << " " << W << "x" << H);
        RenderTarget t = test::sample_target(W, H, 1);
        const FrameStats s =
            test::render_reference(clip_rect(c.x0, c.y0, c.x1, c.y1, w, 0.5f, {9, 9, 9, 255}), t);
        EXPECT_EQ(s.triangles_drawn, 2u);
        expect_rect_coverage(t, c.x0, c.y0, c.x1, c.y1);
      }
    }
  }
}

TEST(FrontViewport, TopLeftCornerOfANonSquareTarget) {
  // NDC x in [-1, -0.5], y in [0.5, 1] on 64x32: pixels [0, 16) x [0, 8), written out by hand.
  RenderTarget t = test::sample_target(64, 32, 1);
  test::render_reference(clip_rect(-1, 0.5, -0.5, 1, 1.0f, 0.5f, {9, 9, 9, 255}), t);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x)
      EXPECT_EQ(!(t.sample_color()[test::sample_index(t, x, y, 0)] == test::kClear),
                x < 16 && y < 8)
          << x << "," << y;
}

TEST(FrontViewport, DepthIsZOverW) {
  for (float w : {1.0f, 2.0f, 8.0f}) {
    for (float z : {0.0f, 0.25f, 0.75f, 1.0f}) {
      RenderTarget t = test::sample_target(16, 16, 4);
      test::render_reference(clip_rect(-0.5, -0.5, 0.5, 0.5, w, z, {9, 9, 9, 255}), t);
      const std::size_t i = test::sample_index(t, 8, 8, 2);
      ASSERT_FALSE(t.sample_color()[i] == test::kClear);
      EXPECT_EQ(t.sample_depth()[i], z) << "w=" << w;
    }
  }
}

}  // namespace
}  // namespace mosaic
