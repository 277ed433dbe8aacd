// Viewport and scissor (DrawState::viewport, DrawState::scissor; front/draw_area.hpp) through
// Renderer::render(), on the reference and every SIMD path:
// - a draw through a viewport equals, bit for bit, the same draw into a target of the viewport's
//   size, wherever the viewport lies: aligned to tiles or not, partly past the target's edges,
//   several viewports in one frame (split screen);
// - a scissored frame holds, in every sample inside the scissor, what the unscissored frame
//   holds there, and the clear values everywhere else (a sample's value depends only on the
//   triangles that cover it), with the scissor's edges on and beside block and tile edges;
// - the binner skips tiles outside the scissor, and a bad rectangle is a clear error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "reference_test_util.hpp"

namespace {

using namespace mosaic;

constexpr int kSamples = 4;
constexpr int kBigW = 200, kBigH = 150;  ///< two tile columns of 128 px, cut by the edge
constexpr int kSmallW = 75, kSmallH = 58;

/// An indexed grid in perspective, crossing the near plane, shaded from its normals: the vertex
/// stage, clipping and the varyings' planes all see the viewport.
struct Grid {
  std::vector<glm::vec4> clip;
  std::vector<float> normals;
  std::vector<std::uint32_t> indices;
};

Grid make_grid(float aspect) {
  constexpr int kCells = 16;
  const glm::mat4 to_unit_depth(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 1);
  const glm::mat4 vp =
      to_unit_depth * glm::perspective(glm::radians(65.0f), aspect, 0.5f, 40.0f) *
      glm::lookAt(glm::vec3(0.2f, 0.4f, 1.2f), glm::vec3(0.0f, 0.0f, -6.0f), glm::vec3(0, 1, 0));
  Grid g;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const float x = -6.0f + 12.0f * float(i) / kCells, z = 3.0f - 20.0f * float(j) / kCells;
      const glm::vec3 p(x, 0.5f * std::sin(1.1f * x) * std::cos(0.9f * z), z);
      g.clip.push_back(vp * glm::vec4(p, 1.0f));
      const glm::vec3 n = glm::normalize(glm::vec3(-0.5f * std::cos(1.1f * x), 1.0f, 0.3f));
      g.normals.insert(g.normals.end(), {n.x, n.y, n.z});
    }
  g.indices = test::grid_indices(kCells);
  return g;
}

const std::uint32_t kNormalVaryings[] = {0, 1, 2};

/// The scene of the viewport tests: the shaded grid, then random screen-space triangles (their
/// coordinates count from the viewport's corner) over and past a kSmallW × kSmallH area, some
/// blending. Valid while `grid` and `meshes` live.
std::vector<Draw> scene(const Grid& grid, const std::vector<Mesh>& meshes) {
  Draw g;
  g.positions = grid.clip;
  g.indices = grid.indices;
  g.attributes = grid.normals;
  g.attribute_count = 3;
  g.varyings = kNormalVaryings;
  g.shader = normal_color_shader();
  std::vector<Draw> draws{g};
  for (const Mesh& m : meshes) draws.push_back(m.draw());
  return draws;
}

std::vector<Isa> every_isa() { return available_isas(); }

std::string name(Isa isa, int threads) {
  return std::string(to_string(isa)) + ", " + std::to_string(threads) + " threads";
}

test::Captured render(std::vector<Draw> draws, int w, int h, Isa isa, int threads,
                      std::optional<PixelRect> viewport, std::optional<PixelRect> scissor,
                      bool painter = false) {
  for (Draw& d : draws) {
    d.state.viewport = viewport;
    d.state.scissor = scissor;
  }
  RenderTarget target = test::sample_target(w, h, kSamples);
  Renderer r({.threads = threads, .isa = isa});
  Frame frame;
  frame.draws = draws;
  frame.painter = painter;
  return test::capture(r, frame, target);
}

