// Depth and colour in the reference rasterizer: per-sample depth against a double-precision
// plane through the snapped vertices, the depth test modes and their ties, perspective-correct
// colour against homogeneous barycentrics, MSAA and SSAA shading positions, and the painter's
// algorithm against the z-buffer.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "reference_test_util.hpp"

namespace mosaic {
namespace {

using test::Fx;

// Depths closer than this are a near-tie that float32 planes may decide either way (their error
// is ~1e-7 here); such samples are skipped rather than guessed.
constexpr double kDepthTieMargin = 1e-5;

bool covered(const RenderTarget& t, int x, int y, int s) {
  return !(t.sample_color()[test::sample_index(t, x, y, s)] == test::kClear);
}

// --- Depth values --------------------------------------------------------------------------------

TEST(ReferenceDepth, SampleDepthIsThePlaneThroughTheSnappedVertices) {
  // Random triangles with vertices off the 1/256 grid; the expected plane goes through the
  // vertices as snapped by the specification (round to nearest), evaluated in double.
  test::Rng rng(51);
  int checked = 0;
  for (int i = 0; i < 40; ++i) {
    std::array<glm::dvec2, 3> raw, snapped;
    std::array<Fx, 3> fx;
    std::array<double, 3> z;
    for (int k = 0; k < 3; ++k) {
      raw[k] = {rng.uniform(-8, 40), rng.uniform(-8, 40)};
      fx[k] = test::snap_fx(raw[k]);
      snapped[k] = test::fx_to_px(fx[k]);
      z[k] = static_cast<float>(rng.uniform(0.05, 0.95));
    }
    const double area2 = std::abs((snapped[1].x - snapped[0].x) * (snapped[2].y - snapped[0].y) -
                                  (snapped[2].x - snapped[0].x) * (snapped[1].y - snapped[0].y));
    if (area2 < 100) continue;  // slivers: steep planes, see depth_tolerance
    DrawState st;
    st.depth_test = DepthTest::kAlways;
    Mesh m = test::screen_mesh(st);
    for (int k = 0; k < 3; ++k)
      m.positions.emplace_back(static_cast<float>(raw[k].x), static_cast<float>(raw[k].y),
                               static_cast<float>(z[k]), 1.0f);
    m.colors.push_back({255, 255, 255, 255});
    // raw[] went through float: snap what the engine was given.
    for (int k = 0; k < 3; ++k) {
      fx[k] = test::snap_fx(glm::dvec2(m.positions[k].x, m.positions[k].y));
      snapped[k] = test::fx_to_px(fx[k]);
    }
    RenderTarget t = test::sample_target(32, 32, 4);
    test::render_reference(m, t);
    const double zmin = std::min({z[0], z[1], z[2]}), zmax = std::max({z[0], z[1], z[2]});
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x)
        for (int k = 0; k < 4; ++k) {
          const std::size_t idx = test::sample_index(t, x, y, k);
          if (!test::oracle_covers(fx, test::sample_fx(x, y, k, 4), FillRule::kD3D)) {
            EXPECT_EQ(t.sample_depth()[idx], 1.0f);  // the clear depth
            continue;
          }
          const glm::dvec2 q = test::sample_px(x, y, k, 4);
          const double expect = std::clamp(test::plane_at(snapped, z, q), zmin, zmax);
          EXPECT_NEAR(t.sample_depth()[idx], expect, test::depth_tolerance(snapped, z, q))
              << x << "," << y << "/" << k;
          ++checked;
        }
  }
  EXPECT_GT(checked, 5000);
}

TEST(ReferenceDepth, ClipSpaceDepthIsZOverWInterpolatedOnScreen) {
  // Vertices with w = 1, 2, 4 and z/w = 0.2, 0.9, 0.5: z/w is affine in window coordinates, so
  // the expected depth is the plane through the projected vertices and their z/w.
  const std::array<glm::dvec4, 3> ndc{glm::dvec4{-0.8125, -0.75, 0.2, 1},
                                      glm::dvec4{0.875, -0.5, 0.9, 2},
                                      glm::dvec4{-0.25, 0.9375, 0.5, 4}};
  Mesh m;
  m.space = Space::kClip;
  m.state.depth_test = DepthTest::kAlways;
  std::array<glm::dvec2, 3> p;
  std::array<double, 3> z;
  for (int k = 0; k < 3; ++k) {
    const double w = ndc[k].w;
    m.positions.emplace_back(static_cast<float>(ndc[k].x * w), static_cast<float>(ndc[k].y * w),
                             static_cast<float>(ndc[k].z * w), static_cast<float>(w));
    p[k] = {(ndc[k].x + 1) * 32, (1 - ndc[k].y) * 32};  // exact: multiples of 1/16 px
    z[k] = static_cast<float>(ndc[k].z);
  }
  RenderTarget t = test::sample_target(64, 64, 4);
  test::render_reference(m, t);
  int checked = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int k = 0; k < 4; ++k) {
        if (!covered(t, x, y, k)) continue;
        const glm::dvec2 q = test::sample_px(x, y, k, 4);
        const double expect = std::clamp(test::plane_at(p, z, q), 0.2, 0.9);
        EXPECT_NEAR(t.sample_depth()[test::sample_index(t, x, y, k)], expect,
                    test::depth_tolerance(p, z, q));
        ++checked;
      }
  EXPECT_GT(checked, 3000);
}

