// Occlusion queries against the hierarchical z of an occluder pass (mosaic/occlusion.hpp).
//
// The exact answer of a query comes from the reference: the occluders' per-sample depth, and
// for a triangle query the query's own per-sample depth rendered alone by the reference; a
// query is truly visible when any of its samples passes the depth test against the occluders'
// depth there. Every "hidden" answer must be truly hidden (conservativeness). Hand-built cases
// check the obvious answers; the random ones print the fraction of truly hidden queries that
// were reported hidden, and assert only what the test can justify independently: a query whose
// depth is no nearer than every sample in every block its bounding box touches is reported
// hidden.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <string>
#include <vector>

#include "isa_dispatch.hpp"
#include "mosaic/mosaic.hpp"
#include "occlusion/box_project.hpp"
#include "reference_test_util.hpp"

namespace {

using mosaic::DepthTest;
using mosaic::HierarchicalZ;
using mosaic::Isa;
using mosaic::Rgba8;
using mosaic::ScreenRect;

/// Block edge of the hierarchical z, from its specification (8×8 pixels), not from the engine.
constexpr int kBlock = 8;

/// Screen-space triangles with one depth per vertex.
struct Tris {
  std::vector<glm::vec4> positions;
  void add(glm::vec2 a, glm::vec2 b, glm::vec2 c, float za, float zb, float zc) {
    positions.emplace_back(a.x, a.y, za, 1.0f);
    positions.emplace_back(b.x, b.y, zb, 1.0f);
    positions.emplace_back(c.x, c.y, zc, 1.0f);
  }
  void add_rect(float x0, float y0, float x1, float y1, float z) {
    add({x0, y0}, {x1, y0}, {x1, y1}, z, z, z);
    add({x0, y0}, {x1, y1}, {x0, y1}, z, z, z);
  }
  mosaic::Draw draw(DepthTest test = DepthTest::kLess) const {
    mosaic::Draw d;
    d.space = mosaic::Space::kScreen;
    d.positions = positions;
    d.state.depth_test = test;
    return d;
  }
};

/// The occluder pass: depth-only, on the fast path, keeping the hierarchical z; and the same
/// frame by the reference, keeping per-sample depth.
struct Occluders {
  int w, h, samples;
  HierarchicalZ hiz;
  std::vector<float> depth;  ///< the reference's per-sample depth, ((y*w+x)*S+s)
};

Occluders occlude(const Tris& occ, int w, int h, int samples, DepthTest test = DepthTest::kLess,
                  float clear_depth = 1.0f) {
  mosaic::Draw d = occ.draw(test);
  d.state.color_write = false;
  const mosaic::Draw draws[] = {d};
  mosaic::Frame frame;
  frame.draws = draws;
  frame.keep_hierarchical_z = true;
  Occluders out{w, h, samples, {}, {}};
  mosaic::RenderTarget fast(w, h, samples);
  fast.set_clear({0, 0, 0, 255}, clear_depth);
  mosaic::Renderer renderer({1, Isa::kAuto});
  renderer.render(frame, fast);
  out.hiz = renderer.hierarchical_z();
  mosaic::RenderTarget ref(w, h, samples, {true, false});
  ref.set_clear({0, 0, 0, 255}, clear_depth);
  mosaic::Renderer reference({1, Isa::kReference});
  reference.render(frame, ref);
  out.depth.assign(ref.sample_depth().begin(), ref.sample_depth().end());
  return out;
}

bool passes(DepthTest test, float z, float stored) {
  switch (test) {
    case DepthTest::kLess:
      return z < stored;
    case DepthTest::kLessEqual:
      return z <= stored;
    case DepthTest::kGreater:
      return z > stored;
    case DepthTest::kGreaterEqual:
      return z >= stored;
    case DepthTest::kAlways:
      return true;
  }
  return true;
}

/// Exact answer for a rectangle at one depth: any sample position inside [x0, x1) × [y0, y1)
/// whose stored depth the depth passes.
bool rect_truly_visible(const Occluders& o, const ScreenRect& r, float z, DepthTest test) {
  for (int y = 0; y < o.h; ++y)
    for (int x = 0; x < o.w; ++x)
      for (int s = 0; s < o.samples; ++s) {
        const glm::dvec2 p = mosaic::test::sample_px(x, y, s, o.samples);
        if (p.x < r.x0 || p.x >= r.x1 || p.y < r.y0 || p.y >= r.y1) continue;
        if (passes(test, z, o.depth[(static_cast<std::size_t>(y) * o.w + x) * o.samples + s]))
          return true;
      }
  return false;
}

/// Exact answer for a draw: the reference renders it alone (kLess keeps each sample's nearest
/// depth over the draw's triangles; reversed for the greater tests), and any covered sample whose
/// depth passes against the occluders' is visible.
bool draw_truly_visible(const Occluders& o, const mosaic::Draw& query) {
  const DepthTest test = query.state.depth_test;
  const bool greater = test == DepthTest::kGreater || test == DepthTest::kGreaterEqual;
  // A clear depth no triangle reaches (depth is clamped to [0, 1]) marks uncovered samples.
  const float none = greater ? -1.0f : 2.0f;
  mosaic::Draw d = query;
  d.state.depth_test = greater ? DepthTest::kGreater : DepthTest::kLess;
  d.state.depth_write = true;
  const mosaic::Draw draws[] = {d};
  mosaic::Frame frame;
  frame.draws = draws;
  mosaic::RenderTarget t(o.w, o.h, o.samples, {true, false});
  t.set_clear({0, 0, 0, 255}, none);
  mosaic::Renderer({1, Isa::kReference}).render(frame, t);
  for (std::size_t i = 0; i < o.depth.size(); ++i) {
    const float z = t.sample_depth()[i];
    if (z != none && passes(test, z, o.depth[i])) return true;
  }
  return false;
}

/// The largest (kLess) stored depth over every sample of every block that pixels
/// [x0, x1] × [y0, y1] (clamped to the image) touch: a query no nearer than it is hidden at
/// block granularity, whatever its shape inside that box.
float farthest_in_blocks(const Occluders& o, int x0, int y0, int x1, int y1) {
  x0 = std::clamp(x0, 0, o.w - 1) / kBlock * kBlock;
  y0 = std::clamp(y0, 0, o.h - 1) / kBlock * kBlock;
  x1 = std::min(o.w, (std::clamp(x1, 0, o.w - 1) / kBlock + 1) * kBlock);
  y1 = std::min(o.h, (std::clamp(y1, 0, o.h - 1) / kBlock + 1) * kBlock);
  float far = -std::numeric_limits<float>::infinity();
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int s = 0; s < o.samples; ++s)
        far = std::max(far, o.depth[(static_cast<std::size_t>(y) * o.w + x) * o.samples + s]);
  return far;
}

