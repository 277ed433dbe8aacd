// test_llvmpipe_peer.cpp — mosaic against Mesa's llvmpipe on small scenes whose edges and
// vertices sit exactly on sample positions, the cases where a fill rule decides coverage.
//
// With FillRule::kOpenGL and the depth test off, mosaic's FrameStats::samples_written must
// equal llvmpipe's GL_SAMPLES_PASSED at 1 and 4 samples, and the 1x images must be identical;
// with the depth test on, 1x images of scenes without depth ties must be identical too. Some
// checks do not need mosaic at all (pixel centres, row order, watertight meshes), so that a
// disagreement can be pinned on one side. Skipped only when no llvmpipe context can be created.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "llvmpipe/llvmpipe_peer.hpp"
#include "mosaic/mosaic.hpp"

namespace {

using mosaic::Rgba8;
using mosaic::peers::LlvmpipeContext;
using mosaic::peers::LlvmpipeScene;

// Thread counts: llvmpipe bins into 64×64 tiles and mosaic into its own, so two threads on a
// 128-pixel scene make both split the work; coverage must not depend on it.
constexpr int kThreads = 2;
// Size of most test scenes: two llvmpipe tiles across, small enough for mosaic's reference path.
constexpr int kSize = 128;
// The standard 4x pattern, 1/16 px from the pixel centre, y down (DESIGN.md): written out
// again here so that vertices can be put on sample positions independently of the engine.
constexpr std::array<std::array<int, 2>, 4> kPattern4{{{-2, -6}, {6, -2}, {-6, 2}, {2, 6}}};

struct Tri {
  std::array<glm::vec3, 3> v;
  Rgba8 color;
};

// A screen-space scene of flat-coloured triangles in one mesh, in the given order.
mosaic::Scene make_scene(const std::vector<Tri>& tris, int width = kSize, int height = kSize) {
  mosaic::Scene s;
  s.name = "test";
  s.width = width;
  s.height = height;
  s.clear_color = {10, 20, 30, 255};
  mosaic::Mesh m;
  m.space = mosaic::Space::kScreen;
  m.color_source = mosaic::ColorSource::kPerTriangle;
  for (const Tri& t : tris) {
    for (const glm::vec3& p : t.v) m.positions.emplace_back(p, 1.0f);
    m.colors.push_back(t.color);
  }
  s.meshes.push_back(std::move(m));
  return s;
}

// The scene with the state the comparisons use: OpenGL's fill rule, and either the depth test
// off (no test, no writes: what GL_SAMPLES_PASSED counts) or `less`.
mosaic::Scene with_state(mosaic::Scene s, bool depth_test) {
  s.for_each_state([&](mosaic::DrawState& st) {
    st.fill_rule = mosaic::FillRule::kOpenGL;
    st.depth_test = depth_test ? mosaic::DepthTest::kLess : mosaic::DepthTest::kAlways;
    st.depth_write = depth_test;
  });
  return s;
}

// A distinct colour per triangle, so that an image shows which triangle owns each pixel.
Rgba8 color_of(std::size_t i) {
  return {static_cast<std::uint8_t>(40 + (i * 67) % 200), static_cast<std::uint8_t>(i * 131 % 256),
          static_cast<std::uint8_t>(60 + (i * 29) % 190), 255};
}

// Positions in 1/256 px, the precision both renderers snap to.
float px(int units) { return static_cast<float>(units) / 256.0f; }
// The centre of pixel i, and its 4x sample s, on the 1/256 grid.
float centre(int i) { return static_cast<float>(i) + 0.5f; }
glm::vec2 sample4(int x, int y, int s) {
  return {centre(x) + static_cast<float>(kPattern4[s][0]) / 16.0f,
          centre(y) + static_cast<float>(kPattern4[s][1]) / 16.0f};
}

struct Result {
  std::vector<Rgba8> image;
  std::uint64_t samples = 0;         // GL_SAMPLES_PASSED or samples_written
  std::vector<Rgba8> sample_colors;  // mosaic only: every sample, (y * width + x) * n + s
};

class LlvmpipePeer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    try {
      context_ = std::make_unique<LlvmpipeContext>(kThreads);
    } catch (const mosaic::peers::PeerUnavailable& e) {
      skip_reason_ = e.what();
    }
  }
  static void TearDownTestSuite() { context_.reset(); }

  void SetUp() override {
    if (!context_) GTEST_SKIP() << "no llvmpipe context: " << skip_reason_;
  }

  static Result gl(const mosaic::Scene& scene, int samples) {
    LlvmpipeScene s(*context_, scene, samples);
    Result r;
    r.samples = s.samples_passed();
    r.image = s.read_image();
    return r;
  }

  static Result mosaic_render(const mosaic::Scene& scene, int samples) {
    mosaic::Renderer renderer(mosaic::RendererOptions{.threads = kThreads});
    mosaic::RenderTarget target(scene.width, scene.height, samples,
                                mosaic::TargetOptions{.keep_sample_color = true});
    target.set_clear(scene.clear_color, scene.clear_depth);
    const std::vector<mosaic::Draw> draws = scene.draws();
    const mosaic::FrameStats stats = renderer.render(mosaic::Frame{.draws = draws}, target);
    Result r;
    r.samples = stats.samples_written;
    r.image.assign(target.color().begin(), target.color().end());
    r.sample_colors.assign(target.sample_color().begin(), target.sample_color().end());
    return r;
  }

  // Pixels where the images differ, listed (the first few) for the failure message.
  static std::string diff(const std::vector<Rgba8>& a, const std::vector<Rgba8>& b, int width) {
    std::string out;
    int n = 0;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
      if (a[i] == b[i]) continue;
      if (++n <= 8) {
        char buf[96];
        std::snprintf(buf, sizeof buf, " (%zu,%zu) gl %d,%d,%d mosaic %d,%d,%d;", i % width,
                      i / width, a[i].r, a[i].g, a[i].b, b[i].r, b[i].g, b[i].b);
        out += buf;
      }
    }
    return std::to_string(n) + " pixels differ:" + out;
  }

  // Resolved images with the same samples underneath: llvmpipe's glBlitFramebuffer rounds a
  // mean that ends in .5 to even, mosaic's box filter rounds it up (resolve/resolve.hpp). So a
  // channel may differ only where mosaic's samples sum to 2 mod 4, and then llvmpipe's value is
  // the even one of the two: anything else is a coverage or colour difference.
  static void expect_same_up_to_tie_rounding(const Result& g, const Result& m, int n) {
    ASSERT_EQ(m.sample_colors.size(), m.image.size() * n);
    std::size_t ties = 0, others = 0;
    for (std::size_t i = 0; i < m.image.size(); ++i) {
      for (int ch = 0; ch < 4; ++ch) {
        auto channel = [ch](Rgba8 c) {
          const std::uint8_t v[4] = {c.r, c.g, c.b, c.a};
          return static_cast<int>(v[ch]);
        };
        int sum = 0;
        for (int s = 0; s < n; ++s) sum += channel(m.sample_colors[i * n + s]);
        const int gv = channel(g.image[i]), mv = channel(m.image[i]);
        if (gv == mv) continue;
        const bool tie = sum % n == n / 2 && gv == sum / n && gv % 2 == 0 && mv == gv + 1;
        ++(tie ? ties : others);
      }
    }
    EXPECT_EQ(others, 0u) << "4x channels that differ other than by tie rounding (" << ties
                          << " differ by it)";
  }

  // The whole comparison: depth off at 1x and 4x (equal counts, identical 1x images), and
  // at 4x images equal up to the resolve's rounding of ties, and depth on at 1x (identical
  // images) when the scene has no depth ties.
  static void compare(const mosaic::Scene& base, bool tie_free_depth) {
    for (int samples : {1, 4}) {
      SCOPED_TRACE("samples " + std::to_string(samples));
      const mosaic::Scene scene = with_state(base, false);
      const Result g = gl(scene, samples);
      const Result m = mosaic_render(scene, samples);
      EXPECT_GT(m.samples, 0u);
      EXPECT_EQ(g.samples, m.samples) << "GL_SAMPLES_PASSED vs mosaic samples_written";
      if (samples == 1) {
        EXPECT_TRUE(g.image == m.image) << diff(g.image, m.image, base.width);
      } else {
        expect_same_up_to_tie_rounding(g, m, samples);
      }
    }
    if (tie_free_depth) {
      const mosaic::Scene scene = with_state(base, true);
      const Result g = gl(scene, 1);
      const Result m = mosaic_render(scene, 1);
      EXPECT_TRUE(g.image == m.image) << "depth test on: " << diff(g.image, m.image, base.width);
    }
  }

  static std::unique_ptr<LlvmpipeContext> context_;
  static std::string skip_reason_;
};