// --- Depth test modes ----------------------------------------------------------------------------

// Full-target quad at one depth in one colour.
Mesh flat_quad(float z, Rgba8 color, DepthTest test, bool write = true) {
  DrawState st;
  st.depth_test = test;
  st.depth_write = write;
  Mesh m = test::screen_mesh(st);
  test::add_tri(m, {-1, -1}, {17, -1}, {17, 17}, color, z);
  test::add_tri(m, {-1, -1}, {17, 17}, {-1, 17}, color, z);
  return m;
}

TEST(ReferenceDepth, DepthTestModesAndTies) {
  const Rgba8 A{255, 0, 0, 255}, B{0, 0, 255, 255};
  struct Case {
    const char* name;
    DepthTest test;
    float clear, za, zb;
    bool a_writes;
    Rgba8 expect;         // colour of every sample after A then B
    unsigned writes_per;  // colour writes per sample
  };
  const Rgba8 clear = test::kClear;
  const Case cases[] = {
      {"less tie: first wins", DepthTest::kLess, 1, 0.5f, 0.5f, true, A, 1},
      {"less nearer", DepthTest::kLess, 1, 0.5f, 0.4f, true, B, 2},
      {"less farther", DepthTest::kLess, 1, 0.5f, 0.6f, true, A, 1},
      {"less-equal tie: last wins", DepthTest::kLessEqual, 1, 0.5f, 0.5f, true, B, 2},
      {"less-equal farther", DepthTest::kLessEqual, 1, 0.5f, 0.6f, true, A, 1},
      {"greater tie", DepthTest::kGreater, 0, 0.5f, 0.5f, true, A, 1},
      {"greater nearer (reversed z)", DepthTest::kGreater, 0, 0.5f, 0.6f, true, B, 2},
      {"greater farther", DepthTest::kGreater, 0, 0.5f, 0.4f, true, A, 1},
      {"greater-equal tie", DepthTest::kGreaterEqual, 0, 0.5f, 0.5f, true, B, 2},
      {"always ignores depth", DepthTest::kAlways, 1, 0.2f, 0.9f, true, B, 2},
      {"less against the clear depth", DepthTest::kLess, 0.3f, 0.5f, 0.5f, true, clear, 0},
      {"less, clear depth equal: fails", DepthTest::kLess, 0.5f, 0.5f, 0.5f, true, clear, 0},
      {"less-equal, clear depth equal: passes", DepthTest::kLessEqual, 0.5f, 0.5f, 0.5f, true, B,
       2},
      {"no depth write: B tests against the clear", DepthTest::kLess, 1, 0.5f, 0.6f, false, B, 2},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    for (int samples : {1, 4}) {
      RenderTarget t = test::sample_target(16, 16, samples);
      t.set_clear(test::kClear, c.clear);
      const FrameStats s = test::render_reference(
          {flat_quad(c.za, A, c.test, c.a_writes), flat_quad(c.zb, B, c.test)}, t);
      const std::size_t n = 16u * 16u * samples;
      EXPECT_EQ(s.samples_tested, 2 * n);
      EXPECT_EQ(s.samples_written, c.writes_per * n);
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(t.sample_color()[i], c.expect) << i;
      for (const Rgba8& px : t.color()) ASSERT_EQ(px, c.expect);
    }
  }
}