/// Random occluders: medium and large triangles at depths 0.1–0.7, with some slope.
Tris random_occluders(mosaic::test::Rng& rng, int w, int h, int count) {
  Tris t;
  for (int i = 0; i < count; ++i) {
    const double cx = rng.uniform(-0.1 * w, 1.1 * w), cy = rng.uniform(-0.1 * h, 1.1 * h);
    const double r = rng.uniform(20, 0.6 * w);
    const double z = rng.uniform(0.1, 0.7);
    auto v = [&] {
      return glm::vec2(static_cast<float>(cx + rng.uniform(-r, r)),
                       static_cast<float>(cy + rng.uniform(-r, r)));
    };
    const glm::vec2 a = v(), b = v(), c = v();
    t.add(a, b, c, static_cast<float>(z + rng.uniform(-0.1, 0.1)),
          static_cast<float>(z + rng.uniform(-0.1, 0.1)),
          static_cast<float>(z + rng.uniform(-0.1, 0.1)));
  }
  return t;
}

// --- Hand-built cases ---

TEST(Occlusion, FullScreenOccluderHidesWhatIsBehindAndNotWhatIsInFront) {
  const int w = 100, h = 70;  // not a multiple of the block size
  Tris occ;
  occ.add_rect(-10, -10, w + 10, h + 10, 0.5f);
  for (int samples : {1, 4}) {
    const Occluders o = occlude(occ, w, h, samples);
    ASSERT_FALSE(o.hiz.empty());
    const ScreenRect r{20.5f, 10.25f, 60.0f, 45.0f};
    EXPECT_FALSE(o.hiz.rect_visible(r, 0.6f));
    EXPECT_FALSE(o.hiz.rect_visible(r, 0.5f)) << "equal depth fails `less`";
    EXPECT_TRUE(o.hiz.rect_visible(r, 0.5f, DepthTest::kLessEqual));
    EXPECT_TRUE(o.hiz.rect_visible(r, 0.4f));
    EXPECT_TRUE(o.hiz.rect_visible(r, 0.6f, DepthTest::kAlways));
    // A whole-screen rectangle behind it, and one reaching past every edge.
    EXPECT_FALSE(o.hiz.rect_visible({0, 0, float(w), float(h)}, 0.9f));
    EXPECT_FALSE(o.hiz.rect_visible({-1e30f, -5, 1e30f, 1e9f}, 0.9f));

    Tris behind, in_front;
    behind.add({10, 10}, {90, 20}, {40, 65}, 0.7f, 0.9f, 0.55f);
    in_front.add({10, 10}, {90, 20}, {40, 65}, 0.7f, 0.9f, 0.45f);  // one corner in front
    EXPECT_FALSE(o.hiz.draw_visible(behind.draw()));
    EXPECT_TRUE(o.hiz.draw_visible(in_front.draw()));
    EXPECT_FALSE(draw_truly_visible(o, behind.draw()));
    EXPECT_TRUE(draw_truly_visible(o, in_front.draw()));
  }
}

