// Homogeneous clipping (front::clip_triangle) and what it does to rendered coverage: the near
// plane, triangles behind the eye, the guard band, and watertightness of clipped shared edges.
//
// Expected coverage comes from geometry worked out independently: a triangle clipped by hand
// with exactly representable intersection points, a ground plane whose visible part is the lower
// half of the image, and edge lines computed in double from the unclipped vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "front/clip.hpp"
#include "front/fixed_point.hpp"
#include "reference/reference.hpp"
#include "reference_test_util.hpp"

namespace mosaic {
namespace {

using test::Fx;

front::ClipVertex cv(double X, double Y, double Z, double W) {
  front::ClipVertex v;
  v.X = X;
  v.Y = Y;
  v.Z = Z;
  v.W = W;
  return v;
}

// --- clip_triangle on its own --------------------------------------------------------------------

TEST(FrontClip, InsideCulledAndClipped) {
  front::ClipPolygon out;
  // Wholly inside the viewport and depth range.
  EXPECT_EQ(
      front::clip_triangle({cv(1, 1, 0.5, 1), cv(9, 1, 0.5, 1), cv(1, 9, 0.5, 1)}, 16, 16, out),
      front::ClipResult::kInside);
  // Wholly beyond one side of the viewport (x > 16), or behind the near plane, or past the far one.
  EXPECT_EQ(
      front::clip_triangle({cv(17, 1, 0.5, 1), cv(30, 1, 0.5, 1), cv(20, 9, 0.5, 1)}, 16, 16, out),
      front::ClipResult::kCulled);
  EXPECT_EQ(
      front::clip_triangle({cv(1, 1, -0.5, 1), cv(9, 1, -0.1, 1), cv(1, 9, -2, 1)}, 16, 16, out),
      front::ClipResult::kCulled);
  EXPECT_EQ(front::clip_triangle({cv(1, 1, 1.5, 1), cv(9, 1, 1.1, 1), cv(1, 9, 2, 1)}, 16, 16, out),
            front::ClipResult::kCulled);
  // Crossing the near plane: z = -1 at the first vertex, +1 at the others, so both crossings
  // are at the midpoints of the two edges from the first vertex.
  ASSERT_EQ(front::clip_triangle({cv(0, 0, -1, 1), cv(8, 0, 1, 1), cv(0, 8, 1, 1)}, 16, 16, out),
            front::ClipResult::kClipped);
  ASSERT_EQ(out.count, 4);
  std::vector<std::array<double, 4>> got;
  for (int i = 0; i < out.count; ++i)
    got.push_back({out.v[i].X, out.v[i].Y, out.v[i].Z, out.v[i].W});
  std::sort(got.begin(), got.end());
  const std::vector<std::array<double, 4>> expect{
      {0, 4, 0, 1}, {0, 8, 1, 1}, {4, 0, 0, 1}, {8, 0, 1, 1}};
  EXPECT_EQ(got, expect);
}

// Distance in pixels from window point q to the line through a and b (both in pixels), measured
// from the end nearer to q so that a far end (1e30) does not swamp it with rounding.
double line_distance(glm::dvec2 a, glm::dvec2 b, glm::dvec2 q) {
  if (glm::length(b - q) < glm::length(a - q)) std::swap(a, b);
  const glm::dvec2 d = b - a;
  const double len = std::hypot(d.x, d.y);
  return std::abs((q.x - a.x) * (d.y / len) - (q.y - a.y) * (d.x / len));
}

// How far a clipped vertex may lie from its edge line: far below the 1/512 px snapping error,
// far above double rounding at guard-band magnitudes (~1e-11 px).
constexpr double kOnLine = 1.0 / 1024;

TEST(FrontClip, GuardBandCrossingsStayOnTheEdgeLines) {
  // One vertex near the viewport, two far away. Every vertex of the clipped polygon must be a
  // corner of the guard band or lie on one of the triangle's edge lines, to well within 1/1024 px,
  // whichever end of an edge is the far one.
  const double far_values[] = {1e6, 1e12, 1e30, 1e38};
  const glm::dvec2 directions[] = {{1, 0.3}, {-1, 0.3}, {0.3, -1}, {-1, -1}, {-0.2, 1}, {1, -1}};
  for (double r : far_values) {
    for (glm::dvec2 d : directions) {
      for (glm::dvec2 d2 : directions) {
        if (d == d2) continue;
        const std::array<glm::dvec2, 3> p{glm::dvec2{20.25, 30.5}, glm::dvec2{20, 30} + r * d,
                                          glm::dvec2{20, 30} + r * d2};
        std::array<front::ClipVertex, 3> in;
        for (int k = 0; k < 3; ++k) in[k] = cv(p[k].x, p[k].y, 0.5, 1);
        front::ClipPolygon out;
        const front::ClipResult res = front::clip_triangle(in, 64, 64, out);
        if (res == front::ClipResult::kCulled) continue;
        ASSERT_EQ(res, front::ClipResult::kClipped);
        for (int i = 0; i < out.count; ++i) {
          const glm::dvec2 q{out.v[i].X / out.v[i].W, out.v[i].Y / out.v[i].W};
          EXPECT_LE(std::max(std::abs(q.x), std::abs(q.y)), front::kGuardBandPx * (1 + 1e-12));
          // A corner of the guard band is a vertex of the clipped polygon too.
          if (std::abs(q.x) == front::kGuardBandPx && std::abs(q.y) == front::kGuardBandPx)
            continue;
          double nearest = 1e300;
          for (int e = 0; e < 3; ++e)
            nearest = std::min(nearest, line_distance(p[e], p[(e + 1) % 3], q));
          EXPECT_LT(nearest, kOnLine) << "r " << r << " d " << d.x << "," << d.y << " d2 " << d2.x
                                      << "," << d2.y << " vertex " << q.x << "," << q.y;
        }
      }
    }
  }
}

// Checks every set-up triangle of a frame against the 16.8 budget of front/fixed_point.hpp:
// snapped coordinates within the guard band, so edge coefficients within 2 * 2^15 * 256.
void expect_within_budget(const std::vector<glm::vec4>& positions, Space space) {
  constexpr std::int64_t kMaxCoefficient = std::int64_t{2} * front::kGuardBandPx * 256;
  Draw d;
  d.space = space;
  d.positions = positions;
  Frame f;
  f.draws = std::span<const Draw>(&d, 1);
  FrameStats stats;
  const std::vector<front::TriangleSetup> tris = reference::setup_frame(f, 24, 16, 0, stats);
  for (const front::TriangleSetup& t : tris) {
    for (const front::EdgeFunction& e : t.edge) {
      ASSERT_LE(std::abs(e.a), kMaxCoefficient);
      ASSERT_LE(std::abs(e.b), kMaxCoefficient);
    }
    ASSERT_LE(std::abs(t.x0), front::kGuardBandPx);
    ASSERT_LE(std::abs(t.y0), front::kGuardBandPx);
    ASSERT_TRUE(0 <= t.bx0 && t.bx0 < t.bx1 && t.bx1 <= 24 && 0 <= t.by0 && t.by0 < t.by1 &&
                t.by1 <= 16);
  }
}

TEST(FrontClip, HostileVerticesStayWithinTheFixedPointBudget) {
  // Found by fuzzing (screen space, whose w is not checked): w of -0 or ~1e-39 beside
  // coordinates near 1e38. Clipping only against the
  // planes the original vertices violated left a crossing point at y = -4e8 px, whose snap
  // overflowed int32.
  expect_within_budget({{9.79471229e+37f, -0.564283371f, 0.310376287f, -0.0f},
                        {-1.83992142e+38f, 738454.562f, -9071.94629f, 2690.12256f},
                        {-7368.23389f, 5479.78613f, 1.55987462e+29f, 6.52395685e+29f}},
                       Space::kScreen);
  expect_within_budget({{4.06893634e-40f, 5.58979366e-07f, 1.32157007e+38f, 6.02558965e+29f},
                        {-5.70514007e-39f, -0.0776310489f, 7.15457995e-32f, -6.48046029e-39f},
                        {-0.545946658f, 0.739517808f, -2.60911833e-31f, 902924.875f}},
                       Space::kScreen);
  // And a batch of random hostile ones in both spaces.
  test::Rng rng(73);
  const float magnitudes[] = {0.0f, 1e-38f, 1e-30f, 1e-6f, 0.5f,   1.0f,
                              3.0f, 1e4f,   1e6f,   1e30f, 3.4e38f};
  std::vector<glm::vec4> positions;
  for (int i = 0; i < 3 * 20000; ++i) {
    auto value = [&] {
      return static_cast<float>(magnitudes[rng.range(0, std::size(magnitudes) - 1)] *
                                rng.uniform(-1, 1));
    };
    positions.push_back({value(), value(), value(), value()});
  }
  expect_within_budget(positions, Space::kClip);
  expect_within_budget(positions, Space::kScreen);
}

// --- Near plane, rendered ------------------------------------------------------------------------

Mesh clip_mesh(const std::vector<glm::vec4>& positions, Rgba8 color = {200, 100, 50, 255}) {
  Mesh m;
  m.space = Space::kClip;
  m.positions = positions;
  m.color = color;
  m.state.depth_test = DepthTest::kAlways;
  return m;
}

TEST(FrontClipRender, NearPlaneCrossingMatchesTheHandClippedPolygon) {
  // Depth z = w - 1 puts the near plane at w = 1. V0 is behind the eye (w = -2, z = -3); V1 has
  // w = 4, z = 3 and V2 w = 2, z = 1, so the near plane cuts V0V1 at t = 1/2 and V0V2 at t = 3/4,
  // both at w = 1: the crossings are exact. In window-homogeneous units (X = (x + w) 32 on a 64 px
  // target) V0 = (-130, -150), V1 = (194, 161), V2 = (25.5, 73), so the visible quad is
  //   V1 / 4 = (48.5, 40.25), V2 / 2 = (12.75, 36.5),
  //   (3 V2 + V0) / 4 = (-13.375, 17.25), (V0 + V1) / 2 = (32, 5.5)   (pixels).
  const std::vector<glm::vec4> tri{
      {-2.0625f, 2.6875f, -3, -2}, {2.0625f, -1.03125f, 3, 4}, {-1.203125f, -0.28125f, 1, 2}};
  const std::array<Fx, 4> quad{test::snap_fx({48.5, 40.25}), test::snap_fx({12.75, 36.5}),
                               test::snap_fx({-13.375, 17.25}), test::snap_fx({32, 5.5})};
  for (int samples : {1, 4, 16}) {
    for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
      RenderTarget t = test::sample_target(64, 64, samples);
      Mesh m = clip_mesh(tri);
      m.state.fill_rule = rule;
      const FrameStats s = test::render_reference(m, t);
      EXPECT_EQ(s.triangles_clipped, 1u);
      EXPECT_EQ(s.triangles_drawn, 2u);
      std::size_t expected_count = 0;
      for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
          for (int k = 0; k < samples; ++k) {
            const bool expect = test::oracle_covers(quad, test::sample_fx(x, y, k, samples), rule);
            expected_count += expect;
            const std::size_t i = test::sample_index(t, x, y, k);
            ASSERT_EQ(!(t.sample_color()[i] == test::kClear), expect)
                << "sample " << x << "," << y << "/" << k;
            if (!expect) continue;
            // Depth z/w is affine on screen: 0 on the near-plane edge, 3/4 at V1, 1/2 at V2.
            const std::array<glm::dvec2, 3> p{glm::dvec2{48.5, 40.25}, glm::dvec2{12.75, 36.5},
                                              glm::dvec2{32, 5.5}};
            const std::array<double, 3> z{0.75, 0.5, 0.0};
            const glm::dvec2 q = test::sample_px(x, y, k, samples);
            EXPECT_NEAR(t.sample_depth()[i], test::plane_at(p, z, q),
                        2 * test::depth_tolerance(p, z, q));
          }
      EXPECT_EQ(s.samples_written, expected_count);
      EXPECT_GT(expected_count, 500u * samples);
    }
  }
}

TEST(FrontClipRender, GroundPlaneShowsExactlyTheLowerHalf) {
  // A ground plane y = -1 seen by an eye looking along +w (x_ndc = x / w, y_ndc = y / w, z = w -
  // 1): one huge triangle reaching 1e5 ahead and 1e6 behind the eye. The ground between the near
  // plane (w = 1, the bottom image edge) and w = 1e5 (1e-5 of the half-height below the horizon)
  // fills the image's width, so a sample is covered iff it lies below the horizon y = H / 2.
  const std::vector<glm::vec4> ground{
      {-1e6f, -1, 1e5f - 1, 1e5f}, {1e6f, -1, 1e5f - 1, 1e5f}, {0, -1, -1e6f - 1, -1e6f}};
  for (int samples : {1, 4}) {
    for (auto [W, H] : {std::pair{64, 64}, std::pair{40, 24}}) {
      RenderTarget t = test::sample_target(W, H, samples);
      const FrameStats s = test::render_reference(clip_mesh(ground), t);
      EXPECT_EQ(s.triangles_clipped, 1u);
      std::size_t covered = 0;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
          for (int k = 0; k < samples; ++k) {
            const bool expect = test::sample_px(x, y, k, samples).y > H / 2.0;
            const bool got = !(t.sample_color()[test::sample_index(t, x, y, k)] == test::kClear);
            covered += got;
            ASSERT_EQ(got, expect) << W << "x" << H << " sample " << x << "," << y << "/" << k;
          }
      EXPECT_EQ(s.samples_written, covered);
    }
  }
}

TEST(FrontClipRender, TrianglesBehindTheEyeOrBeforeTheNearPlaneAreCulled) {
  // Each of these would land on screen if x / w, y / w were used without clipping.
  const std::vector<std::vector<glm::vec4>> cases{
      // Entirely behind the eye (w < 0): x / w etc. lie in the middle of the image.
      {{-0.5f, -0.5f, -3, -2}, {0.5f, -0.5f, -3, -2}, {0, 0.5f, -3, -2}},
      // w from -1 to -4, z = w - 1.
      {{-0.5f, -0.5f, -2, -1}, {2, -1, -5, -4}, {0, 1, -3, -2}},
      // In front of the eye but before the near plane (0 < w < 1, z = w - 1 < 0).
      {{-0.25f, -0.25f, -0.5f, 0.5f}, {0.25f, -0.25f, -0.5f, 0.5f}, {0, 0.25f, -0.75f, 0.25f}},
      // Beyond the far plane (z > w).
      {{-0.5f, -0.5f, 2.5f, 2}, {0.5f, -0.5f, 2.5f, 2}, {0, 0.5f, 2.5f, 2}},
  };
  for (const auto& tri : cases) {
    RenderTarget t = test::sample_target(32, 32, 4);
    const FrameStats s = test::render_reference(clip_mesh(tri), t);
    EXPECT_EQ(s.triangles_in, 1u);
    EXPECT_EQ(s.triangles_outside, 1u);
    EXPECT_EQ(s.triangles_drawn, 0u);
    EXPECT_EQ(s.samples_written, 0u);
    EXPECT_EQ(test::count_covered(t), 0u);
  }
}

// True when, on every line of samples (one sample index, one pixel row or column), the covered
// samples form one unbroken run: what a convex shape covers, and what a crack breaks.
::testing::AssertionResult runs_are_unbroken(const RenderTarget& t) {
  const std::vector<bool> cov = test::covered_samples(t);
  for (int s = 0; s < t.samples(); ++s) {
    for (int y = 0; y < t.height(); ++y) {
      int runs = 0;
      bool prev = false;
      for (int x = 0; x < t.width(); ++x) {
        const bool c = cov[test::sample_index(t, x, y, s)];
        runs += c && !prev;
        prev = c;
      }
      if (runs > 1) return ::testing::AssertionFailure() << "row " << y << " sample " << s;
    }
    for (int x = 0; x < t.width(); ++x) {
      int runs = 0;
      bool prev = false;
      for (int y = 0; y < t.height(); ++y) {
        const bool c = cov[test::sample_index(t, x, y, s)];
        runs += c && !prev;
        prev = c;
      }
      if (runs > 1) return ::testing::AssertionFailure() << "column " << x << " sample " << s;
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(FrontClipRender, SharedEdgeAcrossTheNearPlaneIsWatertight) {
  // Convex quads P, R1, Q, R2 on a ground plane y = -h (z = w - 1), split along the diagonal PQ
  // with P in front of the near plane and Q behind it (half the time behind the eye). Their visible
  // part is convex on screen, so a crack shows as a broken run of samples, and an overlap as more
  // writes than covered samples.
  test::Rng rng(21);
  auto log_uniform = [&](double lo, double hi) {
    return std::exp(rng.uniform(std::log(lo), std::log(hi)));
  };
  int clipped_pairs = 0, seen = 0;
  for (int i = 0; i < 160; ++i) {
    const double h = rng.uniform(0.3, 3) * (rng.coin() ? 1 : -1);
    // Ground coordinates (lateral x, distance d). P ahead of the near plane d = 1; Q between the
    // eye and the near plane or behind the eye.
    const glm::dvec2 P{rng.uniform(-3, 3), rng.uniform(1.05, 20)};
    const glm::dvec2 Q{log_uniform(0.1, 1e3) * (rng.coin() ? 1 : -1),
                       i % 2 ? rng.uniform(0.05, 0.95) : -log_uniform(0.1, 1e3)};
    // R1 and R2 on opposite sides of PQ, on a line crossing PQ between P and Q: a convex quad.
    const glm::dvec2 M = P + rng.uniform(0.1, 0.9) * (Q - P);
    const glm::dvec2 n = glm::dvec2{P.y - Q.y, Q.x - P.x} / glm::length(Q - P);
    const glm::dvec2 R1 = M + log_uniform(0.3, 1e4) * n, R2 = M - log_uniform(0.3, 1e4) * n;
    auto ground = [&](glm::dvec2 g) {
      return glm::vec4(static_cast<float>(g.x), static_cast<float>(-h), static_cast<float>(g.y - 1),
                       static_cast<float>(g.y));
    };
    std::vector<glm::vec4> t1{ground(P), ground(R1), ground(Q)};
    std::vector<glm::vec4> t2{ground(Q), ground(R2), ground(P)};
    if (rng.coin()) std::swap(t1[1], t1[2]);
    if (rng.coin()) std::swap(t2[1], t2[2]);
    for (int samples : {1, 4}) {
      for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
        Mesh m1 = clip_mesh(t1, {255, 0, 0, 255}), m2 = clip_mesh(t2, {0, 255, 0, 255});
        m1.state.fill_rule = m2.state.fill_rule = rule;
        RenderTarget t = test::sample_target(32, 24, samples);
        const FrameStats s = test::render_reference({m1, m2}, t);
        const std::size_t covered = test::count_covered(t);
        ASSERT_EQ(s.samples_written, covered) << "case " << i << ": a sample was covered twice";
        ASSERT_TRUE(runs_are_unbroken(t)) << "case " << i << " samples " << samples;
        clipped_pairs += s.triangles_clipped == 2;
        seen += covered > 0;
      }
    }
  }
  EXPECT_GT(clipped_pairs, 400);
  EXPECT_GT(seen, 400);
}

// Depth error allowed where depths are below 1 and slopes 1/32 per px: a few float32 roundings.
constexpr double kDepthTolerance = 1e-6;

TEST(FrontClipRender, DepthOutsideZeroToOneIsClippedAway) {
  // A screen-space rectangle whose depth runs from -0.5 at x = 0 to 1.5 at x = 64: only the
  // band 16 <= x <= 48 lies within [0, 1], where the depth is (x - 16) / 32. Both clipped edges
  // fall on whole pixels, between samples.
  for (int samples : {1, 4}) {
    Mesh m = test::screen_mesh();
    m.positions = {{0, 2, -0.5f, 1}, {64, 2, 1.5f, 1},  {64, 30, 1.5f, 1},
                   {0, 2, -0.5f, 1}, {64, 30, 1.5f, 1}, {0, 30, -0.5f, 1}};
    m.colors = {{255, 0, 0, 255}, {255, 0, 0, 255}};
    m.state.depth_test = DepthTest::kAlways;
    RenderTarget t = test::sample_target(64, 32, samples);
    const FrameStats s = test::render_reference(m, t);
    EXPECT_EQ(s.triangles_clipped, 2u);
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 64; ++x)
        for (int k = 0; k < samples; ++k) {
          const glm::dvec2 q = test::sample_px(x, y, k, samples);
          const bool expect = q.x > 16 && q.x < 48 && q.y > 2 && q.y < 30;
          const std::size_t i = test::sample_index(t, x, y, k);
          ASSERT_EQ(!(t.sample_color()[i] == test::kClear), expect) << x << "," << y << "/" << k;
          if (expect) {
            EXPECT_NEAR(t.sample_depth()[i], (q.x - 16) / 32, kDepthTolerance);
          }
        }
  }
}

// --- Guard band, rendered ------------------------------------------------------------------------

// Signed distance (px) from q to the line through a and b, positive on the side of `inside`,
// measured from the end nearer to q.
double side_distance(glm::dvec2 a, glm::dvec2 b, glm::dvec2 inside, glm::dvec2 q) {
  if (glm::length(b - q) < glm::length(a - q)) std::swap(a, b);
  const glm::dvec2 d = b - a;
  const double len = std::hypot(d.x, d.y);
  auto cross = [&](glm::dvec2 p) {
    return ((p.x - a.x) * (d.y / len) - (p.y - a.y) * (d.x / len));
  };
  return cross(inside) > 0 ? cross(q) : -cross(q);
}

TEST(FrontClipRender, GuardBandClipsFarVerticesWithoutWrapping) {
  // V0 and V1 straddle the image centre across the direction d; V2 = C + R d is far away. In the
  // image the triangle is the strip between the lines V0V2 and V1V2. Samples farther than 1/128 px
  // from every edge line must be covered iff inside (snapping moves edges by less than that), and
  // must agree with the same strip drawn as a quad whose far end is cut at ~1e4 px.
  constexpr double kMargin = 1.0 / 128;
  const glm::dvec2 centre{32.3, 31.7};
  const glm::dvec2 directions[] = {{1, 0},   {0, 1},     {-1, 0.3}, {0.3, -1},
                                   {-1, -1}, {1, -0.45}, {-0.6, 1}, {0.9, 1}};
  int checked = 0;
  for (double R : {1e6, 1e30}) {
    for (glm::dvec2 d : directions) {
      d /= std::hypot(d.x, d.y);
      const glm::dvec2 n{-d.y, d.x};
      const glm::dvec2 v0 = test::fx_to_px(test::snap_fx(centre + 11.0 * n));
      const glm::dvec2 v1 = test::fx_to_px(test::snap_fx(centre - 13.0 * n + 5.0 * d));
      const glm::vec2 v2f(centre + R * d);  // as the float positions hold it
      const glm::dvec2 v2(v2f);
      // The near replacement: the far vertex slid back along each edge line to ~1e4 px.
      const glm::dvec2 p0 = v0 + (v2 - v0) * (1e4 / glm::length(v2 - v0));
      const glm::dvec2 p1 = v1 + (v2 - v1) * (1e4 / glm::length(v2 - v1));
      for (int samples : {1, 4}) {
        RenderTarget far_t = test::sample_target(64, 64, samples);
        RenderTarget near_t = test::sample_target(64, 64, samples);
        Mesh far_m = test::screen_mesh(), near_m = test::screen_mesh();
        test::add_tri(far_m, v0, v1, v2, {255, 255, 255, 255});
        test::add_tri(near_m, v0, v1, p1, {255, 255, 255, 255});
        test::add_tri(near_m, v0, p1, p0, {255, 255, 255, 255});
        const FrameStats fs = test::render_reference(far_m, far_t);
        test::render_reference(near_m, near_t);
        EXPECT_EQ(fs.triangles_clipped, 1u);
        const glm::dvec2 inside = (v0 + v1) / 2.0 + d;  // a point inside the strip
        for (int y = 0; y < 64; ++y) {
          for (int x = 0; x < 64; ++x) {
            for (int k = 0; k < samples; ++k) {
              const glm::dvec2 q = test::sample_px(x, y, k, samples);
              const double e0 = side_distance(v0, v1, inside, q);
              const double e1 = side_distance(v1, v2, inside, q);
              const double e2 = side_distance(v2, v0, inside, q);
              const double m = std::min({e0, e1, e2});
              if (std::abs(e0) < kMargin || std::abs(e1) < kMargin || std::abs(e2) < kMargin)
                continue;
              const std::size_t i = test::sample_index(far_t, x, y, k);
              const bool got = !(far_t.sample_color()[i] == test::kClear);
              ASSERT_EQ(got, m > 0) << "R " << R << " d " << d.x << "," << d.y << " sample " << x
                                    << "," << y << "/" << k;
              ASSERT_EQ(got, !(near_t.sample_color()[i] == test::kClear));
              ++checked;
            }
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 50000);
}

TEST(FrontClipRender, HugeTrianglesCoverTheWholeImageExactlyOnce) {
  for (double R : {1e6, 1e30}) {
    for (int samples : {1, 4}) {
      RenderTarget t = test::sample_target(48, 40, samples);
      Mesh m = test::screen_mesh();
      // Two triangles sharing the diagonal of a square reaching R beyond every side.
      test::add_tri(m, {-R, -R}, {R, -R}, {R, R}, {255, 0, 0, 255});
      test::add_tri(m, {-R, -R}, {-R, R}, {R, R}, {0, 255, 0, 255});
      m.state.depth_test = DepthTest::kAlways;
      const FrameStats s = test::render_reference(m, t);
      EXPECT_EQ(s.samples_written, 48u * 40u * samples) << R;
      EXPECT_EQ(test::count_covered(t), 48u * 40u * samples) << R;
    }
  }
}

}  // namespace
}  // namespace mosaic