std::unique_ptr<LlvmpipeContext> LlvmpipePeer::context_;
std::string LlvmpipePeer::skip_reason_;

TEST_F(LlvmpipePeer, RendererIsLlvmpipeWithTheRequestedThreads) {
  EXPECT_NE(context_->renderer().find("llvmpipe"), std::string::npos) << context_->renderer();
  const int counted = context_->rasterizer_threads();
  if (counted >= 0) {
    EXPECT_EQ(counted, kThreads) << "LP_NUM_THREADS did not take effect";
  }
}

// A rectangle whose edges lie a quarter pixel off the centres: pixel i is covered iff its
// centre is inside, so the covered pixels follow from the geometry alone. A half-pixel shift,
// or rows read bottom first, moves them.
TEST_F(LlvmpipePeer, PixelCentresAndRowOrderMatchTheScene) {
  const int x0 = 10, x1 = 20, y0 = 0, y1 = 3;  // covered pixels: [x0, x1] × [y0, y1]
  const float l = static_cast<float>(x0) + 0.25f, r = static_cast<float>(x1) + 0.75f;
  const float t = static_cast<float>(y0) + 0.25f, b = static_cast<float>(y1) + 0.75f;
  const Rgba8 white{255, 255, 255, 255};
  const mosaic::Scene scene = with_state(
      make_scene({{{glm::vec3(l, t, 0.5f), glm::vec3(r, t, 0.5f), glm::vec3(r, b, 0.5f)}, white},
                  {{glm::vec3(l, t, 0.5f), glm::vec3(r, b, 0.5f), glm::vec3(l, b, 0.5f)}, white}},
                 64, 32),
      false);
  const Result g = gl(scene, 1);
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const bool inside = x >= x0 && x <= x1 && y >= y0 && y <= y1;
      ASSERT_EQ(g.image[static_cast<std::size_t>(y) * scene.width + x] == white, inside)
          << "pixel (" << x << ", " << y << ")";
    }
  }
  EXPECT_EQ(g.samples, static_cast<std::uint64_t>((x1 - x0 + 1) * (y1 - y0 + 1)));
}