TEST(Occlusion, QueryPeekingOutFromBehindAnOccluderIsVisible) {
  const int w = 96, h = 64;
  Tris occ;
  occ.add_rect(0, 0, 48, 64, 0.3f);  // the left half only, the right keeps the clear depth
  const Occluders o = occlude(occ, w, h, 1);
  EXPECT_FALSE(o.hiz.rect_visible({4, 4, 40, 60}, 0.5f));
  EXPECT_TRUE(o.hiz.rect_visible({4, 4, 52, 60}, 0.5f));         // four pixels past the edge
  EXPECT_TRUE(o.hiz.rect_visible({47.5f, 4, 48.75f, 5}, 0.5f));  // a sliver across it
  Tris q;
  q.add({10, 10}, {40, 12}, {20, 50}, 0.5f, 0.5f, 0.5f);
  EXPECT_FALSE(o.hiz.draw_visible(q.draw()));
  q.add({30, 30}, {60, 31}, {35, 40}, 0.5f, 0.5f, 0.5f);  // a second triangle peeks out
  EXPECT_TRUE(o.hiz.draw_visible(q.draw()));
  EXPECT_TRUE(draw_truly_visible(o, q.draw()));
}

TEST(Occlusion, OffScreenEmptyNanAndNoHierarchicalZ) {
  Tris occ;
  occ.add_rect(0, 0, 64, 64, 0.5f);
  const Occluders o = occlude(occ, 64, 64, 1);
  EXPECT_FALSE(o.hiz.rect_visible({70, 0, 90, 20}, 0.0f)) << "off screen";
  EXPECT_FALSE(o.hiz.rect_visible({10, 10, 10, 20}, 0.0f)) << "empty";
  EXPECT_FALSE(o.hiz.rect_visible({20, 10, 10, 20}, 0.0f)) << "inverted";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(o.hiz.rect_visible({nan, 10, 20, 20}, 0.9f));
  EXPECT_TRUE(o.hiz.rect_visible({0, 10, 20, 20}, nan));
  Tris off;
  off.add({-50, -50}, {-10, -40}, {-30, -5}, 0.0f, 0.0f, 0.0f);
  EXPECT_FALSE(o.hiz.draw_visible(off.draw()));
  const HierarchicalZ none;
  EXPECT_TRUE(none.rect_visible({0, 0, 10, 10}, 1.0f));
  Tris behind;
  behind.add({1, 1}, {9, 1}, {1, 9}, 0.9f, 0.9f, 0.9f);
  EXPECT_TRUE(none.draw_visible(behind.draw()));
  // A malformed query throws as render() would.
  mosaic::Draw bad = behind.draw();
  const std::uint32_t idx[] = {0, 1, 7};
  bad.indices = idx;
  EXPECT_THROW(o.hiz.draw_visible(bad), mosaic::Error);
}

TEST(Occlusion, ReversedDepthUsesTheGreaterTests) {
  Tris occ;
  occ.add_rect(-1, -1, 65, 65, 0.5f);
  const Occluders o = occlude(occ, 64, 64, 4, DepthTest::kGreater, 0.0f);
  EXPECT_FALSE(o.hiz.rect_visible({8, 8, 30, 30}, 0.4f, DepthTest::kGreater));
  EXPECT_FALSE(o.hiz.rect_visible({8, 8, 30, 30}, 0.5f, DepthTest::kGreater));
  EXPECT_TRUE(o.hiz.rect_visible({8, 8, 30, 30}, 0.5f, DepthTest::kGreaterEqual));
  EXPECT_TRUE(o.hiz.rect_visible({8, 8, 30, 30}, 0.6f, DepthTest::kGreater));
  Tris q;
  q.add({5, 5}, {50, 9}, {20, 40}, 0.45f, 0.3f, 0.49f);
  EXPECT_FALSE(o.hiz.draw_visible(q.draw(DepthTest::kGreater)));
  EXPECT_TRUE(o.hiz.draw_visible(q.draw(DepthTest::kLess))) << "the wrong test sees it";
}

