// Triangle setup (front::setup_triangle): edge functions with the fill rule folded in, the
// bounding box, culling, degeneracy, the depth plane, and the 8-bit colour conversion.
//
// The edge functions are checked against the independent oracle of reference_test_util.hpp and
// against cases worked out by hand; the depth plane against a double-precision plane through the
// snapped vertices. The block walker's per-row depth range (raster/hiz.hpp) against the plain one.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include "front/draw_area.hpp"
#include "front/setup.hpp"
#include "raster/hiz.hpp"
#include "raster/tile.hpp"
#include "reference_test_util.hpp"
#include "scenes/rng.hpp"

namespace mosaic {
namespace {

using test::Fx;

front::ScreenVertex sv(double x, double y, float z = 0.5f) {
  front::ScreenVertex v;
  v.x = x;
  v.y = y;
  v.z = z;
  return v;
}
front::ScreenVertex sv(Fx p, float z = 0.5f) {
  return sv(test::fx_to_px(p).x, test::fx_to_px(p).y, z);
}

bool engine_inside(const front::TriangleSetup& t, Fx p) {
  for (const front::EdgeFunction& e : t.edge)
    if (e(p.x, p.y) < 0) return false;
  return true;
}

DrawState rule_state(FillRule rule) {
  DrawState s;
  s.fill_rule = rule;
  return s;
}

Fx px(double x, double y) { return {test::snap_units(x), test::snap_units(y)}; }

TEST(FrontSetup, HandWorkedFillRuleCases) {
  struct Point {
    Fx p;
    bool d3d, gl;
  };
  // Triangle A: top edge y = 1.5, left edge x = 1.5, hypotenuse x + y = 7 (a right edge).
  const std::array<Fx, 3> a{px(1.5, 1.5), px(5.5, 1.5), px(1.5, 5.5)};
  const Point on_a[] = {
      {px(3.5, 1.5), true, false},   // on the top edge: D3D keeps it, OpenGL does not
      {px(1.5, 3.5), true, true},    // on the left edge: both keep it
      {px(3.5, 3.5), false, false},  // on the right edge (hypotenuse): neither
      {px(1.5, 1.5), true, false},   // the top-left vertex: top and left
      {px(5.5, 1.5), false, false},  // top and right
      {px(1.5, 5.5), false, false},  // left and right
      {px(2.5, 2.5), true, true},    // strictly inside
      {px(5.5, 5.5), false, false},  // strictly outside
  };
  // Triangle B: bottom edge y = 5.5, right edge x = 5.5, hypotenuse x + y = 7 (a left edge).
  const std::array<Fx, 3> b{px(1.5, 5.5), px(5.5, 5.5), px(5.5, 1.5)};
  const Point on_b[] = {
      {px(3.5, 5.5), false, true},   // on the bottom edge: OpenGL keeps it, D3D does not
      {px(5.5, 3.5), false, false},  // on the right edge
      {px(3.5, 3.5), true, true},    // on the hypotenuse, a left edge here
      {px(1.5, 5.5), false, true},   // bottom and left
      {px(5.5, 5.5), false, false},  // bottom and right
      {px(5.5, 1.5), false, false},  // right and left
  };
  for (const auto& [tri, points] :
       {std::pair{a, std::span<const Point>(on_a)}, std::pair{b, std::span<const Point>(on_b)}}) {
    for (bool reversed : {false, true}) {
      for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
        front::TriangleSetup t;
        const std::array<front::ScreenVertex, 3> v =
            reversed ? std::array{sv(tri[0]), sv(tri[2]), sv(tri[1])}
                     : std::array{sv(tri[0]), sv(tri[1]), sv(tri[2])};
        ASSERT_EQ(front::setup_triangle(v, rule_state(rule), front::DrawArea::whole(16, 16), false,
                                        {}, t),
                  front::SetupReject::kNone);
        for (const Point& p : points) {
          const bool expect = rule == FillRule::kD3D ? p.d3d : p.gl;
          EXPECT_EQ(engine_inside(t, p.p), expect)
              << "point " << p.p.x << "," << p.p.y << " reversed " << reversed << " rule "
              << static_cast<int>(rule);
          // The oracle agrees with the hand-worked answer too.
          EXPECT_EQ(test::oracle_covers(tri, p.p, rule), expect);
        }
      }
    }
  }
}

TEST(FrontSetup, EdgeFunctionsMatchTheOracleOnACoarseGrid) {
  // Vertices on a 1/8 px grid and points on a 1/16 px grid: many points fall exactly on edges
  // and on vertices, where only the fill rule decides.
  test::Rng rng(11);
  int on_boundary = 0;
  for (int i = 0; i < 400; ++i) {
    std::array<Fx, 3> tri;
    for (Fx& p : tri) p = {rng.range(0, 96) * 32, rng.range(0, 96) * 32};
    for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
      for (bool reversed : {false, true}) {
        const std::array<front::ScreenVertex, 3> v =
            reversed ? std::array{sv(tri[0]), sv(tri[2]), sv(tri[1])}
                     : std::array{sv(tri[0]), sv(tri[1]), sv(tri[2])};
        front::TriangleSetup t;
        const front::SetupReject r = front::setup_triangle(
            v, rule_state(rule), front::DrawArea::whole(16, 16), false, {}, t);
        const std::int64_t area2 = (tri[1].x - tri[0].x) * (tri[2].y - tri[0].y) -
                                   (tri[2].x - tri[0].x) * (tri[1].y - tri[0].y);
        if (area2 == 0) {
          EXPECT_EQ(r, front::SetupReject::kDegenerate);
          continue;
        }
        ASSERT_EQ(r, front::SetupReject::kNone);
        auto check = [&](Fx p) {
          ASSERT_EQ(engine_inside(t, p), test::oracle_covers(tri, p, rule))
              << "tri (" << tri[0].x << "," << tri[0].y << ") (" << tri[1].x << "," << tri[1].y
              << ") (" << tri[2].x << "," << tri[2].y << ") p " << p.x << "," << p.y;
        };
        for (int k = 0; k < 200; ++k) check({rng.range(0, 200) * 16, rng.range(0, 200) * 16});
        // Every lattice point of each edge line from one step before the first vertex to one
        // step past the second: points on the edge, on its vertices, and on its extension.
        for (int e = 0; e < 3; ++e) {
          const Fx a0 = tri[e], a1 = tri[(e + 1) % 3];
          const std::int64_t g = std::gcd(a1.x - a0.x, a1.y - a0.y);
          const Fx step{(a1.x - a0.x) / g, (a1.y - a0.y) / g};
          for (std::int64_t j = -1; j <= g + 1; ++j) {
            check({a0.x + j * step.x, a0.y + j * step.y});
            ++on_boundary;
          }
        }
      }
    }
  }
  EXPECT_GT(on_boundary, 500);
}