// Edges exactly through pixel centres, one of each kind: DESIGN.md's measurement says llvmpipe
// (y down) keeps samples on left and bottom edges and drops those on top and right edges.
TEST_F(LlvmpipePeer, EdgesThroughCentresFollowTheOpenGLRule) {
  const int x0 = 10, x1 = 20, y0 = 5, y1 = 15;  // edges at centre(x0) .. centre(x1), etc.
  const Rgba8 white{255, 255, 255, 255};
  const glm::vec3 tl(centre(x0), centre(y0), 0.5f), tr(centre(x1), centre(y0), 0.5f);
  const glm::vec3 br(centre(x1), centre(y1), 0.5f), bl(centre(x0), centre(y1), 0.5f);
  const mosaic::Scene base = make_scene({{{tl, tr, br}, white}, {{tl, br, bl}, white}}, 32, 32);
  const mosaic::Scene scene = with_state(base, false);
  const Result g = gl(scene, 1);
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const bool inside = x >= x0 && x < x1 && y > y0 && y <= y1;  // left, bottom kept
      ASSERT_EQ(g.image[static_cast<std::size_t>(y) * scene.width + x] == white, inside)
          << "pixel (" << x << ", " << y << ")";
    }
  }
  compare(base, true);
}

// Triangles with horizontal and vertical edges through 4x sample positions and pixel centres,
// in both windings: every edge kind meets a sample exactly.
TEST_F(LlvmpipePeer, AxisAlignedEdgesThroughSamples) {
  std::vector<Tri> tris;
  std::size_t i = 0;
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      const int x = 4 + col * 30, y = 4 + row * 30;
      const glm::vec2 a = sample4(x, y, (row + col) % 4);
      const glm::vec2 b = sample4(x + 17, y + 19, (row + 2 * col + 1) % 4);
      const glm::vec2 c = row % 2 ? glm::vec2(centre(x + 3), centre(y + 22)) : b;
      const float z = 0.1f + 0.025f * static_cast<float>(i);  // distinct, all below 1
      // A right triangle with a horizontal top edge and a vertical right edge, and its mirror
      // with a horizontal bottom edge and a vertical left edge; windings alternate.
      Tri t1{{glm::vec3(a.x, a.y, z), glm::vec3(c.x, a.y, z), glm::vec3(c.x, c.y, z)},
             color_of(i++)};
      Tri t2{{glm::vec3(a.x, a.y + 1, z + 0.01f), glm::vec3(a.x, c.y + 2, z + 0.01f),
              glm::vec3(c.x - 1, c.y + 2, z + 0.01f)},
             color_of(i++)};
      if (col % 2) std::swap(t1.v[1], t1.v[2]);
      if (row % 2) std::swap(t2.v[0], t2.v[1]);
      tris.push_back(t1);
      tris.push_back(t2);
    }
  }
  compare(make_scene(tris), true);
}

