// Coverage of the reference rasterizer: the fill rules (D3D top-left, OpenGL bottom-left) at
// 1, 4 and 16 samples, shared edges and vertices covered exactly once, and a jittered full-screen
// triangulation that must cover every sample exactly once.
//
// Expectations come from cases worked out by hand and from the independent oracle in
// reference_test_util.hpp; the sample positions from the standard tables written there.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "reference_test_util.hpp"

namespace mosaic {
namespace {

using test::Fx;

Mesh rule_mesh(FillRule rule) {
  DrawState s;
  s.fill_rule = rule;
  s.depth_test = DepthTest::kAlways;
  return test::screen_mesh(s);
}

bool covered(const RenderTarget& t, int x, int y, int s) {
  return !(t.sample_color()[test::sample_index(t, x, y, s)] == test::kClear);
}

TEST(ReferenceFill, HandWorkedTrianglesAtPixelCentres) {
  // Triangle A (1.5,1.5) (5.5,1.5) (1.5,5.5): top edge y = 1.5, left edge x = 1.5, right edge
  // x + y = 7. Pixel centres are (x + 0.5, y + 0.5), so (x, y) lies on the top edge when y = 1, on
  // the left one when x = 1 and on the hypotenuse when x + y = 6.
  //   D3D keeps top and left:  x >= 1, y >= 1, x + y <= 5   (10 pixels)
  //   OpenGL keeps left only:  x >= 1, y >= 2, x + y <= 5   (6 pixels)
  // Triangle B (1.5,5.5) (5.5,5.5) (5.5,1.5): bottom edge y = 5.5, right edge x = 5.5, and the
  // hypotenuse is a left edge.
  //   D3D:    x <= 4, y <= 4, x + y >= 6   (6 pixels)
  //   OpenGL: x <= 4, y <= 5, x + y >= 6   (10 pixels)
  // Together they are the square, 16 pixels either way, each covered once.
  auto in_a = [](int x, int y, FillRule r) {
    return x >= 1 && y >= (r == FillRule::kD3D ? 1 : 2) && x + y <= 5;
  };
  auto in_b = [](int x, int y, FillRule r) {
    return x <= 4 && y <= (r == FillRule::kD3D ? 4 : 5) && x + y >= 6;
  };
  for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
    for (bool reversed : {false, true}) {
      Mesh a = rule_mesh(rule), b = rule_mesh(rule);
      if (!reversed) {
        test::add_tri(a, {1.5, 1.5}, {5.5, 1.5}, {1.5, 5.5}, {255, 0, 0, 255});
        test::add_tri(b, {1.5, 5.5}, {5.5, 5.5}, {5.5, 1.5}, {0, 255, 0, 255});
      } else {
        test::add_tri(a, {1.5, 1.5}, {1.5, 5.5}, {5.5, 1.5}, {255, 0, 0, 255});
        test::add_tri(b, {1.5, 5.5}, {5.5, 1.5}, {5.5, 5.5}, {0, 255, 0, 255});
      }
      RenderTarget ta = test::sample_target(8, 8, 1), tb = test::sample_target(8, 8, 1),
                   tab = test::sample_target(8, 8, 1);
      EXPECT_EQ(test::render_reference(a, ta).samples_written, rule == FillRule::kD3D ? 10u : 6u);
      EXPECT_EQ(test::render_reference(b, tb).samples_written, rule == FillRule::kD3D ? 6u : 10u);
      EXPECT_EQ(test::render_reference({a, b}, tab).samples_written, 16u);
      for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
          EXPECT_EQ(covered(ta, x, y, 0), in_a(x, y, rule)) << x << "," << y;
          EXPECT_EQ(covered(tb, x, y, 0), in_b(x, y, rule)) << x << "," << y;
          EXPECT_EQ(covered(tab, x, y, 0), in_a(x, y, rule) || in_b(x, y, rule));
        }
      }
    }
  }
}