/// A 160×120 view from world z = 5 towards the origin, and the hierarchical z of a depth-only
/// wall at world z = 0 (a big quad, drawn in clip space) seen through it.
struct WallView {
  static constexpr int w = 160, h = 120;
  glm::mat4 vp = glm::perspectiveRH_ZO(glm::radians(60.0f), float(w) / h, 0.5f, 50.0f) *
                 glm::lookAtRH(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  HierarchicalZ hiz;
  WallView() {
    const std::vector<glm::vec3> wall_xyz{{-20, -20, 0}, {20, -20, 0}, {20, 20, 0},
                                          {-20, -20, 0}, {20, 20, 0},  {-20, 20, 0}};
    mosaic::Draw wall;
    wall.positions_xyz = wall_xyz;
    wall.transform = vp;
    wall.state.color_write = false;
    const mosaic::Draw draws[] = {wall};
    mosaic::Frame frame;
    frame.draws = draws;
    frame.keep_hierarchical_z = true;
    mosaic::RenderTarget target(w, h);
    mosaic::Renderer renderer({1});
    renderer.render(frame, target);
    hiz = renderer.hierarchical_z();
  }
};

TEST(Occlusion, ClipSpaceBoxWithAMatrix) {
  // A unit cube seen through a perspective camera, behind or in front of a wall at z = 0 (world),
  // or reaching through the near plane.
  const WallView view;
  const glm::mat4& vp = view.vp;
  const HierarchicalZ& hiz = view.hiz;

  std::vector<glm::vec3> cube;
  const std::uint32_t faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                     {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  std::vector<std::uint32_t> idx;
  for (int i = 0; i < 8; ++i)
    cube.emplace_back(i & 1 ? 0.5f : -0.5f, i & 2 ? 0.5f : -0.5f, i & 4 ? 0.5f : -0.5f);
  for (const auto& f : faces)
    for (std::uint32_t k : {f[0], f[1], f[2], f[0], f[2], f[3]}) idx.push_back(k);
  mosaic::Draw box;
  box.positions_xyz = cube;
  box.indices = idx;
  box.transform = vp * glm::translate(glm::mat4(1), glm::vec3(0.3f, -0.2f, -2.0f));
  EXPECT_FALSE(hiz.draw_visible(box)) << "behind the wall";
  box.transform = vp * glm::translate(glm::mat4(1), glm::vec3(0.3f, -0.2f, 2.0f));
  EXPECT_TRUE(hiz.draw_visible(box)) << "in front of the wall";
  box.transform = vp * glm::translate(glm::mat4(1), glm::vec3(0, 0, 4.8f)) *
                  glm::scale(glm::mat4(1), glm::vec3(2.0f));
  EXPECT_TRUE(hiz.draw_visible(box)) << "through the near plane";
  box.transform = vp * glm::translate(glm::mat4(1), glm::vec3(0, 0, 9.0f));
  EXPECT_FALSE(hiz.draw_visible(box)) << "behind the camera";
}

/// The 12 triangles of `b`'s faces, drawn through `vp` with `test`.
struct BoxDraw {
  std::vector<glm::vec3> corners;
  std::vector<std::uint32_t> indices;
  mosaic::Draw draw;
  BoxDraw(const mosaic::Box& b, const glm::mat4& vp, DepthTest test = DepthTest::kLess) {
    for (int i = 0; i < 8; ++i)
      corners.emplace_back(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y,
                           i & 4 ? b.max.z : b.min.z);
    const std::uint32_t faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& f : faces)
      for (std::uint32_t k : {f[0], f[1], f[2], f[0], f[2], f[3]}) indices.push_back(k);
    draw.positions_xyz = corners;
    draw.indices = indices;
    draw.transform = vp;
    draw.state.depth_test = test;
  }
  BoxDraw(const BoxDraw&) = delete;
};

TEST(Occlusion, BoxBatchesNearPlaneOffScreenNonFiniteAndBounds) {
  // The wall at world z = 0, seen from z = 5.
  const WallView view;
  const int w = WallView::w, h = WallView::h;
  const glm::mat4& vp = view.vp;
  const HierarchicalZ& hiz = view.hiz;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const mosaic::Box boxes[] = {
      {{-0.2f, -0.7f, -2.5f}, {0.8f, 0.3f, -1.5f}},  // behind the wall
      {{-0.2f, -0.7f, 1.5f}, {0.8f, 0.3f, 2.5f}},    // in front of it
      {{-1, -1, 3.8f}, {1, 1, 5.8f}},                // through the near plane
      {{-0.5f, -0.5f, 8.5f}, {0.5f, 0.5f, 9.5f}},    // behind the camera
      {{40, -0.5f, 1}, {41, 0.5f, 2}},               // in front of the wall, off the screen
      {{nan, -0.5f, 1}, {0.5f, 0.5f, 2}},            // not finite
  };
  const std::uint8_t expected[] = {0, 1, 1, 0, 0, 1};
  std::vector<std::uint8_t> visible(std::size(boxes), 7);
  std::vector<mosaic::BoxBounds> bounds(std::size(boxes));
  hiz.boxes_visible(boxes, vp, visible, DepthTest::kLess, bounds);
  for (std::size_t i = 0; i < std::size(boxes); ++i) {
    EXPECT_EQ(visible[i], expected[i]) << "box " << i;
    const BoxDraw d(boxes[i], vp);
    if (i != 5) {
      EXPECT_EQ(visible[i] != 0, hiz.draw_visible(d.draw)) << "box " << i;
    }
  }
  // The box in front: its rectangle holds every projected corner, widened by a pixel (less a
  // float rounding), and its
  // nearest depth is no farther than any corner's.
  const BoxDraw front(boxes[1], vp);
  for (const glm::vec3& c : front.corners) {
    const glm::dvec4 p = glm::dmat4(vp) * glm::dvec4(c, 1.0);
    const double x = (p.x / p.w + 1) * w / 2, y = (1 - p.y / p.w) * h / 2, z = p.z / p.w;
    EXPECT_LE(bounds[1].rect.x0, x - 0.999);
    EXPECT_GE(bounds[1].rect.x1, x + 0.999);
    EXPECT_LE(bounds[1].rect.y0, y - 0.999);
    EXPECT_GE(bounds[1].rect.y1, y + 0.999);
    EXPECT_LT(bounds[1].nearest, z);
  }
  EXPECT_LT(bounds[1].rect.x1 - bounds[1].rect.x0, w);  // and it is a box's, not the screen's
  EXPECT_EQ(bounds[2].rect.x0, 0.0f);
  EXPECT_EQ(bounds[2].rect.x1, float(w));
  EXPECT_EQ(bounds[2].nearest, 0.0f);
  // Sizes must agree; an empty hierarchical z answers visible.
  std::vector<std::uint8_t> short_answers(2);
  EXPECT_THROW(hiz.boxes_visible(boxes, vp, short_answers), mosaic::Error);
  EXPECT_THROW(hiz.boxes_visible(boxes, vp, visible, DepthTest::kLess, {bounds.data(), 2}),
               mosaic::Error);
  const HierarchicalZ none;
  none.boxes_visible(boxes, vp, visible);
  for (std::uint8_t v : visible) EXPECT_EQ(v, 1);
}

TEST(Occlusion, BoxProjectionIsBitIdenticalOnEverySimdPath) {
  // Boxes of every kind (in front, through the near plane, behind, off screen, huge, flat,
  // inverted, non-finite, w just above 0) through the scalar projection and each ISA's.
  mosaic::test::Rng rng(31);
  const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(70.0f), 1.5f, 0.1f, 100.0f);
  const glm::mat4 vp = proj * glm::lookAtRH(glm::vec3(1, 2, 6), glm::vec3(0), glm::vec3(0, 1, 0));
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<mosaic::Box> boxes;
  for (int i = 0; i < 997; ++i) {
    const float s = static_cast<float>(std::exp(rng.uniform(std::log(1e-3), std::log(1e4))));
    const glm::vec3 c(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-40, 12));
    const glm::vec3 e(rng.uniform(0, 1) * s, rng.uniform(0, 1) * s, rng.uniform(0, 1) * s);
    mosaic::Box b{c - e, c + e};
    switch (i % 11) {
      case 0:
        std::swap(b.min, b.max);  // inverted: still a box
        break;
      case 1:
        b.max.y = b.min.y;  // flat
        break;
      case 2:
        b.min.x = i % 2 ? nan : inf;
        break;
      case 3:  // a corner just in front of the eye plane
        b.min = glm::vec3(1, 2, 6) - glm::vec3(0.0f, 0.0f, 1e-6f);
        break;
      default:
        break;
    }
    boxes.push_back(b);
  }
  const mosaic::occlusion::BoxView view(vp, 203, 141, false), greater(vp, 203, 141, true);
  for (const auto* v : {&view, &greater}) {
    std::vector<mosaic::occlusion::Projected> want(boxes.size());
    mosaic::occlusion::project_boxes(boxes.data(), boxes.size(), *v, want.data());
    for (mosaic::Isa isa : mosaic::dispatch::runnable_isas()) {
      std::vector<mosaic::occlusion::Projected> got(boxes.size());
      mosaic::dispatch::box_projector(isa)(boxes.data(), boxes.size(), *v, got.data());
      for (std::size_t i = 0; i < boxes.size(); ++i) {
        const auto& a = want[i];
        const auto& b = got[i];
        ASSERT_EQ(a.answered, b.answered) << mosaic::to_string(isa) << " box " << i;
        ASSERT_EQ(a.visible, b.visible) << mosaic::to_string(isa) << " box " << i;
        ASSERT_EQ(0, std::memcmp(&a.bounds, &b.bounds, sizeof a.bounds))
            << mosaic::to_string(isa) << " box " << i;
      }
    }
  }
}