// A fan of 16 triangles around a centre exactly on a sample (a pixel centre, then a 4x sample
// position): the centre sample is covered by exactly one triangle. The same polygon fanned from
// one of its vertices must cover exactly as many samples on each renderer (watertightness,
// independent of the other renderer).
TEST_F(LlvmpipePeer, FanAroundASample) {
  constexpr int kFanTriangles = 16;
  constexpr double kRadius = 40.0;
  for (const glm::vec2 c : {glm::vec2(centre(64), centre(64)), sample4(63, 61, 1)}) {
    SCOPED_TRACE("centre " + std::to_string(c.x) + ", " + std::to_string(c.y));
    std::vector<glm::vec2> rim;
    for (int k = 0; k < kFanTriangles; ++k) {
      const double a = 2.0 * 3.14159265358979 * k / kFanTriangles;
      // Rim vertices on the 1/256 grid (a convex polygon still); every fourth lies a whole
      // number of pixels from the centre, so on a sample position too.
      rim.emplace_back(px(static_cast<int>(std::lround((c.x + kRadius * std::cos(a)) * 256))),
                       px(static_cast<int>(std::lround((c.y + kRadius * std::sin(a)) * 256))));
    }
    std::vector<Tri> fan, from_vertex;
    for (int k = 0; k < kFanTriangles; ++k) {
      const glm::vec2 a = rim[k], b = rim[(k + 1) % kFanTriangles];
      fan.push_back({{glm::vec3(c, 0.5f), glm::vec3(a, 0.5f), glm::vec3(b, 0.5f)}, color_of(k)});
      if (k >= 1 && k + 1 < kFanTriangles)
        from_vertex.push_back(
            {{glm::vec3(rim[0], 0.5f), glm::vec3(a, 0.5f), glm::vec3(b, 0.5f)}, color_of(k)});
    }
    compare(make_scene(fan), false);
    for (int samples : {1, 4}) {
      const Result g1 = gl(with_state(make_scene(fan), false), samples);
      const Result g2 = gl(with_state(make_scene(from_vertex), false), samples);
      EXPECT_EQ(g1.samples, g2.samples) << "llvmpipe is not watertight, samples " << samples;
      const Result m1 = mosaic_render(with_state(make_scene(fan), false), samples);
      const Result m2 = mosaic_render(with_state(make_scene(from_vertex), false), samples);
      EXPECT_EQ(m1.samples, m2.samples) << "mosaic is not watertight, samples " << samples;
    }
  }
}