TEST(ReferenceFill, FourSampleEdgesThroughSamplePositions) {
  // The 4x pattern in 1/16 px: s0 (-2,-6), s1 (6,-2), s2 (-6,2), s3 (2,6). A rectangle with
  // left x = 10.375 (s0 of column 10: 10.5 - 2/16), right x = 20.375 (s0 of column 20),
  // top y = 4.125 (s0 of row 4: 4.5 - 6/16), bottom y = 12.125 (s0 of row 12), drawn as two
  // triangles. Samples exactly on the left edge are in under both rules, on the right edge out;
  // on the top edge in for D3D only, on the bottom edge in for OpenGL only. The corner (10.375,
  // 4.125) is s0 of pixel (10, 4): in for D3D (top and left), out for OpenGL.
  const double left = 10.375, right = 20.375, top = 4.125, bottom = 12.125;
  for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
    Mesh m = rule_mesh(rule);
    test::add_tri(m, {left, top}, {right, top}, {right, bottom}, {255, 0, 0, 255});
    test::add_tri(m, {left, top}, {right, bottom}, {left, bottom}, {0, 255, 0, 255});
    RenderTarget t = test::sample_target(32, 16, 4);
    const FrameStats s = test::render_reference(m, t);
    const bool d3d = rule == FillRule::kD3D;
    std::size_t expect_count = 0;
    for (int y = 0; y < 16; ++y) {
      for (int x = 0; x < 32; ++x) {
        for (int k = 0; k < 4; ++k) {
          const glm::dvec2 p = test::sample_px(x, y, k, 4);
          const bool in_x = (left < p.x && p.x < right) || p.x == left;
          const bool in_y =
              (top < p.y && p.y < bottom) || (p.y == top && d3d) || (p.y == bottom && !d3d);
          expect_count += in_x && in_y;
          EXPECT_EQ(covered(t, x, y, k), in_x && in_y) << x << "," << y << "/" << k;
        }
      }
    }
    EXPECT_EQ(s.samples_written, expect_count);
    // Spot checks written out: pixel (10, 4) has s1, s3 and, for D3D only, s0.
    EXPECT_EQ(covered(t, 10, 4, 0), d3d);
    EXPECT_TRUE(covered(t, 10, 4, 1));
    EXPECT_FALSE(covered(t, 10, 4, 2));
    EXPECT_TRUE(covered(t, 10, 4, 3));
    // Column 20 keeps only s2 (x = 20.125); row 12 only s0, for OpenGL.
    EXPECT_TRUE(covered(t, 20, 8, 2));
    EXPECT_FALSE(covered(t, 20, 8, 0));
    EXPECT_EQ(covered(t, 15, 12, 0), !d3d);
    EXPECT_FALSE(covered(t, 15, 12, 1));
  }
}

// Renders one triangle alone and compares every sample with the oracle.
void expect_matches_oracle(const std::array<Fx, 3>& tri, FillRule rule, int samples, int W, int H) {
  Mesh m = rule_mesh(rule);
  test::add_tri_fx(m, tri[0], tri[1], tri[2], {255, 255, 255, 255});
  RenderTarget t = test::sample_target(W, H, samples);
  const FrameStats s = test::render_reference(m, t);
  std::size_t expect_count = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int k = 0; k < samples; ++k) {
        const bool expect = test::oracle_covers(tri, test::sample_fx(x, y, k, samples), rule);
        expect_count += expect;
        ASSERT_EQ(covered(t, x, y, k), expect)
            << "sample " << x << "," << y << "/" << k << " of (" << tri[0].x << "," << tri[0].y
            << ") (" << tri[1].x << "," << tri[1].y << ") (" << tri[2].x << "," << tri[2].y << ")";
      }
  EXPECT_EQ(s.samples_written, expect_count);
}

