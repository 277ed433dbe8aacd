// FrameStats counters of the reference on small hand-made frames: triangles in, drawn, culled by
// face, degenerate, outside, clipped and non-finite, and the sample counters. Every expected
// number is counted by hand from the frame.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "reference_test_util.hpp"

namespace mosaic {
namespace {

// (10,10) -> (10,30) -> (30,30) runs down, then right: counter-clockwise as seen on screen.
void add_ccw(Mesh& m, glm::dvec2 o = {0, 0}) {
  test::add_tri(m, o + glm::dvec2{10, 10}, o + glm::dvec2{10, 30}, o + glm::dvec2{30, 30},
                {255, 0, 0, 255});
}
void add_cw(Mesh& m, glm::dvec2 o = {0, 0}) {
  test::add_tri(m, o + glm::dvec2{10, 10}, o + glm::dvec2{30, 30}, o + glm::dvec2{10, 30},
                {0, 255, 0, 255});
}

TEST(ReferenceStats, BackAndFrontFaceCulling) {
  struct Case {
    FrontFace front;
    CullMode cull;
    bool ccw_drawn, cw_drawn;
  };
  const Case cases[] = {
      {FrontFace::kCounterClockwise, CullMode::kNone, true, true},
      {FrontFace::kCounterClockwise, CullMode::kBack, true, false},
      {FrontFace::kCounterClockwise, CullMode::kFront, false, true},
      {FrontFace::kClockwise, CullMode::kNone, true, true},
      {FrontFace::kClockwise, CullMode::kBack, false, true},
      {FrontFace::kClockwise, CullMode::kFront, true, false},
  };
  for (const Case& c : cases) {
    DrawState st;
    st.front_face = c.front;
    st.cull = c.cull;
    Mesh m = test::screen_mesh(st);
    add_ccw(m);
    add_cw(m, {24, 0});  // side by side, no overlap
    RenderTarget t = test::sample_target(64, 40, 1);
    const FrameStats s = test::render_reference(m, t);
    const unsigned drawn = unsigned(c.ccw_drawn) + unsigned(c.cw_drawn);
    EXPECT_EQ(s.triangles_in, 2u);
    EXPECT_EQ(s.triangles_drawn, drawn);
    EXPECT_EQ(s.triangles_culled_face, 2u - drawn);
    // Pixel (12, 27) is inside the first (ccw) triangle only, (36, 27) inside the second only.
    EXPECT_EQ(!(t.pixel(12, 27) == test::kClear), c.ccw_drawn);
    EXPECT_EQ(!(t.pixel(36, 27) == test::kClear), c.cw_drawn);
  }
}

TEST(ReferenceStats, ClipSpaceWindingFollowsNdc) {
  // Counter-clockwise in y-up NDC is counter-clockwise on screen: front for kCounterClockwise.
  Mesh m;
  m.space = Space::kClip;
  m.state.cull = CullMode::kBack;
  m.positions = {{-0.5f, -0.5f, 0.5f, 1}, {0.5f, -0.5f, 0.5f, 1}, {0, 0.5f, 0.5f, 1}};
  RenderTarget t = test::sample_target(16, 16, 1);
  EXPECT_EQ(test::render_reference(m, t).triangles_drawn, 1u);
  m.state.front_face = FrontFace::kClockwise;
  const FrameStats s = test::render_reference(m, t);
  EXPECT_EQ(s.triangles_drawn, 0u);
  EXPECT_EQ(s.triangles_culled_face, 1u);
}

TEST(ReferenceStats, EveryRejectionIsCountedOnce) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  DrawState st;
  st.cull = CullMode::kBack;  // counter-clockwise on screen is the front
  Mesh m = test::screen_mesh(st);
  add_ccw(m);                                                             // drawn
  add_ccw(m, {20, 2});                                                    // drawn
  add_cw(m);                                                              // back face
  test::add_tri(m, {1, 1}, {5, 5}, {9, 9}, {1, 1, 1, 255});               // degenerate: collinear
  test::add_tri(m, {3, 3}, {3.001, 3}, {3, 9}, {1, 1, 1, 255});           // degenerate: snaps
  test::add_tri(m, {70, 10}, {70, 30}, {90, 30}, {1, 1, 1, 255});         // outside: right of it
  test::add_tri(m, {10, -30}, {10, -10}, {30, -10}, {1, 1, 1, 255});      // outside: above
  test::add_tri(m, {10, 10}, {10, 30}, {30, 30}, {1, 1, 1, 255}, 1.5f);   // outside: beyond far
  test::add_tri(m, {10, 10}, {10, 30}, {30, 30}, {1, 1, 1, 255}, -0.5f);  // outside: before near
  m.positions.push_back({nan, 1, 0.5f, 1});                               // non-finite
  m.positions.push_back({1, 9, 0.5f, 1});
  m.positions.push_back({9, 9, 0.5f, 1});
  m.colors.push_back({1, 1, 1, 255});
  m.positions.push_back({1, 1, 0.5f, 1});  // non-finite: w
  m.positions.push_back({1, 9, 0.5f, inf});
  m.positions.push_back({9, 9, 0.5f, 1});
  m.colors.push_back({1, 1, 1, 255});
  RenderTarget t = test::sample_target(64, 40, 4);
  const FrameStats s = test::render_reference(m, t);
  EXPECT_EQ(s.triangles_in, 11u);
  EXPECT_EQ(s.triangles_drawn, 2u);
  EXPECT_EQ(s.triangles_culled_face, 1u);
  EXPECT_EQ(s.triangles_degenerate, 2u);
  EXPECT_EQ(s.triangles_outside, 4u);
  EXPECT_EQ(s.triangles_nonfinite, 2u);
  EXPECT_EQ(s.triangles_clipped, 0u);
  EXPECT_EQ(s.isa, Isa::kReference);
  EXPECT_EQ(s.threads, 1);
}

TEST(ReferenceStats, ClippedTrianglesCountOnceEvenWhenCulled) {
  // A triangle crossing the near plane (z = w - 1) becomes a quad, drawn as two pieces. Drawn, it
  // is one clipped triangle and two drawn pieces; back-facing, it is one clipped triangle culled
  // once (not once per piece).
  const std::vector<glm::vec4> ccw_ndc{
      {-2, -2, -3, -1}, {2.0625f, -1.03125f, 3, 4}, {-1.203125f, 0.28125f, 1, 2}};
  for (CullMode cull : {CullMode::kNone, CullMode::kBack, CullMode::kFront}) {
    Mesh m;
    m.space = Space::kClip;
    m.positions = ccw_ndc;
    m.state.cull = cull;
    m.state.depth_test = DepthTest::kAlways;
    RenderTarget t = test::sample_target(64, 64, 1);
    const FrameStats s = test::render_reference(m, t);
    EXPECT_EQ(s.triangles_in, 1u);
    EXPECT_EQ(s.triangles_clipped, 1u);
    const bool culled = s.triangles_drawn == 0;
    EXPECT_EQ(s.triangles_drawn, culled ? 0u : 2u);
    EXPECT_EQ(s.triangles_culled_face, culled ? 1u : 0u) << static_cast<int>(cull);
    EXPECT_EQ(s.triangles_degenerate + s.triangles_outside, 0u);
    if (cull == CullMode::kNone) {
      EXPECT_FALSE(culled);
    }
    EXPECT_EQ(test::count_covered(t) > 0, !culled);
  }
  // Exactly one of the two culling modes culls it.
  int culled_modes = 0;
  for (CullMode cull : {CullMode::kBack, CullMode::kFront}) {
    Mesh m;
    m.space = Space::kClip;
    m.positions = ccw_ndc;
    m.state.cull = cull;
    RenderTarget t = test::sample_target(64, 64, 1);
    culled_modes += test::render_reference(m, t).triangles_drawn == 0;
  }
  EXPECT_EQ(culled_modes, 1);
}

TEST(ReferenceStats, SamplesTestedAndWritten) {
  // A 4x4 px square (two triangles, edges between samples: 16 px, 64 samples at 4x) drawn twice
  // at the same depth with "less": the second copy is tested everywhere and written nowhere.
  for (int samples : {1, 4, 16}) {
    Mesh m = test::screen_mesh();
    for (int copy = 0; copy < 2; ++copy) {
      test::add_tri(m, {2, 2}, {6, 2}, {6, 6}, {255, 0, 0, 255}, 0.5f);
      test::add_tri(m, {2, 2}, {6, 6}, {2, 6}, {255, 0, 0, 255}, 0.5f);
    }
    RenderTarget t = test::sample_target(8, 8, samples);
    const FrameStats s = test::render_reference(m, t);
    const std::uint64_t n = 16u * samples;
    EXPECT_EQ(s.triangles_drawn, 4u);
    EXPECT_EQ(s.samples_tested, 2 * n);
    EXPECT_EQ(s.samples_written, n);
    EXPECT_EQ(test::count_covered(t), n);
  }
}

TEST(ReferenceStats, CountersAddUpOverDraws) {
  Mesh a = test::screen_mesh(), b = test::screen_mesh();
  add_ccw(a);
  add_cw(a, {24, 0});
  add_ccw(b, {0, 5});
  // b is indexed: triangles (0,1,2) and (2,1,0), the same triangle in both windings.
  b.indices = {0, 1, 2, 2, 1, 0};
  b.colors.push_back({0, 0, 255, 255});
  b.state.cull = CullMode::kBack;
  RenderTarget t = test::sample_target(64, 40, 1);
  const FrameStats s = test::render_reference({a, b}, t);
  EXPECT_EQ(s.triangles_in, 4u);
  EXPECT_EQ(s.triangles_drawn, 3u);
  EXPECT_EQ(s.triangles_culled_face, 1u);
}

}  // namespace
}  // namespace mosaic