TEST(Occlusion, RectangleBatchesAnswerAsRectVisible) {
  mosaic::test::Rng rng(5);
  const Occluders o = occlude(random_occluders(rng, 203, 141, 30), 203, 141, 4);
  std::vector<ScreenRect> rects;
  std::vector<float> depths;
  for (int q = 0; q < 2000; ++q) {
    const float x0 = static_cast<float>(rng.uniform(-20, 203));
    const float y0 = static_cast<float>(rng.uniform(-20, 141));
    rects.push_back({x0, y0, x0 + static_cast<float>(rng.uniform(0.5, 60)),
                     y0 + static_cast<float>(rng.uniform(0.5, 60))});
    depths.push_back(static_cast<float>(rng.uniform(0.2, 1.0)));
  }
  for (DepthTest test : {DepthTest::kLess, DepthTest::kGreaterEqual}) {
    std::vector<std::uint8_t> visible(rects.size());
    o.hiz.rects_visible(rects, depths, visible, test);
    for (std::size_t i = 0; i < rects.size(); ++i)
      ASSERT_EQ(visible[i] != 0, o.hiz.rect_visible(rects[i], depths[i], test)) << i;
  }
  std::vector<std::uint8_t> fewer(3);
  EXPECT_THROW(o.hiz.rects_visible(rects, depths, fewer), mosaic::Error);
}