TEST(ReferenceFill, RandomTrianglesMatchTheOracle) {
  // Vertices on a 1/16 px grid, partly outside the 12x10 target: every sample position of every
  // standard pattern is on that grid, so vertices often sit on samples and edges run through them.
  test::Rng rng(31);
  for (int i = 0; i < 150; ++i) {
    std::array<Fx, 3> tri;
    for (Fx& p : tri) p = {rng.range(-3 * 16, 15 * 16) * 16, rng.range(-3 * 16, 13 * 16) * 16};
    for (int samples : {1, 4, 16})
      for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
        expect_matches_oracle(tri, rule, samples, 12, 10);
        if (HasFatalFailure()) return;
      }
  }
}

TEST(ReferenceFill, SharedEdgesAreCoveredExactlyOnce) {
  // Two triangles P Q R1 and Q P R2 with R1, R2 on opposite sides of PQ, random winding each,
  // vertices on the 1/8 px grid so that PQ runs through many samples (horizontal, vertical and
  // diagonal edges come up often on this small grid).
  test::Rng rng(32);
  int shared_samples = 0;
  for (int i = 0; i < 1000; ++i) {
    auto pt = [&] { return Fx{rng.range(0, 12 * 8) * 32, rng.range(0, 10 * 8) * 32}; };
    Fx P = pt(), Q = pt();
    if (i % 2) {
      // Half the cases: P on a 1x or 4x sample and PQ horizontal, vertical or diagonal, so that
      // it runs through the same sample of a whole row, column or diagonal of pixels.
      const int pattern = rng.coin() ? 1 : 4;
      P = test::sample_fx(static_cast<int>(rng.range(2, 9)), static_cast<int>(rng.range(2, 7)),
                          static_cast<int>(rng.range(0, pattern - 1)), pattern);
      const Fx dirs[] = {{256, 0}, {0, 256}, {256, 256}, {-256, 256}};
      const Fx d = dirs[rng.range(0, 3)];
      const std::int64_t k = rng.range(1, 4) * (rng.coin() ? 1 : -1);
      Q = {P.x + k * d.x, P.y + k * d.y};
    }
    const Fx R1 = pt(), R2 = pt();
    auto side = [&](Fx r) { return (Q.x - P.x) * (r.y - P.y) - (Q.y - P.y) * (r.x - P.x); };
    if (side(R1) == 0 || side(R2) == 0 || (side(R1) > 0) == (side(R2) > 0)) continue;
    std::array<Fx, 3> t1{P, Q, R1}, t2{Q, P, R2};
    if (rng.coin()) std::swap(t1[0], t1[1]);
    if (rng.coin()) std::swap(t2[0], t2[1]);
    for (int samples : {1, 4})
      for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
        Mesh m = rule_mesh(rule);
        test::add_tri_fx(m, t1[0], t1[1], t1[2], {255, 0, 0, 255});
        test::add_tri_fx(m, t2[0], t2[1], t2[2], {0, 255, 0, 255});
        RenderTarget t = test::sample_target(12, 10, samples);
        const FrameStats s = test::render_reference(m, t);
        EXPECT_EQ(s.samples_written, test::count_covered(t)) << "a sample was covered twice";
        for (int y = 0; y < 10; ++y)
          for (int x = 0; x < 12; ++x)
            for (int k = 0; k < samples; ++k) {
              const Fx q = test::sample_fx(x, y, k, samples);
              const bool in1 = test::oracle_covers(t1, q, rule);
              const bool in2 = test::oracle_covers(t2, q, rule);
              ASSERT_FALSE(in1 && in2);  // the oracle itself splits shared samples
              ASSERT_EQ(covered(t, x, y, k), in1 || in2) << i << " " << x << "," << y << "/" << k;
              // Samples on the segment PQ (strictly between its ends) must be covered once.
              const std::int64_t cr = (Q.x - P.x) * (q.y - P.y) - (Q.y - P.y) * (q.x - P.x);
              if (cr == 0 && std::min(P.x, Q.x) <= q.x && q.x <= std::max(P.x, Q.x) &&
                  std::min(P.y, Q.y) <= q.y && q.y <= std::max(P.y, Q.y) &&
                  !(q.x == P.x && q.y == P.y) && !(q.x == Q.x && q.y == Q.y)) {
                EXPECT_TRUE(covered(t, x, y, k));
                ++shared_samples;
              }
            }
      }
  }
  EXPECT_GT(shared_samples, 200);
}