TEST(FrontSetup, BoundingBoxHoldsEveryCoveredSampleAndStaysInTheTarget) {
  test::Rng rng(12);
  constexpr int kW = 12, kH = 10;
  for (int i = 0; i < 300; ++i) {
    std::array<Fx, 3> tri;
    for (Fx& p : tri) p = {rng.range(-5 * 256, 17 * 256), rng.range(-5 * 256, 15 * 256)};
    front::TriangleSetup t;
    const front::SetupReject r = front::setup_triangle(
        {sv(tri[0]), sv(tri[1]), sv(tri[2])}, {}, front::DrawArea::whole(kW, kH), false, {}, t);
    if (r != front::SetupReject::kNone) continue;
    EXPECT_LE(0, t.bx0);
    EXPECT_LE(0, t.by0);
    EXPECT_LE(t.bx1, kW);
    EXPECT_LE(t.by1, kH);
    for (int samples : {1, 4, 16}) {
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
          for (int s = 0; s < samples; ++s)
            if (test::oracle_covers(tri, test::sample_fx(x, y, s, samples), FillRule::kD3D)) {
              EXPECT_TRUE(t.bx0 <= x && x < t.bx1 && t.by0 <= y && y < t.by1)
                  << "pixel " << x << "," << y << " outside its triangle's box";
            }
    }
  }
}

TEST(FrontSetup, FaceCullingByScreenWinding) {
  // (10,10) -> (10,30) -> (30,30) runs down, then right: counter-clockwise as seen on screen.
  const std::array<front::ScreenVertex, 3> ccw{sv(10, 10), sv(10, 30), sv(30, 30)};
  const std::array<front::ScreenVertex, 3> cw{sv(10, 10), sv(30, 30), sv(10, 30)};
  struct Case {
    FrontFace front;
    CullMode cull;
    bool ccw_kept, cw_kept;
  };
  const Case cases[] = {
      {FrontFace::kCounterClockwise, CullMode::kNone, true, true},
      {FrontFace::kCounterClockwise, CullMode::kBack, true, false},
      {FrontFace::kCounterClockwise, CullMode::kFront, false, true},
      {FrontFace::kClockwise, CullMode::kBack, false, true},
      {FrontFace::kClockwise, CullMode::kFront, true, false},
  };
  for (const Case& c : cases) {
    DrawState s;
    s.front_face = c.front;
    s.cull = c.cull;
    front::TriangleSetup t;
    EXPECT_EQ(front::setup_triangle(ccw, s, front::DrawArea::whole(64, 64), false, {}, t),
              c.ccw_kept ? front::SetupReject::kNone : front::SetupReject::kFace);
    EXPECT_EQ(front::setup_triangle(cw, s, front::DrawArea::whole(64, 64), false, {}, t),
              c.cw_kept ? front::SetupReject::kNone : front::SetupReject::kFace);
  }
}