TEST(Occlusion, RandomBoxBatchesAreConservative) {
  // World boxes through a perspective camera against random occluders: a box reported hidden
  // must have no sample of its faces pass the depth test (the reference renders them), and the
  // triangle query of its faces must agree that it is hidden.
  mosaic::test::Rng rng(23);
  const int w = 203, h = 141;
  const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(60.0f), float(w) / h, 2.0f, 30.0f);
  const glm::mat4 vp = proj * glm::lookAtRH(glm::vec3(0, 0, 12), glm::vec3(0), glm::vec3(0, 1, 0));
  std::size_t hidden = 0, total = 0;
  for (int scene = 0; scene < 4; ++scene) {
    const int samples = scene % 2 ? 4 : 1;
    const Occluders o = occlude(random_occluders(rng, w, h, 30), w, h, samples);
    std::vector<mosaic::Box> boxes;
    for (int q = 0; q < 150; ++q) {
      const glm::vec3 c(rng.uniform(-7, 7), rng.uniform(-5, 5), rng.uniform(-16, 9));
      const glm::vec3 e(rng.uniform(0.05, 1.5), rng.uniform(0.05, 1.5), rng.uniform(0.05, 1.5));
      boxes.push_back({c - e, c + e});
    }
    std::vector<std::uint8_t> visible(boxes.size());
    o.hiz.boxes_visible(boxes, vp, visible);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      ++total;
      if (visible[i]) continue;
      ++hidden;
      const BoxDraw d(boxes[i], vp);
      ASSERT_FALSE(draw_truly_visible(o, d.draw)) << "scene " << scene << " box " << i;
      ASSERT_FALSE(o.hiz.draw_visible(d.draw)) << "scene " << scene << " box " << i;
    }
  }
  std::printf("boxes: %zu queries, %zu reported hidden\n", total, hidden);
  ASSERT_GT(hidden, total / 10) << "the scenes hide too little to test anything";
}