TEST(ReferenceFill, FanAroundAVertexOnASampleCoversItOnce) {
  // Eight triangles around (8.5, 8.5), the 1x sample of pixel (8, 8): the fan closes, so that
  // sample, and every other sample inside the rim, is covered exactly once.
  const glm::dvec2 c{8.5, 8.5};
  for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
    for (bool reversed : {false, true}) {
      Mesh m = rule_mesh(rule);
      const int n = 8;
      for (int i = 0; i < n; ++i) {
        // Rim points on a square of half-size 5 so that rim vertices are on the grid.
        auto rim = [&](int k) {
          const glm::dvec2 corners[8] = {{5, 0},  {5, 5},   {0, 5},  {-5, 5},
                                         {-5, 0}, {-5, -5}, {0, -5}, {5, -5}};
          return c + corners[k % 8];
        };
        if (reversed)
          test::add_tri(m, c, rim(i + 1), rim(i),
                        test::distinct_color(static_cast<std::uint32_t>(i)));
        else
          test::add_tri(m, c, rim(i), rim(i + 1),
                        test::distinct_color(static_cast<std::uint32_t>(i)));
      }
      for (int samples : {1, 4, 16}) {
        RenderTarget t = test::sample_target(17, 17, samples);
        const FrameStats s = test::render_reference(m, t);
        EXPECT_EQ(s.samples_written, test::count_covered(t));
        // Every sample strictly inside the rim square (3.5 .. 13.5) is covered.
        for (int y = 3; y < 14; ++y)
          for (int x = 3; x < 14; ++x)
            for (int k = 0; k < samples; ++k) {
              const glm::dvec2 p = test::sample_px(x, y, k, samples);
              if (p.x > 3.5 && p.x < 13.5 && p.y > 3.5 && p.y < 13.5) {
                EXPECT_TRUE(covered(t, x, y, k)) << x << "," << y << "/" << k;
              }
            }
        EXPECT_TRUE(covered(t, 8, 8, 0));
      }
    }
  }
}

// --- Full-screen triangulation -------------------------------------------------------------------

struct Grid {
  static constexpr int kCols = 17, kRows = 13;  // vertices
  std::vector<glm::dvec2> v;
  glm::dvec2 at(int i, int j) const { return v[static_cast<std::size_t>(j * kCols + i)]; }
};

// A kCols x kRows grid over a W x H image whose outer ring lies `margin` px outside it, jittered
// by up to one pixel at 1/256 px resolution: a third of the vertices anywhere, a third on the
// 1/16 px grid (where every standard sample lies), a third on the half-pixel grid (pixel centres).
Grid jittered_grid(test::Rng& rng, int W, int H, double margin) {
  Grid g;
  for (int j = 0; j < Grid::kRows; ++j) {
    for (int i = 0; i < Grid::kCols; ++i) {
      auto coord = [&](int k, int n, int size) {
        if (k == 0) return -margin;
        if (k == n - 1) return size + margin;
        return static_cast<double>(k) * size / (n - 1);
      };
      glm::dvec2 p{coord(i, Grid::kCols, W), coord(j, Grid::kRows, H)};
      // Snap the base to the 1/2 px grid, then jitter.
      p = glm::floor(p * 2.0) / 2.0;
      for (int axis = 0; axis < 2; ++axis) {
        const std::int64_t step = rng.range(0, 2) == 0 ? 1 : rng.coin() ? 16 : 128;
        const std::int64_t j256 = rng.range(-256 / step, 256 / step) * step;
        p[axis] += static_cast<double>(j256) / 256.0;
      }
      g.v.push_back(p);
    }
  }
  return g;
}