TEST(ReferenceDepth, SlopedTriangleAgainstAFlatOneSplitsWhereTheDepthsCross) {
  // A: depth 0 at x = -1 rising to 1 at x = 33 (constant in y); B: depth 0.5. With "less", A is
  // in front where its depth is below 0.5, i.e. left of x = 16; with "greater" (clear 0), right.
  for (DepthTest dt : {DepthTest::kLess, DepthTest::kGreater}) {
    for (int samples : {1, 4, 16}) {
      DrawState st;
      st.depth_test = dt;
      Mesh a = test::screen_mesh(st), b = test::screen_mesh(st);
      a.positions = {{-1, -1, 0, 1}, {33, -1, 1, 1}, {33, 33, 1, 1},
                     {-1, -1, 0, 1}, {33, 33, 1, 1}, {-1, 33, 0, 1}};
      a.colors = {{255, 0, 0, 255}, {255, 0, 0, 255}};
      test::add_tri(b, {-1, -1}, {33, -1}, {33, 33}, {0, 0, 255, 255}, 0.5f);
      test::add_tri(b, {-1, -1}, {33, 33}, {-1, 33}, {0, 0, 255, 255}, 0.5f);
      RenderTarget t = test::sample_target(32, 32, samples);
      t.set_clear(test::kClear, dt == DepthTest::kLess ? 1.0f : 0.0f);
      test::render_reference({b, a}, t);
      for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
          for (int k = 0; k < samples; ++k) {
            const double sx = test::sample_px(x, y, k, samples).x;
            const double za = (sx + 1) / 34;
            if (std::abs(za - 0.5) < kDepthTieMargin) continue;
            const bool a_wins = dt == DepthTest::kLess ? za < 0.5 : za > 0.5;
            EXPECT_EQ(t.sample_color()[test::sample_index(t, x, y, k)].r, a_wins ? 255 : 0)
                << x << "," << y << "/" << k;
          }
    }
  }
}

// --- Colour --------------------------------------------------------------------------------------

struct ColorTri {
  std::array<glm::dvec4, 3> clip;
  std::array<Rgba8, 3> color;
};

Mesh color_mesh(const ColorTri& c) {
  Mesh m;
  m.space = Space::kClip;
  m.color_source = ColorSource::kPerVertex;
  m.state.depth_test = DepthTest::kAlways;
  for (int k = 0; k < 3; ++k) {
    m.positions.emplace_back(static_cast<float>(c.clip[k].x), static_cast<float>(c.clip[k].y),
                             static_cast<float>(c.clip[k].z), static_cast<float>(c.clip[k].w));
    m.colors.push_back(c.color[k]);
  }
  return m;
}

// The perspective-correct colour channel `ch` at pixel position p, from homogeneous barycentrics.
double expected_channel(const ColorTri& c, int W, int H, glm::dvec2 p, int ch) {
  const auto b = test::homogeneous_barycentrics(c.clip, W, H, p);
  double v = 0;
  for (int k = 0; k < 3; ++k) {
    const Rgba8 col = c.color[k];
    const std::uint8_t chan[4] = {col.r, col.g, col.b, col.a};
    v += b[k] * chan[ch];
  }
  return v;
}