// A jittered grid covering the whole image, its quads split along a random diagonal, each
// triangle in a random winding, interior vertices on pixel centres and 4x sample positions:
// shared edges in both windings, and every sample covered exactly once — so both renderers
// must count exactly width × height × samples.
TEST_F(LlvmpipePeer, SharedEdgesInBothWindingsCoverEverySampleOnce) {
  constexpr int kCells = 8;
  constexpr int kCell = kSize / kCells;
  std::mt19937 rng(7);  // mt19937's sequence is fixed by the standard
  std::array<std::array<glm::vec2, kCells + 1>, kCells + 1> grid;
  for (int j = 0; j <= kCells; ++j) {
    for (int i = 0; i <= kCells; ++i) {
      glm::vec2 p(static_cast<float>(i * kCell), static_cast<float>(j * kCell));
      if (i > 0 && i < kCells && j > 0 && j < kCells) {
        const int x = i * kCell + static_cast<int>(rng() % 5) - 2;
        const int y = j * kCell + static_cast<int>(rng() % 5) - 2;
        const auto kind = rng() % 3;  // pixel centre, 4x sample, or any 1/256 point
        if (kind == 0) p = {centre(x), centre(y)};
        if (kind == 1) p = sample4(x, y, static_cast<int>(rng() % 4));
        if (kind == 2) p = {px(x * 256 + static_cast<int>(rng() % 256)), px(y * 256 + 77)};
      }
      grid[j][i] = p;
    }
  }
  std::vector<Tri> tris;
  for (int j = 0; j < kCells; ++j) {
    for (int i = 0; i < kCells; ++i) {
      const glm::vec2 a = grid[j][i], b = grid[j][i + 1], c = grid[j + 1][i + 1],
                      d = grid[j + 1][i];
      std::array<std::array<glm::vec2, 3>, 2> halves =
          rng() % 2 ? std::array<std::array<glm::vec2, 3>, 2>{{{a, b, c}, {a, c, d}}}
                    : std::array<std::array<glm::vec2, 3>, 2>{{{a, b, d}, {b, c, d}}};
      for (auto& h : halves) {
        if (rng() % 2) std::swap(h[1], h[2]);
        const float z = 0.05f + 0.9f * static_cast<float>(tris.size()) / (2 * kCells * kCells);
        tris.push_back(
            {{glm::vec3(h[0], z), glm::vec3(h[1], z), glm::vec3(h[2], z)}, color_of(tris.size())});
      }
    }
  }
  const mosaic::Scene base = make_scene(tris);
  for (int samples : {1, 4}) {
    const auto all = static_cast<std::uint64_t>(kSize) * kSize * samples;
    EXPECT_EQ(gl(with_state(base, false), samples).samples, all) << "llvmpipe, " << samples;
    EXPECT_EQ(mosaic_render(with_state(base, false), samples).samples, all)
        << "mosaic, " << samples;
  }
  compare(base, true);  // constant, distinct depth per triangle: no ties
}

// Random triangles whose vertices lie on pixel centres or 4x sample positions, overlapping,
// drawn in an order unrelated to depth; each triangle's depth slopes within its own band, so
// the depth test decides every overlap and no two triangles ever tie.
TEST_F(LlvmpipePeer, VerticesOnSamplesWithDepth) {
  constexpr int kTriangles = 60;
  std::mt19937 rng(11);
  // Depth bands: a permutation (Fisher–Yates), so that depth is unrelated to draw order.
  std::array<int, kTriangles> bands;
  for (int k = 0; k < kTriangles; ++k) bands[k] = k;
  for (int k = kTriangles - 1; k > 0; --k) std::swap(bands[k], bands[rng() % (k + 1)]);
  std::vector<Tri> tris;
  for (int k = 0; k < kTriangles; ++k) {
    const int band = bands[k];
    const float z0 = (static_cast<float>(band) + 0.1f) / kTriangles;
    Tri t;
    t.color = color_of(static_cast<std::size_t>(k));
    for (int v = 0; v < 3; ++v) {
      const int x = static_cast<int>(rng() % kSize), y = static_cast<int>(rng() % kSize);
      const glm::vec2 p =
          rng() % 2 ? glm::vec2(centre(x), centre(y)) : sample4(x, y, static_cast<int>(rng() % 4));
      t.v[v] = glm::vec3(p, z0 + 0.25f * static_cast<float>(v) / kTriangles);
    }
    tris.push_back(t);
  }
  compare(make_scene(tris), true);
}

