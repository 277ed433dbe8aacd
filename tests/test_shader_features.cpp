// Shader features (mosaic/shader.hpp): discard, the front-facing flag and analytic derivatives
// of the varyings.
//
// Each against hand-known values (a discarded quad shows what is behind it and writes no depth;
// a triangle's facing follows its winding and DrawState::front_face; an affine varying's
// derivative is its slope, and a perspective one's matches a finite difference), and against the
// reference bit for bit on every ISA, at 1x, 4x and 16x MSAA, 4x SSAA, with blending, the
// painter's order and 1 or 2 threads, on random clip-space scenes with culling off.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "reference_test_util.hpp"

namespace mosaic {
namespace {

using test::simd_isas;

constexpr Rgba8 kBackground{10, 20, 30, 255};

test::Captured render(std::span<const Draw> draws, int w, int h, int samples, bool ssaa, Isa isa,
                      int threads = 2, bool painter = false) {
  return test::render_draws(draws, w, h, {samples, ssaa, isa, threads, painter}, kBackground);
}

/// Screen-space vertices and one attribute pair (u, v) per vertex.
struct ScreenGeometry {
  std::vector<glm::vec4> pos;
  std::vector<float> attr;
  void vertex(float x, float y, float z, float u, float v) {
    pos.emplace_back(x, y, z, 1.0f);
    attr.insert(attr.end(), {u, v});
  }
  /// An axis-aligned quad [x0, x1) × [y0, y1) at depth z, with u = x and v = y.
  void quad(float x0, float y0, float x1, float y1, float z) {
    vertex(x0, y0, z, x0, y0);
    vertex(x1, y0, z, x1, y0);
    vertex(x1, y1, z, x1, y1);
    vertex(x0, y0, z, x0, y0);
    vertex(x1, y1, z, x1, y1);
    vertex(x0, y1, z, x0, y1);
  }
};

const std::vector<std::uint32_t> kUv{0, 1};

Draw screen_draw(const ScreenGeometry& g, std::size_t first, std::size_t count, Shader shader) {
  Draw d;
  d.space = Space::kScreen;
  d.positions = std::span<const glm::vec4>(g.pos).subspan(first, count);
  d.attributes = std::span<const float>(g.attr).subspan(2 * first, 2 * count);
  d.attribute_count = 2;
  d.varyings = kUv;
  d.shader = std::move(shader);
  return d;
}

/// Keeps pixels whose column (u) is even, red; discards the odd ones.
Shader even_columns_shader() {
  return make_shader(
      [](const Fragment& f) -> std::optional<glm::vec4> {
        if (static_cast<int>(std::floor(f.varying(0))) % 2 != 0) return std::nullopt;
        return glm::vec4(1, 0, 0, 1);
      },
      2);
}

TEST(ShaderFeatures, OptionalReturnImpliesDiscardsAndPlainDoesNot) {
  EXPECT_TRUE(even_columns_shader().uses().discards);
  EXPECT_FALSE(make_shader([](const Fragment&) { return glm::vec4(1); }).uses().discards);
  const Shader batch =
      make_shader([](const ShaderInput&, ShaderOutput&) {}, ShaderUses{0, true, true});
  EXPECT_TRUE(batch.uses().discards);
  EXPECT_TRUE(batch.uses().derivatives);
}

TEST(ShaderFeatures, DiscardedPixelsShowWhatIsBehindAndWriteNoDepth) {
  // A near quad that discards its odd columns, drawn before a far green quad: the green quad
  // shows through exactly the odd columns, and the near quad's depth is only in the even ones.
  constexpr int kW = 40, kH = 24;
  ScreenGeometry g;
  g.quad(4, 4, 36, 20, 0.2f);  // near, discarding
  g.quad(0, 0, 40, 24, 0.6f);  // far, green
  const Draw near = screen_draw(g, 0, 6, even_columns_shader());
  Draw far = screen_draw(g, 6, 6, Shader());
  far.shader = make_shader([](const Fragment&) { return glm::vec4(0, 1, 0, 1); }, 0);
  const std::vector<Draw> draws{near, far};
  for (const Isa isa : available_isas()) {
    const auto out = render(draws, kW, kH, 1, false, isa);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const bool inside = x >= 4 && x < 36 && y >= 4 && y < 20;
        const Rgba8 want = inside && x % 2 == 0 ? Rgba8{255, 0, 0, 255} : Rgba8{0, 255, 0, 255};
        const std::size_t i = static_cast<std::size_t>(y) * kW + x;
        ASSERT_EQ(out.color[i], want) << to_string(isa) << " pixel " << x << "," << y;
        ASSERT_EQ(out.sample_depth[i], inside && x % 2 == 0 ? 0.2f : 0.6f) << x << "," << y;
      }
    // Written: 16 × 16 kept pixels of the near quad, then every pixel but those of the far one.
    EXPECT_EQ(out.stats.samples_written, 16u * 16u + (kW * kH - 16u * 16u)) << to_string(isa);
  }
}

TEST(ShaderFeatures, FrontFacingFollowsWindingAndFrontFace) {
  // Two screen triangles, one clockwise and one counter-clockwise on screen (y down); the
  // shader paints front faces white and back faces black.
  ScreenGeometry g;
  g.vertex(2, 2, 0.5f, 0, 0);  // clockwise on screen: left pixel block
  g.vertex(14, 2, 0.5f, 0, 0);
  g.vertex(2, 14, 0.5f, 0, 0);
  g.vertex(18, 2, 0.5f, 0, 0);  // counter-clockwise on screen: right
  g.vertex(18, 14, 0.5f, 0, 0);
  g.vertex(30, 2, 0.5f, 0, 0);
  const Shader facing = make_shader(
      [](const Fragment& f) { return f.front_facing() ? glm::vec4(1) : glm::vec4(0, 0, 0, 1); }, 0);
  for (const FrontFace ff : {FrontFace::kCounterClockwise, FrontFace::kClockwise}) {
    Draw d = screen_draw(g, 0, 6, facing);
    d.state.front_face = ff;
    const std::vector<Draw> draws{d};
    for (const Isa isa : available_isas()) {
      const auto out = render(draws, 32, 16, 4, false, isa);
      const Rgba8 left = out.color[4 * 32 + 4], right = out.color[4 * 32 + 20];
      // Counter-clockwise on screen is what kCounterClockwise calls front.
      const bool right_front = ff == FrontFace::kCounterClockwise;
      EXPECT_EQ(right.r, right_front ? 255 : 0) << to_string(isa);
      EXPECT_EQ(left.r, right_front ? 0 : 255) << to_string(isa);
    }
  }
}

/// Writes varying 0's derivatives, offset and scaled to 8 bits: r = 0.5 + ddx, g = 0.5 + ddy.
Shader slope_shader(float scale) {
  return make_shader(
      [scale](const Fragment& f) {
        return glm::vec4(0.5f + scale * f.ddx(0), 0.5f + scale * f.ddy(0), 0.5f + scale * f.ddx(1),
                         1.0f);
      },
      ShaderUses{2, true, false});
}

TEST(ShaderFeatures, AffineDerivativesAreTheSlopes) {
  // In screen space (w = 1) with u = 0.1 x + 0.05 y and v = -0.2 x: the derivatives are the
  // constants, read back through a shader that records them per pixel.
  std::vector<float> seen_dx, seen_dy, seen_vx;
  const Shader record = make_shader(
      [](const ShaderInput& in, ShaderOutput& out) {
        for (int l = 0; l < kShaderBatch; ++l) {
          out.r[l] = in.ddx[0][l];
          out.g[l] = in.ddy[0][l];
          out.b[l] = -in.ddx[1][l];
          out.a[l] = 1.0f;
        }
      },
      ShaderUses{2, true, false});
  ScreenGeometry g;
  const auto vtx = [&](float x, float y) { g.vertex(x, y, 0.5f, 0.1f * x + 0.05f * y, -0.2f * x); };
  vtx(1, 1);
  vtx(60, 5);
  vtx(9, 40);
  const std::vector<Draw> draws{screen_draw(g, 0, 3, record)};
  for (const Isa isa : available_isas()) {
    const auto out = render(draws, 64, 48, 1, false, isa);
    std::size_t drawn = 0;
    for (const Rgba8 c : out.color) {
      if (c == kBackground) continue;
      ++drawn;
      // 0.1 · 255 = 25.5 rounds up to 26; 0.05 · 255 = 12.75 to 13; 0.2 · 255 = 51.
      ASSERT_EQ(c.r, 26) << to_string(isa);
      ASSERT_EQ(c.g, 13) << to_string(isa);
      ASSERT_EQ(c.b, 51) << to_string(isa);
    }
    EXPECT_GT(drawn, 500u) << to_string(isa);
  }
}

TEST(ShaderFeatures, PerspectiveDerivativesMatchFiniteDifferences) {
  // A clip-space triangle with w from 1 to 4: at a few pixel centres, the analytic derivative
  // against a central difference of the perspective-correct varying one pixel either side.
  const std::vector<glm::vec4> pos{
      {-0.9f, -0.9f, 0.1f, 1.0f}, {3.6f, -2.0f, 0.5f, 4.0f}, {-1.5f, 2.7f, 0.9f, 3.0f}};
  const std::vector<float> attr{0.0f, 1.0f, 8.0f, -3.0f, 2.0f, 5.0f};
  struct Probe {
    float v, dx, dy;
  };
  constexpr int kW = 96, kH = 96;
  // Records every lane's (x, y, u, du/dx, du/dy) into the probe grid (one shader thread: the
  // test renders with one thread; writes are per pixel).
  static std::vector<Probe> grid;
  grid.assign(kW * kH, Probe{NAN, NAN, NAN});
  const Shader record = make_shader(
      [](const ShaderInput& in, ShaderOutput& out) {
        for (int l = 0; l < kShaderBatch; ++l) {
          if ((in.active >> l) & 1u) {
            const int px = static_cast<int>(in.x[l]), py = static_cast<int>(in.y[l]);
            grid[static_cast<std::size_t>(py) * kW + px] = {in.varying[0][l], in.ddx[0][l],
                                                            in.ddy[0][l]};
          }
          out.r[l] = out.g[l] = out.b[l] = out.a[l] = 1.0f;
        }
      },
      ShaderUses{2, true, false});
  Draw d;
  d.positions = pos;
  d.attributes = attr;
  d.attribute_count = 2;
  d.varyings = kUv;
  d.shader = record;
  const std::vector<Draw> draws{d};
  render(draws, kW, kH, 1, false, Isa::kReference, 1);
  int checked = 0;
  for (int y = 1; y + 1 < kH; ++y)
    for (int x = 1; x + 1 < kW; ++x) {
      const auto at = [&](int px, int py) { return grid[static_cast<std::size_t>(py) * kW + px]; };
      const Probe c = at(x, y), l = at(x - 1, y), r = at(x + 1, y), u = at(x, y - 1),
                  dn = at(x, y + 1);
      if (std::isnan(c.v) || std::isnan(l.v) || std::isnan(r.v) || std::isnan(u.v) ||
          std::isnan(dn.v))
        continue;
      // The second derivative of a ratio of planes is small next to the first over one pixel.
      EXPECT_NEAR(c.dx, (r.v - l.v) / 2, 2e-3 + 0.02 * std::abs(c.dx)) << x << "," << y;
      EXPECT_NEAR(c.dy, (dn.v - u.v) / 2, 2e-3 + 0.02 * std::abs(c.dy)) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 1000);
}

/// Random clip-space triangles, both windings, culling off; attributes (u, v, w) per vertex.
struct RandomScene {
  std::vector<glm::vec4> pos;
  std::vector<float> attr;
  explicit RandomScene(std::uint64_t seed, int triangles) {
    test::Rng rng(seed);
    for (int i = 0; i < triangles * 3; ++i) {
      const double wv = rng.uniform(-0.3, 3.0);
      pos.emplace_back(static_cast<float>(rng.uniform(-1.4, 1.4) * std::abs(wv)),
                       static_cast<float>(rng.uniform(-1.4, 1.4) * std::abs(wv)),
                       static_cast<float>(rng.uniform(-0.1, 1.1) * wv), static_cast<float>(wv));
      for (int a = 0; a < 3; ++a) attr.push_back(static_cast<float>(rng.uniform(-4, 4)));
    }
  }
  Draw draw(Shader shader, BlendMode blend) const {
    Draw d;
    d.positions = pos;
    d.attributes = attr;
    d.attribute_count = 3;
    d.varyings = varyings;
    d.shader = std::move(shader);
    d.state.blend = blend;
    return d;
  }
  std::vector<std::uint32_t> varyings{2, 0, 1};
};

/// Uses all three features: discards where a non-linear function of the varyings is negative,
/// colours by facing and by the derivatives.
Shader everything_shader() {
  return make_shader(
      [](const Fragment& f) -> std::optional<glm::vec4> {
        const float a = f.varying(0), b = f.varying(1);
        if (std::sin(2.0f * a) * std::cos(1.5f * b) < -0.3f) return std::nullopt;
        const float side = f.front_facing() ? 0.9f : 0.2f;
        return glm::vec4(side, 0.5f + 0.1f * f.ddx(1), 0.5f + 0.1f * f.ddy(2),
                         0.4f + 0.05f * std::abs(f.ddx(0)));
      },
      ShaderUses{3, true, true});
}

TEST(ShaderFeatures, RandomScenesMatchTheReferenceOnEveryPath) {
  const int w = 141, h = 117;
  const RandomScene scene(77, 160);
  struct Mode {
    int samples;
    bool ssaa;
  };
  for (const BlendMode blend : {BlendMode::kNone, BlendMode::kSourceOver}) {
    // A discarding draw between two that do not, so the queue and the late depth meet.
    const std::vector<Draw> draws{scene.draw(slope_shader(0.05f), BlendMode::kNone),
                                  scene.draw(everything_shader(), blend),
                                  scene.draw(slope_shader(0.02f), blend)};
    for (const bool painter : {false, true})
      for (const Mode m : {Mode{1, false}, Mode{4, false}, Mode{4, true}, Mode{16, false}}) {
        const auto ref = render(draws, w, h, m.samples, m.ssaa, Isa::kReference, 1, painter);
        EXPECT_GT(ref.stats.samples_written, 0u);
        for (const Isa isa : simd_isas())
          for (const int threads : {1, 2})
            test::expect_same(ref, render(draws, w, h, m.samples, m.ssaa, isa, threads, painter),
                              std::to_string(m.samples) + "x ssaa " + std::to_string(m.ssaa) +
                                  " blend " + std::to_string(int(blend)) + " painter " +
                                  std::to_string(painter) + " " + to_string(isa) + " threads " +
                                  std::to_string(threads));
      }
  }
}

TEST(ShaderFeatures, DiscardingEverythingWritesNothing) {
  const RandomScene scene(5, 60);
  const std::vector<Draw> draws{scene.draw(
      make_shader([](const Fragment&) -> std::optional<glm::vec4> { return std::nullopt; }, 0),
      BlendMode::kNone)};
  for (const Isa isa : available_isas()) {
    const auto out = render(draws, 64, 64, 4, false, isa);
    EXPECT_EQ(out.stats.samples_written, 0u) << to_string(isa);
    EXPECT_GT(out.stats.triangles_drawn, 0u) << to_string(isa);
    for (const Rgba8 c : out.color) ASSERT_EQ(c, kBackground) << to_string(isa);
    for (const float z : out.sample_depth) ASSERT_EQ(z, 1.0f) << to_string(isa);
  }
}

}  // namespace
}  // namespace mosaic