std::array<int, 4> channels(Rgba8 c) { return {c.r, c.g, c.b, c.a}; }

// The same channel interpolated linearly in screen space (what a renderer without perspective
// correction would produce), to show that the scenes tell the two apart.
double affine_channel(const ColorTri& c, int W, int H, glm::dvec2 p, int ch) {
  std::array<glm::dvec2, 3> s;
  std::array<double, 3> f;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 h = test::window_homogeneous(c.clip[k], W, H);
    s[k] = {h.x / h.z, h.y / h.z};
    f[k] = channels(c.color[k])[ch];
  }
  return test::plane_at(s, f, p);
}

// Clip-space triangles: different w, some crossing the near plane (z = w - 0.5 there).
std::vector<ColorTri> color_cases() {
  auto at = [](double x, double y, double w, double z_ndc) {
    return glm::dvec4{x * w, y * w, z_ndc * w, w};
  };
  return {
      // w = 1, 3, 7 in view.
      {{at(-0.9, -0.8, 1, 0.5), at(0.85, -0.6, 3, 0.5), at(-0.1, 0.9, 7, 0.5)},
       {Rgba8{255, 0, 0, 255}, Rgba8{0, 255, 0, 128}, Rgba8{0, 0, 255, 0}}},
      // A strongly receding one.
      {{at(-0.95, 0.95, 0.5, 0.2), at(0.95, 0.9, 0.6, 0.2), at(0.1, -0.95, 12, 0.2)},
       {Rgba8{10, 250, 30, 255}, Rgba8{240, 20, 200, 255}, Rgba8{128, 128, 0, 255}}},
      // Crossing the near plane: the first vertex is behind the eye (w = -1, z = w - 0.5).
      {{glm::dvec4{0.3, 2, -1.5, -1}, glm::dvec4{-1.5, -1, 1.5, 2}, glm::dvec4{2, -0.5, 2.5, 3}},
       {Rgba8{255, 255, 0, 255}, Rgba8{0, 40, 255, 255}, Rgba8{200, 0, 90, 255}}},
  };
}

TEST(ReferenceColor, PixelCentreColourIsPerspectiveCorrect) {
  int checked = 0;
  double max_affine_gap = 0;
  for (const ColorTri& c : color_cases()) {
    RenderTarget t = test::sample_target(64, 64, 1);
    test::render_reference(color_mesh(c), t);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        if (!covered(t, x, y, 0)) continue;
        const glm::dvec2 p{x + 0.5, y + 0.5};
        const auto got = channels(t.sample_color()[test::sample_index(t, x, y, 0)]);
        for (int ch = 0; ch < 4; ++ch) {
          const double e = expected_channel(c, 64, 64, p, ch);
          EXPECT_LE(std::abs(got[ch] - e), 1.0) << x << "," << y << " channel " << ch;
          if (c.clip[0].w > 0)
            max_affine_gap =
                std::max(max_affine_gap, std::abs(affine_channel(c, 64, 64, p, ch) - e));
        }
        ++checked;
      }
    EXPECT_EQ(test::count_covered(t) > 100, true);
  }
  EXPECT_GT(checked, 1500);
  EXPECT_GT(max_affine_gap, 20.0);  // the scenes do tell perspective from affine
}