// Two triangles per grid cell, random diagonal, random winding each, distinct colours; indexed,
// so that every triangle using a vertex reads the very same position.
Mesh grid_mesh(const Grid& g, test::Rng& rng, FillRule rule) {
  Mesh m = rule_mesh(rule);
  for (const glm::dvec2& p : g.v)
    m.positions.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y), 0.5f, 1.0f);
  std::uint32_t n = 0;
  auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (rng.coin()) std::swap(b, c);
    m.indices.insert(m.indices.end(), {a, b, c});
    m.colors.push_back(test::distinct_color(n++));
  };
  auto id = [](int i, int j) { return static_cast<std::uint32_t>(j * Grid::kCols + i); };
  for (int j = 0; j + 1 < Grid::kRows; ++j) {
    for (int i = 0; i + 1 < Grid::kCols; ++i) {
      const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (rng.coin()) {
        tri(a, b, c);
        tri(a, c, d);
      } else {
        tri(a, b, d);
        tri(b, c, d);
      }
    }
  }
  return m;
}

TEST(ReferenceWatertight, JitteredGridCoversEverySampleExactlyOnce) {
  constexpr int kW = 64, kH = 64;
  for (std::uint64_t seed : {41u, 42u}) {
    for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
      for (int samples : {1, 4, 16}) {
        test::Rng rng(seed);
        const Grid g = jittered_grid(rng, kW, kH, 2);
        const Mesh m = grid_mesh(g, rng, rule);
        RenderTarget t = test::sample_target(kW, kH, samples);
        const FrameStats s = test::render_reference(m, t);
        const std::size_t all = static_cast<std::size_t>(kW) * kH * samples;
        // Every triangle is drawn, or culled for covering no sample (a jittered cell's sliver).
        EXPECT_EQ(s.triangles_drawn + s.triangles_no_sample, 2u * 16 * 12);
        EXPECT_EQ(s.samples_written, all) << "seed " << seed << " samples " << samples;
        EXPECT_EQ(test::count_covered(t), all) << "seed " << seed << " samples " << samples;
      }
    }
  }
}

TEST(ReferenceWatertight, GridWithAFarOuterRingIsWatertight) {
  // The outer ring at 1e6 px and at 1e30 px: every border triangle is clipped by the guard band,
  // and the clipped shared edges must still meet exactly.
  constexpr int kW = 48, kH = 40;
  for (double margin : {1e6, 1e30}) {
    for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
      for (int samples : {1, 4}) {
        test::Rng rng(43);
        const Grid g = jittered_grid(rng, kW, kH, margin);
        const Mesh m = grid_mesh(g, rng, rule);
        RenderTarget t = test::sample_target(kW, kH, samples);
        const FrameStats s = test::render_reference(m, t);
        const std::size_t all = static_cast<std::size_t>(kW) * kH * samples;
        EXPECT_GT(s.triangles_clipped, 0u);
        EXPECT_EQ(s.samples_written, all) << "margin " << margin;
        EXPECT_EQ(test::count_covered(t), all) << "margin " << margin;
      }
    }
  }
}

TEST(ReferenceWatertight, ClipSpaceGridWithPerspectiveIsWatertight) {
  // The same triangulation given in clip space with a random w per vertex: the perspective
  // divide rounds each vertex once, the same way in every triangle that uses it.
  constexpr int kW = 64, kH = 48;
  for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
    for (int samples : {1, 4}) {
      test::Rng rng(44);
      const Grid g = jittered_grid(rng, kW, kH, 2);
      Mesh m = grid_mesh(g, rng, rule);
      m.space = Space::kClip;
      for (glm::vec4& p : m.positions) {
        const float w = static_cast<float>(std::exp(rng.uniform(-3, 3)));
        const float ndc_x = p.x / kW * 2 - 1, ndc_y = 1 - p.y / kH * 2;
        p = glm::vec4(ndc_x * w, ndc_y * w, 0.5f * w, w);
      }
      RenderTarget t = test::sample_target(kW, kH, samples);
      const FrameStats s = test::render_reference(m, t);
      const std::size_t all = static_cast<std::size_t>(kW) * kH * samples;
      EXPECT_EQ(s.samples_written, all);
      EXPECT_EQ(test::count_covered(t), all);
    }
  }
}

}  // namespace
}  // namespace mosaic