bool same_depth(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

/// Compares the big target's capture with the small one's placed at (vx, vy): equal where they
/// overlap, the clear values elsewhere in the big one. Returns the mismatches.
std::size_t placed_mismatches(const test::Captured& small, const test::Captured& big, int vx,
                              int vy) {
  std::size_t bad = 0;
  for (int y = 0; y < kBigH; ++y)
    for (int x = 0; x < kBigW; ++x) {
      const int sx = x - vx, sy = y - vy;
      const bool inside = sx >= 0 && sy >= 0 && sx < kSmallW && sy < kSmallH;
      const std::size_t bp = static_cast<std::size_t>(y) * kBigW + static_cast<std::size_t>(x);
      const std::size_t sp = static_cast<std::size_t>(sy) * kSmallW + static_cast<std::size_t>(sx);
      if (inside ? !(big.color[bp] == small.color[sp]) : !(big.color[bp] == test::kClear)) ++bad;
      for (int s = 0; s < kSamples; ++s) {
        const std::size_t bi = bp * kSamples + static_cast<std::size_t>(s);
        const std::size_t si = sp * kSamples + static_cast<std::size_t>(s);
        if (inside) {
          bad += !(big.sample_color[bi] == small.sample_color[si]);
          bad += !same_depth(big.sample_depth[bi], small.sample_depth[si]);
        } else {
          bad += !(big.sample_color[bi] == test::kClear);
          bad += !same_depth(big.sample_depth[bi], 1.0f);
        }
      }
    }
  return bad;
}

// The viewport is the transform: the same frame into a kSmallW × kSmallH target and through
// such a viewport of a larger one, at block-, tile- and unaligned offsets, against the far
// corner, and partly off every edge.
TEST(Viewport, DrawingThroughAViewportEqualsDrawingIntoASmallerTarget) {
  const Grid grid = make_grid(float(kSmallW) / float(kSmallH));
  test::Rng rng(7);
  const std::vector<Mesh> meshes = test::random_draws(kSmallW, kSmallH, 3, 60, rng);
  const std::vector<Draw> draws = scene(grid, meshes);
  const int offsets[][2] = {{0, 0},     {64, 8},   {13, 7},   {kBigW - kSmallW, kBigH - kSmallH},
                            {120, 100}, {-21, -9}, {150, -30}};
  const test::Captured want =
      render(draws, kSmallW, kSmallH, Isa::kReference, 1, std::nullopt, std::nullopt);
  ASSERT_GT(want.stats.triangles_clipped, 0u);
  ASSERT_GT(want.stats.triangles_drawn, 150u);
  for (Isa isa : every_isa())
    for (int threads : {1, 2, 3}) {
      if (isa == Isa::kReference && threads > 1) continue;
      const test::Captured small =
          render(draws, kSmallW, kSmallH, isa, threads, std::nullopt, std::nullopt);
      test::expect_same(want, small, name(isa, threads));
      for (const auto& o : offsets) {
        const PixelRect vp{o[0], o[1], kSmallW, kSmallH};
        const std::string what = name(isa, threads) + ", viewport at " + std::to_string(o[0]) +
                                 ", " + std::to_string(o[1]);
        const test::Captured big = render(draws, kBigW, kBigH, isa, threads, vp, std::nullopt);
        EXPECT_EQ(placed_mismatches(want, big, o[0], o[1]), 0u) << what;
        const bool within =
            o[0] >= 0 && o[1] >= 0 && o[0] + kSmallW <= kBigW && o[1] + kSmallH <= kBigH;
        if (within) {  // nothing is cut off: every counter of the triangles agrees
          EXPECT_EQ(big.stats.triangles_drawn, want.stats.triangles_drawn) << what;
          EXPECT_EQ(big.stats.triangles_outside, want.stats.triangles_outside) << what;
          EXPECT_EQ(big.stats.triangles_no_sample, want.stats.triangles_no_sample) << what;
          EXPECT_EQ(big.stats.samples_written, want.stats.samples_written) << what;
        }
      }
    }
}

// Split screen: two draws of one frame through two viewports side by side, each equal to its
// own small-target render, and a kScreen draw counts from its viewport's corner.
TEST(Viewport, SplitScreenDrawsEachViewportAsItsOwnTarget) {
  const Grid grid = make_grid(float(kSmallW) / float(kSmallH));
  test::Rng rng(11);
  const std::vector<Mesh> meshes = test::random_draws(kSmallW, kSmallH, 1, 40, rng);
  const std::vector<Draw> left = scene(grid, {}), right = scene(grid, meshes);
  const test::Captured want_left =
      render(left, kSmallW, kSmallH, Isa::kReference, 1, std::nullopt, std::nullopt);
  const test::Captured want_right =
      render(right, kSmallW, kSmallH, Isa::kReference, 1, std::nullopt, std::nullopt);
  for (Isa isa : every_isa()) {
    std::vector<Draw> both;
    for (Draw d : left) {
      d.state.viewport = PixelRect{3, 40, kSmallW, kSmallH};
      both.push_back(d);
    }
    for (Draw d : right) {
      d.state.viewport = PixelRect{3 + kSmallW, 40, kSmallW, kSmallH};
      both.push_back(d);
    }
    RenderTarget target = test::sample_target(kBigW, kBigH, kSamples);
    Renderer r({.threads = 2, .isa = isa});
    Frame frame;
    frame.draws = both;
    const test::Captured got = test::capture(r, frame, target);
    // Each half, read from the big target, against its own render.
    for (int half = 0; half < 2; ++half) {
      const test::Captured& want = half ? want_right : want_left;
      const int vx = 3 + half * kSmallW, vy = 40;
      std::size_t bad = 0;
      for (int y = 0; y < kSmallH; ++y)
        for (int x = 0; x < kSmallW; ++x)
          for (int s = 0; s < kSamples; ++s) {
            const std::size_t b = test::sample_index(target, x + vx, y + vy, s);
            const std::size_t w =
                (static_cast<std::size_t>(y) * kSmallW + static_cast<std::size_t>(x)) * kSamples +
                static_cast<std::size_t>(s);
            bad += !(got.sample_color[b] == want.sample_color[w]);
            bad += !same_depth(got.sample_depth[b], want.sample_depth[w]);
          }
      EXPECT_EQ(bad, 0u) << to_string(isa) << ", half " << half;
    }
  }
}

/// Scissors at the thresholds: edges on a block edge (8 px), one pixel either side, on the tile
/// edge (128 px), a single pixel, empty, reaching past the target, and the whole target.
const PixelRect kScissors[] = {
    {8, 16, 120, 112},
    {7, 15, 122, 114},
    {9, 17, 118, 110},
    {127, 0, 2, kBigH},
    {128, 64, 40, 1},
    {50, 60, 1, 1},
    {60, 40, 0, 30},
    {-40, -40, 100, 90},
    {190, 140, 500, 90},
    {0, 0, kBigW, kBigH},
    {-16384, -16384, 16384, 16384},
};

// The scissor keeps exactly its samples of the unscissored frame, on every ISA, 1 and 3 threads,
// with and without the painter's algorithm (whose runs mix draws), and with a viewport too
// (the two intersect).
TEST(Scissor, KeepsExactlyItsSamplesOfTheUnscissoredFrame) {
  const Grid grid = make_grid(float(kBigW) / float(kBigH));
  test::Rng rng(5);
  const std::vector<Mesh> meshes = test::random_draws(kBigW, kBigH, 3, 120, rng);
  const std::vector<Draw> draws = scene(grid, meshes);
  for (bool painter : {false, true}) {
    const test::Captured full =
        render(draws, kBigW, kBigH, Isa::kReference, 1, std::nullopt, std::nullopt, painter);
    ASSERT_GT(full.stats.samples_written, 10000u);
    for (const PixelRect& sc : kScissors)
      for (const std::optional<PixelRect> vp :
           {std::optional<PixelRect>{}, std::optional<PixelRect>{PixelRect{0, 0, kBigW, 100}}}) {
        const auto kept = [&](int x, int y) {
          const bool in_vp = !vp || (y < vp->y + vp->height);
          return in_vp && x >= sc.x && y >= sc.y && x < sc.x + sc.width && y < sc.y + sc.height;
        };
        // With the viewport (the target's width, 100 px of its height) the clip-space grid is
        // mapped differently; its unscissored frame is rendered through the viewport alone.
        const test::Captured base =
            vp ? render(draws, kBigW, kBigH, Isa::kReference, 1, vp, std::nullopt, painter) : full;
        for (Isa isa : every_isa())
          for (int threads : {1, 3}) {
            if (isa == Isa::kReference && threads > 1) continue;
            const std::string what = name(isa, threads) + ", scissor " + std::to_string(sc.x) +
                                     "," + std::to_string(sc.y) + " " + std::to_string(sc.width) +
                                     "x" + std::to_string(sc.height) + (vp ? ", viewport" : "") +
                                     (painter ? ", painter" : "");
            const test::Captured got = render(draws, kBigW, kBigH, isa, threads, vp, sc, painter);
            std::size_t bad = 0;
            for (int y = 0; y < kBigH; ++y)
              for (int x = 0; x < kBigW; ++x)
                for (int s = 0; s < kSamples; ++s) {
                  const std::size_t i =
                      (static_cast<std::size_t>(y) * kBigW + static_cast<std::size_t>(x)) *
                          kSamples +
                      static_cast<std::size_t>(s);
                  if (kept(x, y)) {
                    bad += !(got.sample_color[i] == base.sample_color[i]);
                    bad += !same_depth(got.sample_depth[i], base.sample_depth[i]);
                  } else {
                    bad += !(got.sample_color[i] == test::kClear);
                    bad += !same_depth(got.sample_depth[i], 1.0f);
                  }
                }
            EXPECT_EQ(bad, 0u) << what;
          }
      }
  }
}

// Triangles wholly outside the scissor are counted as outside and binned nowhere; with the
// scissor inside one tile (of 128 px and of the 32 px such a frame is split into), no triangle
// is binned to two tiles (unscissored, many are).
TEST(Scissor, TheBinnerSkipsTilesOutsideIt) {
  Mesh m = test::screen_mesh();
  // Large triangles over both tile columns and rows, and small ones left of x = 100.
  for (int k = 0; k < 8; ++k)
    test::add_tri(m, {-10.0 + k, -10.0}, {kBigW + 20.0, 30.0 + k}, {30.0, kBigH + 20.0},
                  test::distinct_color(static_cast<std::uint32_t>(k)), 0.1f * float(k + 1) / 9);
  for (int k = 0; k < 20; ++k)
    test::add_tri(m, {10.0 + 4 * k, 10.0}, {12.0 + 4 * k, 10.0}, {11.0 + 4 * k, 14.0},
                  test::distinct_color(static_cast<std::uint32_t>(100 + k)));
  const std::vector<Draw> draws{m.draw()};
  for (Isa isa : every_isa()) {
    if (isa == Isa::kReference) continue;  // the reference has no bins
    const test::Captured full = render(draws, kBigW, kBigH, isa, 2, std::nullopt, std::nullopt);
    EXPECT_GT(full.stats.triangles_binned, full.stats.triangles_drawn) << to_string(isa);
    EXPECT_EQ(full.stats.triangles_outside, 0u) << to_string(isa);
    const test::Captured cut =
        render(draws, kBigW, kBigH, isa, 2, std::nullopt, PixelRect{130, 36, 20, 20});
    EXPECT_EQ(cut.stats.triangles_outside, 20u) << to_string(isa);
    EXPECT_EQ(cut.stats.triangles_drawn, 8u) << to_string(isa);
    EXPECT_EQ(cut.stats.triangles_binned, 8u) << to_string(isa);
  }
}

// A rectangle out of bounds is Error{kInvalidDraw}, thrown before anything is drawn: the
// target keeps its last frame.
TEST(BadDraw, ViewportsAndScissorsOutOfBounds) {
  Mesh m = test::screen_mesh();
  test::add_tri(m, {0, 0}, {40, 0}, {0, 40}, test::distinct_color(1));
  RenderTarget target = test::sample_target(64, 64, 1);
  Renderer r({.threads = 1});
  Frame frame;
  const std::vector<Draw> good{m.draw()};
  frame.draws = good;
  r.render(frame, target);
  const std::vector<Rgba8> before(target.color().begin(), target.color().end());
  const PixelRect bad_viewports[] = {
      {0, 0, 0, 10}, {0, 0, 10, -1}, {0, 0, 16385, 10}, {-16385, 0, 8, 8}, {0, 16385, 8, 8}};
  const PixelRect bad_scissors[] = {
      {0, 0, -1, 10}, {0, 0, 10, 16385}, {16385, 0, 1, 1}, {0, -16385, 1, 1}};
  const auto expect_rejected = [&](const DrawState& s, const std::string& what) {
    std::vector<Draw> draws{m.draw(), m.draw()};
    draws[1].state = s;
    frame.draws = draws;
    try {
      r.render(frame, target);
      ADD_FAILURE() << what << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kInvalidDraw) << what;
      EXPECT_NE(std::string(e.what()).find("draw 1"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(std::equal(before.begin(), before.end(), target.color().begin())) << what;
  };
  for (const PixelRect& v : bad_viewports) {
    DrawState s;
    s.viewport = v;
    expect_rejected(s, "viewport " + std::to_string(v.x) + "," + std::to_string(v.width));
  }
  for (const PixelRect& c : bad_scissors) {
    DrawState s;
    s.scissor = c;
    expect_rejected(s, "scissor " + std::to_string(c.x) + "," + std::to_string(c.width));
  }
  // The bounds themselves are accepted.
  DrawState edge;
  edge.viewport = PixelRect{-16384, 16384, 16384, 1};
  edge.scissor = PixelRect{16384, -16384, 0, 16384};
  std::vector<Draw> draws{m.draw()};
  draws[0].state = edge;
  frame.draws = draws;
  EXPECT_NO_THROW(r.render(frame, target));
}

}  // namespace