TEST(FrontSetup, DegenerateAfterSnappingAndOutside) {
  front::TriangleSetup t;
  // Collinear.
  EXPECT_EQ(front::setup_triangle({sv(1, 1), sv(5, 5), sv(9, 9)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kDegenerate);
  // Two vertices 0.001 px apart snap to the same point.
  EXPECT_EQ(front::setup_triangle({sv(3, 3), sv(3.001, 3), sv(9, 12)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kDegenerate);
  // Collinear only after snapping: 2.001 -> 2 (0.256 units round down).
  EXPECT_EQ(front::setup_triangle({sv(0, 0), sv(1, 1), sv(2, 2.001)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kDegenerate);
  // ... but 2.003 (0.768 units) rounds up and leaves a sliver.
  EXPECT_EQ(front::setup_triangle({sv(0, 0), sv(1, 1), sv(2, 2.003)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kNone);
  // Entirely left of, right of, above and below a 16x16 target.
  EXPECT_EQ(front::setup_triangle({sv(-9, 1), sv(-1, 5), sv(-4, 9)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kOutside);
  EXPECT_EQ(front::setup_triangle({sv(16.5, 1), sv(20, 5), sv(18, 9)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kOutside);
  EXPECT_EQ(front::setup_triangle({sv(1, -9), sv(5, -1), sv(9, -4)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kOutside);
  EXPECT_EQ(front::setup_triangle({sv(1, 17), sv(5, 20), sv(9, 18)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kOutside);
}

TEST(FrontSetup, DepthPlaneGoesThroughTheSnappedVertices) {
  // Vertices off the 1/256 grid with depth slopes near 1/64 per px: a plane through the unsnapped
  // points would be off by ~1e-4, far beyond the tolerance.
  test::Rng rng(13);
  int checked = 0;
  for (int i = 0; i < 200; ++i) {
    std::array<glm::dvec2, 3> raw;
    std::array<double, 3> z;
    for (int k = 0; k < 3; ++k) {
      raw[k] = {rng.uniform(0, 64), rng.uniform(0, 64)};
      z[k] = static_cast<float>(rng.unit());
    }
    std::array<glm::dvec2, 3> snapped;
    std::array<Fx, 3> fx;
    for (int k = 0; k < 3; ++k) {
      fx[k] = test::snap_fx(raw[k]);
      snapped[k] = test::fx_to_px(fx[k]);
    }
    const double area =
        0.5 * std::abs((snapped[1].x - snapped[0].x) * (snapped[2].y - snapped[0].y) -
                       (snapped[2].x - snapped[0].x) * (snapped[1].y - snapped[0].y));
    if (area < 50) continue;  // slivers have steep planes; their float error is not "tight"
    front::TriangleSetup t;
    const std::array<front::ScreenVertex, 3> v{sv(raw[0].x, raw[0].y, static_cast<float>(z[0])),
                                               sv(raw[1].x, raw[1].y, static_cast<float>(z[1])),
                                               sv(raw[2].x, raw[2].y, static_cast<float>(z[2]))};
    ASSERT_EQ(front::setup_triangle(v, {}, front::DrawArea::whole(64, 64), false, {}, t),
              front::SetupReject::kNone);
    const double zmin = std::min({z[0], z[1], z[2]}), zmax = std::max({z[0], z[1], z[2]});
    EXPECT_EQ(t.z_min, static_cast<float>(zmin));
    EXPECT_EQ(t.z_max, static_cast<float>(zmax));
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(front::sample_depth(t, static_cast<float>(snapped[k].x),
                                      static_cast<float>(snapped[k].y)),
                  z[k], test::depth_tolerance(snapped, z, snapped[k]));
    }
    for (int k = 0; k < 100; ++k) {
      const Fx q{rng.range(0, 64 * 16) * 16, rng.range(0, 64 * 16) * 16};
      if (!test::oracle_covers(fx, q, FillRule::kD3D)) continue;
      const glm::dvec2 qp = test::fx_to_px(q);
      const double expect = std::clamp(test::plane_at(snapped, z, qp), zmin, zmax);
      EXPECT_NEAR(front::sample_depth(t, static_cast<float>(qp.x), static_cast<float>(qp.y)),
                  expect, test::depth_tolerance(snapped, z, qp))
          << qp.x << "," << qp.y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(FrontSetup, DepthIsClampedToTheVertexRange) {
  front::TriangleSetup t;
  ASSERT_EQ(front::setup_triangle({sv(0, 0, 0.25f), sv(8, 0, 0.5f), sv(0, 8, 0.75f)}, {},
                                  front::DrawArea::whole(16, 16), false, {}, t),
            front::SetupReject::kNone);
  // Far beyond each side the plane leaves [0.25, 0.75]; the depth stops at the nearest bound.
  EXPECT_EQ(front::sample_depth(t, -100, -100), 0.25f);
  EXPECT_EQ(front::sample_depth(t, 0, 1000), 0.75f);
  EXPECT_EQ(front::sample_depth(t, 1000, 0), 0.75f);  // ddx = 1/32: 0.25 + 1000/32 > 0.75
  // Inside: exact plane values (all dyadic).
  EXPECT_EQ(front::sample_depth(t, 4, 0), 0.375f);
  EXPECT_EQ(front::sample_depth(t, 0, 4), 0.5f);
  EXPECT_EQ(front::sample_depth(t, 2, 2), 0.25f + 2 * 0.03125f + 2 * 0.0625f);
}

TEST(FrontSetup, UnormConversionClampsAndRoundsHalfUp) {
  EXPECT_EQ(front::to_unorm8(0.0f), 0);
  EXPECT_EQ(front::to_unorm8(0.49f), 0);
  EXPECT_EQ(front::to_unorm8(0.5f), 1);
  EXPECT_EQ(front::to_unorm8(127.5f), 128);
  EXPECT_EQ(front::to_unorm8(254.49f), 254);
  EXPECT_EQ(front::to_unorm8(254.5f), 255);
  EXPECT_EQ(front::to_unorm8(255.0f), 255);
  EXPECT_EQ(front::to_unorm8(1e9f), 255);
  EXPECT_EQ(front::to_unorm8(-3.0f), 0);
  EXPECT_EQ(front::to_unorm8(-std::numeric_limits<float>::infinity()), 0);
  EXPECT_EQ(front::to_unorm8(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(front::to_unorm8(std::numeric_limits<float>::quiet_NaN()), 0);
}

// The block walker's depth range over an 8×8 block, made from per-triangle and per-row terms
// (BlockDepthRows), is BlockDepthRange::over()'s bit for bit: planes of every sign and scale, and
// blocks near, far from and on either side of the plane's anchor.
TEST(FrontSetup, BlockDepthRowsEqualTheDepthRangeOfEachBlock) {
  SplitMix64 rng{77};
  const auto value = [&rng] {
    const double scale[] = {0.0, 1e-7, 1e-3, 0.5, 3.0, 1e4};
    return static_cast<float>(rng.uniform(-1, 1) * scale[rng.next() % std::size(scale)]);
  };
  std::size_t checked = 0, differ = 0;
  for (int i = 0; i < 20000; ++i) {
    front::TriangleSetup t;
    t.z = {value(), value(), value()};
    t.x0 = static_cast<float>(std::floor(rng.uniform(-100, 17000) * 256) / 256);
    t.y0 = static_cast<float>(std::floor(rng.uniform(-100, 17000) * 256) / 256);
    t.z_min = std::min(value(), value());
    t.z_max = t.z_min + std::abs(value());
    const raster::BlockDepthRows<raster::kBlockSize> rows(t);
    const int py0 = 8 * static_cast<int>(rng.uniform(-16, 2100));
    const auto row = raster::BlockDepthRows<raster::kBlockSize>::row(t, py0);
    for (int k = 0; k < 4; ++k) {
      const int px0 = 8 * static_cast<int>(rng.uniform(-16, 2100));
      const auto [lo, hi] = rows.at(px0, row, t.z_min, t.z_max);
      const auto [rlo, rhi] = raster::BlockDepthRange(t).over(px0, py0, raster::kBlockSize,
                                                              raster::kBlockSize, t.z_min, t.z_max);
      differ += std::memcmp(&lo, &rlo, sizeof lo) != 0 || std::memcmp(&hi, &rhi, sizeof hi) != 0;
      ++checked;
    }
  }
  EXPECT_EQ(differ, 0u) << "of " << checked;
}

}  // namespace
}  // namespace mosaic