// --- Random scenes: conservativeness, and how often a hidden query is found hidden ---

TEST(Occlusion, RandomRectanglesAreConservativeAndExactAtBlockGranularity) {
  mosaic::test::Rng rng(7);
  const int w = 203, h = 141;
  std::size_t truly_hidden = 0, reported_hidden = 0, total = 0;
  for (int scene = 0; scene < 6; ++scene) {
    const int samples = scene % 2 ? 4 : 1;
    const Occluders o = occlude(random_occluders(rng, w, h, 30), w, h, samples);
    for (int q = 0; q < 500; ++q) {
      const float x0 = static_cast<float>(rng.uniform(-20, w));
      const float y0 = static_cast<float>(rng.uniform(-20, h));
      const ScreenRect r{x0, y0, x0 + static_cast<float>(rng.uniform(0.5, 60)),
                         y0 + static_cast<float>(rng.uniform(0.5, 60))};
      const float z = static_cast<float>(rng.uniform(0.2, 1.0));
      const bool visible = o.hiz.rect_visible(r, z);
      const bool truth = rect_truly_visible(o, r, z, DepthTest::kLess);
      ASSERT_TRUE(visible || !truth)
          << "a visible rectangle reported hidden, scene " << scene << " query " << q;
      // At block granularity the answer is exact: hidden iff the depth is no nearer than every
      // sample of every block meeting the rectangle on the screen.
      const int px0 = static_cast<int>(std::floor(r.x0)), py0 = static_cast<int>(std::floor(r.y0));
      const int px1 = static_cast<int>(std::floor(r.x1)), py1 = static_cast<int>(std::floor(r.y1));
      const bool on_screen = r.x1 > 0 && r.y1 > 0 && r.x0 < w && r.y0 < h;
      if (on_screen && px1 >= 0 && py1 >= 0) {
        EXPECT_EQ(visible, z < farthest_in_blocks(o, px0, py0, px1, py1))
            << "scene " << scene << " query " << q;
      }
      ++total;
      truly_hidden += !truth;
      reported_hidden += !visible;
    }
  }
  std::printf("rectangles: %zu queries, %zu truly hidden, %zu reported hidden (%.1f %%)\n", total,
              truly_hidden, reported_hidden,
              truly_hidden ? 100.0 * double(reported_hidden) / double(truly_hidden) : 0.0);
  ASSERT_GT(truly_hidden, total / 10) << "the scenes hide too little to measure anything";
}

TEST(Occlusion, QueryPrecisionOnTheBuiltInScenes) {
  // The measure of query precision: 20,000 random rectangles (8 to 64 px, depths 0 to 1)
  // against the depth-only pass of each scene shaped like the occlusion benchmarks, at 1080p 1x.
  // Exactly hidden: no sample centre inside the rectangle holds a depth farther than the query's.
  // rect_visible() must never call a visible one hidden, and must find at least 95 % of the
  // hidden ones on the large-triangle scene.
  constexpr int kW = 1920, kH = 1080, kQueries = 20'000;
  for (const char* name : {"random-small", "random-large", "slivers"}) {
    mosaic::Scene sc = mosaic::builtin_scene(name, kW, kH, 1);
    sc.for_each_state([](mosaic::DrawState& st) {
      st.depth_test = DepthTest::kLess;
      st.depth_write = true;
      st.color_write = false;
    });
    const std::vector<mosaic::Draw> draws = sc.draws();
    mosaic::Frame frame;
    frame.draws = draws;
    frame.keep_hierarchical_z = true;
    mosaic::RenderTarget target(kW, kH, 1, {.keep_sample_depth = true});
    mosaic::Renderer renderer({2});
    renderer.render(frame, target);
    const HierarchicalZ& hiz = renderer.hierarchical_z();
    const std::span<const float> depth = target.sample_depth();
    mosaic::test::Rng rng(99);
    std::size_t hidden = 0, found = 0, wrong = 0;
    for (int q = 0; q < kQueries; ++q) {
      const float x0 = static_cast<float>(rng.uniform(0, kW)),
                  y0 = static_cast<float>(rng.uniform(0, kH));
      const ScreenRect r{x0, y0, x0 + static_cast<float>(rng.uniform(8, 64)),
                         y0 + static_cast<float>(rng.uniform(8, 64))};
      const float z = static_cast<float>(rng.unit());
      bool truly_hidden = true;
      const int px0 = static_cast<int>(std::ceil(r.x0 - 0.5f));
      const int px1 = std::min(kW, static_cast<int>(std::ceil(r.x1 - 0.5f)));
      const int py0 = static_cast<int>(std::ceil(r.y0 - 0.5f));
      const int py1 = std::min(kH, static_cast<int>(std::ceil(r.y1 - 0.5f)));
      for (int y = py0; y < py1 && truly_hidden; ++y)
        for (int x = px0; x < px1 && truly_hidden; ++x)
          truly_hidden = !(z < depth[static_cast<std::size_t>(y) * kW + x]);
      const bool reported_hidden = !hiz.rect_visible(r, z);
      hidden += truly_hidden;
      found += truly_hidden && reported_hidden;
      wrong += reported_hidden && !truly_hidden;
    }
    std::printf("%s: %d rectangles, %zu exactly hidden, %zu found hidden (%.1f %%), %zu wrong\n",
                name, kQueries, hidden, found,
                hidden ? 100.0 * double(found) / double(hidden) : 0.0, wrong);
    EXPECT_EQ(wrong, 0u) << name;
    if (std::string(name) == "random-large") {
      ASSERT_GT(hidden, 1000u);
      EXPECT_GE(double(found), 0.95 * double(hidden)) << name;
    }
  }
}