// Triangles with three different vertex colours, interpolated (llvmpipe: `smooth`): coverage is
// the same as ever, and colours may differ only by rounding — both interpolate the same linear
// function in float at the pixel centre, and the .tris format does not fix the rounding.
TEST_F(LlvmpipePeer, SmoothColoursDifferByRoundingOnly) {
  constexpr int kTriangles = 30;
  constexpr int kMaxRoundingDifference = 1;
  std::mt19937 rng(5);
  mosaic::Scene base = make_scene({});
  mosaic::Mesh& m = base.meshes[0];
  m.color_source = mosaic::ColorSource::kPerVertex;
  m.colors.clear();
  for (int k = 0; k < kTriangles; ++k) {
    for (int v = 0; v < 3; ++v) {
      const int x = static_cast<int>(rng() % (kSize * 256)),
                y = static_cast<int>(rng() % (kSize * 256));
      m.positions.emplace_back(px(x), px(y), 0.5f, 1.0f);
      m.colors.push_back({static_cast<std::uint8_t>(rng() % 256),
                          static_cast<std::uint8_t>(rng() % 256),
                          static_cast<std::uint8_t>(rng() % 256), 255});
    }
  }
  for (int samples : {1, 4}) {
    const mosaic::Scene scene = with_state(base, false);
    const Result g = gl(scene, samples);
    const Result r = mosaic_render(scene, samples);
    EXPECT_EQ(g.samples, r.samples) << "samples " << samples;
    int worst = 0;
    for (std::size_t i = 0; i < g.image.size(); ++i) {
      worst =
          std::max({worst, std::abs(g.image[i].r - r.image[i].r),
                    std::abs(g.image[i].g - r.image[i].g), std::abs(g.image[i].b - r.image[i].b)});
    }
    EXPECT_LE(worst, kMaxRoundingDifference) << "samples " << samples;
  }
}

// A vertex exactly half-way between two 1/256 px steps snaps to the even step on both sides
// (llvmpipe's subpixel_snap is util_iround, round half to even). The left edge of this rectangle
// lies at 10.5 + 1/512 px and snaps to 10.5, through the centres of column 10, which the left-edge
// rule keeps (100 pixels); rounding the tie up would give 10.5 + 1/256 and leave column 10 out.
TEST_F(LlvmpipePeer, SnapTiesRoundLikeLlvmpipe) {
  const float l = 10.5f + 1.0f / 512.0f, r = 20.25f, t = 2.25f, b = 12.25f;
  const Rgba8 white{255, 255, 255, 255};
  const mosaic::Scene scene = with_state(
      make_scene({{{glm::vec3(l, t, 0.5f), glm::vec3(r, t, 0.5f), glm::vec3(r, b, 0.5f)}, white},
                  {{glm::vec3(l, t, 0.5f), glm::vec3(r, b, 0.5f), glm::vec3(l, b, 0.5f)}, white}},
                 32, 32),
      false);
  const Result m = mosaic_render(scene, 1);
  EXPECT_EQ(m.samples, 100u);
  EXPECT_EQ(gl(scene, 1).samples, m.samples);
}

// Back-face culling keeps the same triangles on both sides: the mapping of mosaic's front face
// (counter-clockwise as seen, y down) onto GL's under GL_UPPER_LEFT.
TEST_F(LlvmpipePeer, CullingKeepsTheSameWinding) {
  const Rgba8 red{255, 0, 0, 255}, green{0, 255, 0, 255};
  // On screen (y down), a → b → c turns counter-clockwise: right, then up.
  const glm::vec3 a(8.5f, 50.25f, 0.5f), b(50.5f, 50.25f, 0.5f), c(50.5f, 8.75f, 0.5f);
  mosaic::Scene base = make_scene(
      {{{a, b, c}, red},
       {{a + glm::vec3(60, 0, 0), c + glm::vec3(60, 0, 0), b + glm::vec3(60, 0, 0)}, green}});
  for (const mosaic::CullMode cull : {mosaic::CullMode::kBack, mosaic::CullMode::kFront}) {
    mosaic::Scene scene = with_state(base, false);
    scene.for_each_state([&](mosaic::DrawState& s) { s.cull = cull; });
    const Result g = gl(scene, 1);
    const Result m = mosaic_render(scene, 1);
    EXPECT_TRUE(g.image == m.image) << diff(g.image, m.image, scene.width);
    EXPECT_EQ(g.samples, m.samples);
    // Counter-clockwise is front by default: back-face culling keeps only the red triangle,
    // front-face culling only the green one.
    const bool back = cull == mosaic::CullMode::kBack;
    EXPECT_EQ(g.image[40 * kSize + 45], back ? red : base.clear_color);
    EXPECT_EQ(g.image[40 * kSize + 105], back ? base.clear_color : green);
  }
}

}  // namespace