TEST(ReferenceColor, EqualWIsAffineInScreenSpace) {
  // Screen-space vertices (w = 1): colour is the plane through the vertex colours.
  Mesh m = test::screen_mesh();
  m.color_source = ColorSource::kPerVertex;
  m.positions = {{2.25, 3.5, 0.5, 1}, {60.75, 10, 0.5, 1}, {20, 61.125, 0.5, 1}};
  m.colors = {{0, 100, 255, 255}, {255, 0, 50, 255}, {30, 200, 0, 255}};
  RenderTarget t = test::sample_target(64, 64, 1);
  test::render_reference(m, t);
  const std::array<glm::dvec2, 3> p{glm::dvec2{2.25, 3.5}, glm::dvec2{60.75, 10},
                                    glm::dvec2{20, 61.125}};
  int checked = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (!covered(t, x, y, 0)) continue;
      const auto got = channels(t.sample_color()[test::sample_index(t, x, y, 0)]);
      for (int ch = 0; ch < 4; ++ch) {
        std::array<double, 3> f;
        for (int k = 0; k < 3; ++k) f[k] = channels(m.colors[k])[ch];
        EXPECT_LE(std::abs(got[ch] - test::plane_at(p, f, {x + 0.5, y + 0.5})), 1.0);
      }
      ++checked;
    }
  EXPECT_GT(checked, 1000);
}

TEST(ReferenceColor, MsaaShadesAtThePixelCentreSsaaAtEachSample) {
  for (bool ssaa : {false, true}) {
    const ColorTri c = color_cases()[0];
    RenderTarget t = test::sample_target(64, 64, 4);
    test::FrameOptions fo;
    fo.ssaa = ssaa;
    test::render_reference(color_mesh(c), t, fo);
    int checked = 0, differing = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        // Pixels whose four samples are all covered, so that the centre is inside too and no
        // extrapolation is involved.
        bool all = true;
        for (int k = 0; k < 4; ++k) all = all && covered(t, x, y, k);
        if (!all) continue;
        for (int k = 0; k < 4; ++k) {
          const glm::dvec2 at = ssaa ? test::sample_px(x, y, k, 4) : glm::dvec2{x + 0.5, y + 0.5};
          const auto got = channels(t.sample_color()[test::sample_index(t, x, y, k)]);
          for (int ch = 0; ch < 4; ++ch)
            EXPECT_LE(std::abs(got[ch] - expected_channel(c, 64, 64, at, ch)), 1.0)
                << (ssaa ? "ssaa " : "msaa ") << x << "," << y << "/" << k;
          differing += !(t.sample_color()[test::sample_index(t, x, y, k)] ==
                         t.sample_color()[test::sample_index(t, x, y, 0)]);
        }
        ++checked;
      }
    EXPECT_GT(checked, 500);
    // MSAA: one colour per pixel; SSAA: the samples of a pixel differ somewhere.
    if (ssaa)
      EXPECT_GT(differing, 100);
    else
      EXPECT_EQ(differing, 0);
  }
}

// --- Painter's algorithm -------------------------------------------------------------------------