TEST(Occlusion, RandomTriangleListsAreConservative) {
  mosaic::test::Rng rng(11);
  const int w = 160, h = 112;
  std::size_t truly_hidden = 0, reported_hidden = 0, total = 0, must_hide = 0;
  for (int scene = 0; scene < 4; ++scene) {
    const int samples = scene % 2 ? 4 : 1;
    const Occluders o = occlude(random_occluders(rng, w, h, 30), w, h, samples);
    for (int q = 0; q < 100; ++q) {
      Tris t;
      const double cx = rng.uniform(-10, w + 10), cy = rng.uniform(-10, h + 10);
      const double r = rng.uniform(2, 30), z = rng.uniform(0.2, 1.0);
      const int n = 1 + static_cast<int>(rng.range(0, 3));
      float zmin = 1, xmin = 1e9f, ymin = 1e9f, xmax = -1e9f, ymax = -1e9f;
      for (int k = 0; k < n; ++k) {
        glm::vec2 p[3];
        float zz[3];
        for (int v = 0; v < 3; ++v) {
          p[v] = glm::vec2(static_cast<float>(cx + rng.uniform(-r, r)),
                           static_cast<float>(cy + rng.uniform(-r, r)));
          zz[v] = static_cast<float>(std::clamp(z + rng.uniform(-0.05, 0.05), 0.0, 1.0));
          zmin = std::min(zmin, zz[v]);
          xmin = std::min(xmin, p[v].x);
          ymin = std::min(ymin, p[v].y);
          xmax = std::max(xmax, p[v].x);
          ymax = std::max(ymax, p[v].y);
        }
        t.add(p[0], p[1], p[2], zz[0], zz[1], zz[2]);
      }
      const bool visible = o.hiz.draw_visible(t.draw());
      const bool truth = draw_truly_visible(o, t.draw());
      ASSERT_TRUE(visible || !truth)
          << "a visible triangle list reported hidden, scene " << scene << " query " << q;
      // Sufficient for "hidden" at block granularity: no vertex nearer than the farthest sample
      // of the blocks the triangles' (one-pixel-padded) bounding box touches.
      const bool on_screen = xmax > 0 && ymax > 0 && xmin < w && ymin < h;
      if (on_screen && zmin >= farthest_in_blocks(o, static_cast<int>(std::floor(xmin)) - 1,
                                                  static_cast<int>(std::floor(ymin)) - 1,
                                                  static_cast<int>(std::floor(xmax)) + 1,
                                                  static_cast<int>(std::floor(ymax)) + 1)) {
        ++must_hide;
        EXPECT_FALSE(visible) << "scene " << scene << " query " << q;
      }
      ++total;
      truly_hidden += !truth;
      reported_hidden += !visible;
    }
  }
  std::printf(
      "triangle lists: %zu queries, %zu truly hidden, %zu reported hidden (%.1f %%), "
      "%zu hidden behind whole blocks\n",
      total, truly_hidden, reported_hidden,
      truly_hidden ? 100.0 * double(reported_hidden) / double(truly_hidden) : 0.0, must_hide);
  ASSERT_GT(must_hide, 0u) << "no query fell behind whole blocks: the check checked nothing";
  ASSERT_GT(truly_hidden, total / 10) << "the scenes hide too little to measure anything";
}

}  // namespace