TEST(ReferencePainter, InterpenetratingTrianglesZBufferVersusPainter) {
  // A: depth 0.1 at x = 2 rising to 0.7 at x = 62 (mean vertex depth 0.3).
  // B: depth 0.8 at x = 2 falling to 0.2 at x = 62 (mean 0.4).
  // They cross at x = 37. The z-buffer shows the nearer one per pixel; the painter draws B (the
  // farther mean) first and A over it, whatever the submission order (A is submitted first).
  DrawState st;  // kLess, depth write on
  Mesh a = test::screen_mesh(st), b = test::screen_mesh(st);
  const Rgba8 ca{255, 0, 0, 255}, cb{0, 0, 255, 255};
  a.positions = {{2, 2, 0.1f, 1}, {62, 2, 0.7f, 1}, {2, 62, 0.1f, 1}};
  a.colors = {ca};
  b.positions = {{2, 2, 0.8f, 1}, {62, 2, 0.2f, 1}, {62, 62, 0.2f, 1}};
  b.colors = {cb};
  const std::array<Fx, 3> fa{test::snap_fx({2, 2}), test::snap_fx({62, 2}), test::snap_fx({2, 62})};
  const std::array<Fx, 3> fb{test::snap_fx({2, 2}), test::snap_fx({62, 2}),
                             test::snap_fx({62, 62})};
  RenderTarget z = test::sample_target(64, 64, 1), painter = test::sample_target(64, 64, 1);
  test::render_reference({a, b}, z);
  test::FrameOptions fo;
  fo.painter = true;
  const FrameStats ps = test::render_reference({a, b}, painter, fo);
  int differ = 0, checked = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const Fx q = test::sample_fx(x, y, 0, 1);
      const bool in_a = test::oracle_covers(fa, q, FillRule::kD3D);
      const bool in_b = test::oracle_covers(fb, q, FillRule::kD3D);
      const double sx = x + 0.5;
      const double za = 0.1 + 0.6 * (sx - 2) / 60, zb = 0.8 - 0.6 * (sx - 2) / 60;
      const Rgba8 got_z = z.pixel(x, y), got_p = painter.pixel(x, y);
      const Rgba8 expect_p = in_a ? ca : in_b ? cb : test::kClear;
      EXPECT_EQ(got_p, expect_p) << x << "," << y;
      if (!(in_a && in_b && std::abs(za - zb) < kDepthTieMargin)) {
        const Rgba8 expect_z = in_a && in_b ? (za < zb ? ca : cb) : expect_p;
        EXPECT_EQ(got_z, expect_z) << x << "," << y;
        ++checked;
      }
      differ += !(got_z == got_p);
    }
  EXPECT_GT(checked, 3000);
  EXPECT_GT(differ, 100);  // B in front right of x = 37, where the painter shows A
  EXPECT_EQ(ps.triangles_drawn, 2u);
}

TEST(ReferencePainter, CyclicOverlapHasNoCorrectPainterOrder) {
  // Three long triangles around the corners p0, p1, p2: triangle i has its base (depth 0.2) just
  // before p_i and its apex (depth 0.8) well past p_(i+1). At p_(i+1) it lies under triangle
  // i+1's base end: depth ~0.61 against ~0.24. The three "under" relations form a cycle, so no
  // order of whole triangles is right everywhere: the painter must get at least one corner wrong,
  // while the z-buffer shows triangle i at p_i.
  const std::array<glm::dvec2, 3> corner{glm::dvec2{10, 12}, glm::dvec2{54, 14},
                                         glm::dvec2{30, 54}};
  const std::array<Rgba8, 3> colour{Rgba8{255, 0, 0, 255}, Rgba8{0, 255, 0, 255},
                                    Rgba8{0, 0, 255, 255}};
  std::vector<Mesh> tris;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec2 from = corner[i], to = corner[(i + 1) % 3];
    const glm::dvec2 d = to - from;
    const glm::dvec2 n = glm::dvec2{-d.y, d.x} * (10.0 / glm::length(d));
    const glm::dvec2 base = from - 0.1 * d, apex = to + 0.5 * d;
    Mesh m = test::screen_mesh();
    m.positions = {glm::vec4(glm::vec2(base + n), 0.2f, 1), glm::vec4(glm::vec2(base - n), 0.2f, 1),
                   glm::vec4(glm::vec2(apex), 0.8f, 1)};
    m.colors = {colour[i]};
    tris.push_back(m);
  }
  RenderTarget z = test::sample_target(64, 64, 1), painter = test::sample_target(64, 64, 1);
  test::render_reference(tris, z);
  test::FrameOptions fo;
  fo.painter = true;
  test::render_reference(tris, painter, fo);
  int painter_wrong = 0;
  for (int i = 0; i < 3; ++i) {
    const int x = static_cast<int>(corner[i].x), y = static_cast<int>(corner[i].y);
    EXPECT_EQ(z.pixel(x, y), colour[i]) << "corner " << i;
    painter_wrong += !(painter.pixel(x, y) == colour[i]);
  }
  EXPECT_GE(painter_wrong, 1);
}

}  // namespace
}  // namespace mosaic
