// Fragment shaders, vertex attributes and blending (mosaic/shader.hpp, issue 7).
//
// A checkerboard computed from interpolated UVs on a ground plane seen at a grazing angle (and
// reaching behind the camera, so that the near plane clips it): the reference's image against the
// analytic checkerboard (ray-plane intersection per pixel centre), and every SIMD path against the
// reference bit for bit at 1x, 4x MSAA and 4x SSAA. Perspective correctness on the recorded
// varyings, with affine interpolation shown to be far off. Source-over blending in draw order
// against the reference and a hand-computed pixel; the built-in shaders against hand-computed
// values and against the colour sources they replace; random clip-space scenes with many
// varyings, blending and every sample count; bad input rejected with the target untouched;
// thread-count determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <limits>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "reference_test_util.hpp"
#include "shade/shading.hpp"

namespace mosaic {
namespace {

using test::simd_isas;

using Image = test::Captured;

constexpr Rgba8 kBackground{10, 20, 30, 255};

Image render(std::span<const Draw> draws, int w, int h, int samples, bool ssaa, Isa isa,
             int threads = 2, bool painter = false) {
  return test::render_draws(draws, w, h, {samples, ssaa, isa, threads, painter}, kBackground);
}

using test::expect_same;

// --- The grazing checkerboard ----------------------------------------------------------------

/// World units per checker cell side.
constexpr double kCell = 2.0;
/// The two checker colours, exact in 8 bits (k / 255 * 255 rounds back to k).
constexpr Rgba8 kLight{230, 225, 210, 255}, kDark{40, 60, 120, 255};

glm::vec4 to_unit(Rgba8 c) { return glm::vec4(c.r, c.g, c.b, c.a) / 255.0f; }

/// Parity of the cell of (u, v), in cell units; clamped so that an extrapolated lane far outside
/// the plane cannot overflow the conversion.
int cell_parity(double u, double v) {
  const double lim = 1e6;
  const auto cu = static_cast<long long>(std::floor(std::clamp(u, -lim, lim)));
  const auto cv = static_cast<long long>(std::floor(std::clamp(v, -lim, lim)));
  return static_cast<int>((cu + cv) & 1);
}

Shader checker_shader() {
  const glm::vec4 light = to_unit(kLight), dark = to_unit(kDark);
  return make_shader(
      [=](const Fragment& f) { return cell_parity(f.varying(0), f.varying(1)) ? light : dark; }, 2);
}

/// A ground plane y = 0 from 3 units behind the camera to 400 ahead, seen from 0.6 units above it
/// looking almost level: the checker cells shrink to a few pixels towards the horizon, and the
/// near plane clips the quad. UV = world (x, z) / kCell, as attributes 0 and 1 of a
/// 3-float vertex (attribute 2 is an unread distraction).
struct GroundPlane {
  int width = 0, height = 0;
  glm::dmat4 view_projection{1.0};
  std::vector<glm::vec4> clip;
  std::vector<float> attributes;
  std::vector<std::uint32_t> indices{0, 1, 2, 0, 2, 3};
  std::vector<std::uint32_t> varyings{0, 1};
  Shader shader = checker_shader();

  GroundPlane(int w, int h) : width(w), height(h) {
    const glm::dmat4 proj = glm::perspectiveRH_ZO(glm::radians(60.0), double(w) / h, 0.1, 500.0);
    const glm::dmat4 view =
        glm::lookAtRH(glm::dvec3(0.3, 0.6, 0), glm::dvec3(0.3, 0.35, -10), glm::dvec3(0, 1, 0));
    view_projection = proj * view;
    const double xs[4] = {-40, 40, 40, -40}, zs[4] = {3, 3, -400, -400};
    for (int i = 0; i < 4; ++i) {
      clip.push_back(glm::vec4(view_projection * glm::dvec4(xs[i], 0, zs[i], 1)));
      attributes.insert(attributes.end(), {static_cast<float>(xs[i] / kCell),
                                           static_cast<float>(zs[i] / kCell), 123.0f});
    }
  }

  Draw draw() const {
    Draw d;
    d.positions = clip;
    d.indices = indices;
    d.attributes = attributes;
    d.attribute_count = 3;
    d.varyings = varyings;
    d.shader = shader;
    return d;
  }

  /// Where the ray through pixel position (px, py) meets the plane, as UV; false above the
  /// horizon or behind the camera.
  bool uv_at(double px, double py, double& u, double& v) const {
    const glm::dmat4 inv = glm::inverse(view_projection);
    const double nx = 2 * px / width - 1, ny = 1 - 2 * py / height;
    glm::dvec4 a = inv * glm::dvec4(nx, ny, 0, 1), b = inv * glm::dvec4(nx, ny, 1, 1);
    const glm::dvec3 p0 = glm::dvec3(a) / a.w, p1 = glm::dvec3(b) / b.w;
    if (!(p1.y < p0.y)) return false;
    const double t = p0.y / (p0.y - p1.y);
    const glm::dvec3 hit = p0 + t * (p1 - p0);
    u = hit.x / kCell;
    v = hit.z / kCell;
    return hit.z < 3 && hit.z > -400 && std::abs(hit.x) < 40;
  }
};

TEST(Shaders, GrazingCheckerboardMatchesTheAnalyticCheckerboard) {
  const int w = 320, h = 200;
  const GroundPlane plane(w, h);
  const Draw draws[] = {plane.draw()};
  const Image ref = render(draws, w, h, 1, false, Isa::kReference, 1);
  EXPECT_GT(ref.stats.triangles_clipped, 0u) << "the plane should cross the near plane";
  // Every pixel centre whose analytic UV is clear of a cell border (by more than float
  // interpolation can err at these magnitudes, |uv| <= 200) must show that cell's colour.
  constexpr double kBorderMargin = 2e-3;
  std::size_t checked = 0, wrong = 0, light = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double u, v;
      if (!plane.uv_at(x + 0.5, y + 0.5, u, v)) continue;
      const double fu = u - std::floor(u), fv = v - std::floor(v);
      if (std::min({fu, 1 - fu, fv, 1 - fv}) < kBorderMargin) continue;
      const Rgba8 expected = cell_parity(u, v) ? kLight : kDark;
      const Rgba8 got = ref.color[static_cast<std::size_t>(y) * w + x];
      ++checked;
      light += expected == kLight;
      if (!(got == expected)) {
        if (++wrong <= 5) ADD_FAILURE() << "pixel " << x << "," << y << " uv " << u << "," << v;
      }
    }
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(checked, static_cast<std::size_t>(w * h / 3)) << "the plane should fill the lower half";
  EXPECT_GT(light, checked / 4);
  EXPECT_LT(light, checked * 3 / 4);
}

TEST(Shaders, GrazingCheckerboardIsBitIdenticalOnEveryPath) {
  const int w = 203, h = 141;  // tiles and blocks do not divide it
  const GroundPlane plane(w, h);
  const Draw draws[] = {plane.draw()};
  struct Mode {
    int samples;
    bool ssaa;
  };
  for (const Mode m : {Mode{1, false}, Mode{4, false}, Mode{4, true}, Mode{16, false}}) {
    const Image ref = render(draws, w, h, m.samples, m.ssaa, Isa::kReference, 1);
    for (Isa isa : simd_isas())
      expect_same(
          ref, render(draws, w, h, m.samples, m.ssaa, isa),
          std::to_string(m.samples) + "x ssaa " + std::to_string(m.ssaa) + " " + to_string(isa));
  }
}

// --- Perspective correctness on the values the shader receives --------------------------------

/// A shader that records (x, y, varying 0, varying 1) of every active lane. Not thread-safe: only
/// for the single-threaded reference.
struct Recorder {
  std::vector<std::array<float, 4>>* out;
  void operator()(const ShaderInput& in, ShaderOutput& res) const {
    for (int l = 0; l < kShaderBatch; ++l) {
      if ((in.active >> l) & 1)
        out->push_back({in.x[l], in.y[l], in.varying[0][l], in.varying[1][l]});
      res.r[l] = res.g[l] = res.b[l] = res.a[l] = 1.0f;
    }
  }
};

TEST(Shaders, VaryingsArePerspectiveCorrectAndAffineWouldNotBe) {
  // One triangle, all in front of the camera, with w from 1 to 40: the shader's varyings at each
  // pixel centre against the exact perspective-correct value (homogeneous barycentrics in
  // double), and against what affine (screen-space linear) interpolation would give.
  const int w = 128, h = 96;
  const glm::dmat4 vp =
      glm::perspectiveRH_ZO(glm::radians(70.0), double(w) / h, 0.5, 100.0) *
      glm::lookAtRH(glm::dvec3(0, 1, 0), glm::dvec3(0, 0.5, -10), glm::dvec3(0, 1, 0));
  const std::array<glm::dvec4, 3> world{glm::dvec4(-3, 0, -0.6, 1), glm::dvec4(4, 0, -1, 1),
                                        glm::dvec4(0, 0, -40, 1)};
  const std::array<std::array<double, 2>, 3> attr{{{0, 0}, {10, -3}, {2, 50}}};
  std::array<glm::dvec4, 3> clip;
  std::vector<glm::vec4> positions;
  std::vector<float> attributes;
  for (int i = 0; i < 3; ++i) {
    positions.push_back(glm::vec4(vp * world[i]));
    clip[i] = glm::dvec4(positions.back());
    attributes.insert(attributes.end(),
                      {static_cast<float>(attr[i][0]), static_cast<float>(attr[i][1])});
  }
  std::vector<std::array<float, 4>> seen;
  const std::vector<std::uint32_t> varyings{0, 1};
  Draw d;
  d.positions = positions;
  d.attributes = attributes;
  d.attribute_count = 2;
  d.varyings = varyings;
  d.shader = make_shader(Recorder{&seen}, 2);
  const Draw draws[] = {d};
  render(draws, w, h, 1, false, Isa::kReference, 1);
  ASSERT_GT(seen.size(), 500u);
  // Screen positions of the corners (for affine interpolation), and the same snapped to 1/256 px
  // as the renderer snaps them.
  std::array<glm::dvec2, 3> screen, snapped;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 hw = test::window_homogeneous(clip[i], w, h);
    screen[i] = {hw.x / hw.z, hw.y / hw.z};
    snapped[i] = test::fx_to_px(test::snap_fx(screen[i]));
  }
  double worst_snapped = 0, worst = 0, worst_affine = 0;
  for (const auto& s : seen) {
    const glm::dvec2 p(s[0], s[1]);
    const auto b = test::homogeneous_barycentrics(clip, w, h, p);
    // Perspective-correct over the snapped triangle: screen barycentrics weighted by 1/w.
    std::array<double, 3> lq;
    double sum = 0;
    for (int i = 0; i < 3; ++i) {
      std::array<double, 3> unit{};
      unit[i] = 1;
      lq[i] = test::plane_at(snapped, unit, p) / clip[i].w;
      sum += lq[i];
    }
    for (int k = 0; k < 2; ++k) {
      const double exact = b[0] * attr[0][k] + b[1] * attr[1][k] + b[2] * attr[2][k];
      const double on_snapped =
          (lq[0] * attr[0][k] + lq[1] * attr[1][k] + lq[2] * attr[2][k]) / sum;
      const double affine = test::plane_at(screen, {attr[0][k], attr[1][k], attr[2][k]}, p);
      worst_snapped = std::max(worst_snapped, std::abs(s[2 + k] - on_snapped));
      worst = std::max(worst, std::abs(s[2 + k] - exact));
      worst_affine = std::max(worst_affine, std::abs(affine - exact));
    }
  }
  // Against the snapped triangle: float planes over values up to 50, errors of a few 1e-5.
  // Against the unsnapped one, snapping (vertices move by up to 1/512 px) adds the steepest
  // gradient (about 10 units per pixel near the far corner) times 1/512 px. Affine
  // interpolation is off by whole units where the triangle recedes.
  EXPECT_LT(worst_snapped, 1e-3);
  EXPECT_LT(worst, 0.05);
  EXPECT_GT(worst_affine, 1.0);
}

// --- Blending ------------------------------------------------------------------------------------

/// Round-to-nearest x / 255, the specification of BlendMode::kSourceOver, written independently.
std::uint8_t div255_spec(std::uint32_t x) {
  return static_cast<std::uint8_t>(std::lround(static_cast<double>(x) / 255.0));
}
Rgba8 over_spec(Rgba8 s, Rgba8 d) {
  const std::uint32_t a = s.a, ia = 255 - a;
  return {div255_spec(s.r * a + d.r * ia), div255_spec(s.g * a + d.g * ia),
          div255_spec(s.b * a + d.b * ia), div255_spec(255 * a + d.a * ia)};
}

TEST(Shaders, Div255IsRoundedDivisionOverItsWholeRange) {
  for (std::uint32_t x = 0; x <= 255u * 255u; ++x) ASSERT_EQ(shade::div255(x), div255_spec(x)) << x;
}

/// A screen-space quad covering [x0, x1) × [y0, y1) at depth z, in a constant colour.
struct Quad {
  std::vector<glm::vec4> p;
  Quad(float x0, float y0, float x1, float y1, float z = 0.5f)
      : p{{x0, y0, z, 1}, {x1, y0, z, 1}, {x1, y1, z, 1},
          {x0, y0, z, 1}, {x1, y1, z, 1}, {x0, y1, z, 1}} {}
  Draw draw(Rgba8 c, BlendMode blend, bool use_shader) const {
    Draw d;
    d.space = Space::kScreen;
    d.positions = p;
    d.color = c;
    d.state.blend = blend;
    d.state.depth_test = DepthTest::kAlways;
    if (use_shader) d.shader = flat_color_shader(to_unit(c));
    return d;
  }
};

TEST(Shaders, SourceOverBlendsInDrawOrderByHand) {
  // Three overlapping translucent quads; the pixel inside all three is the hand-computed
  // source-over of the three in draw order over the clear colour, with or without a shader.
  const Quad a(2, 2, 20, 20), b(6, 6, 24, 24), c(10, 4, 28, 16);
  const Rgba8 ca{200, 100, 50, 128}, cb{20, 240, 90, 77}, cc{255, 255, 0, 200};
  for (bool shader : {false, true}) {
    const Draw draws[] = {a.draw(ca, BlendMode::kSourceOver, shader),
                          b.draw(cb, BlendMode::kSourceOver, shader),
                          c.draw(cc, BlendMode::kSourceOver, shader)};
    const Rgba8 expected = over_spec(cc, over_spec(cb, over_spec(ca, kBackground)));
    const Rgba8 reversed = over_spec(ca, over_spec(cb, over_spec(cc, kBackground)));
    ASSERT_FALSE(expected == reversed) << "the test needs order to matter";
    for (Isa isa : available_isas()) {
      const Image img = render(draws, 32, 32, 1, false, isa);
      EXPECT_EQ(img.color[12 * 32 + 12], expected) << to_string(isa) << " shader " << shader;
      EXPECT_EQ(img.color[3 * 32 + 3], over_spec(ca, kBackground)) << to_string(isa);
    }
  }
}

TEST(Shaders, BlendingMatchesTheReferenceEverywhere) {
  // Random overlapping translucent triangles, half with a shader, some blending and some not,
  // with depth testing: every path, MSAA and SSAA, against the reference.
  const int w = 97, h = 75;
  test::Rng rng(77);
  std::vector<std::vector<glm::vec4>> pos(6);
  std::vector<Draw> draws;
  for (std::size_t i = 0; i < pos.size(); ++i) {
    for (int t = 0; t < 40; ++t) {
      const double cx = rng.uniform(0, w), cy = rng.uniform(0, h), r = rng.uniform(3, 25);
      for (int k = 0; k < 3; ++k)
        pos[i].emplace_back(static_cast<float>(cx + rng.uniform(-r, r)),
                            static_cast<float>(cy + rng.uniform(-r, r)),
                            static_cast<float>(rng.uniform(0, 1)), 1.0f);
    }
  }
  for (std::size_t i = 0; i < pos.size(); ++i) {
    Draw d;
    d.space = Space::kScreen;
    d.positions = pos[i];
    const Rgba8 c{
        static_cast<std::uint8_t>(rng.range(0, 255)), static_cast<std::uint8_t>(rng.range(0, 255)),
        static_cast<std::uint8_t>(rng.range(0, 255)), static_cast<std::uint8_t>(rng.range(0, 255))};
    d.color = c;
    d.state.blend = i % 3 == 2 ? BlendMode::kNone : BlendMode::kSourceOver;
    d.state.depth_test = i % 2 ? DepthTest::kLessEqual : DepthTest::kAlways;
    d.state.depth_write = i != 1;
    if (i % 2) d.shader = flat_color_shader(to_unit(c));
    draws.push_back(d);
  }
  for (int samples : {1, 4, 8}) {
    for (bool ssaa : {false, true}) {
      const Image ref = render(draws, w, h, samples, ssaa, Isa::kReference, 1);
      for (Isa isa : simd_isas())
        expect_same(ref, render(draws, w, h, samples, ssaa, isa),
                    "blend " + std::to_string(samples) + "x ssaa " + std::to_string(ssaa) + " " +
                        to_string(isa));
    }
  }
}

// --- Built-in shaders ----------------------------------------------------------------------------

TEST(Shaders, LambertAgainstHandComputedValues) {
  // A screen-space quad with one constant normal: n = (1, 2, 2) (length 3), light (0, 0, 5).
  // n·l = 2/3: k = 0.1 + 0.9 * 2/3 = 0.7, rgb = albedo * 0.7 = (0.56, 0.28, 0.14) -> 142.8,
  // 71.4, 35.7 -> (143, 71, 36). Facing away (n = (-1, -2, -2)): ambient alone, k = 0.1 ->
  // (20.4, 10.2, 5.1) -> (20, 10, 5); two-sided it is lit as facing.
  const Quad q(0, 0, 16, 16);
  Lambert lp;
  lp.light_dir = {0, 0, 5};
  lp.albedo = {0.8f, 0.4f, 0.2f};
  lp.ambient = 0.1f;
  lp.diffuse = 0.9f;
  struct Case {
    float sign;
    bool two_sided;
    Rgba8 expected;
  };
  for (const Case c : {Case{1, false, {143, 71, 36, 255}}, Case{-1, false, {20, 10, 5, 255}},
                       Case{-1, true, {143, 71, 36, 255}}}) {
    std::vector<float> normals;
    for (int v = 0; v < 6; ++v) normals.insert(normals.end(), {c.sign, 2 * c.sign, 2 * c.sign});
    const std::vector<std::uint32_t> varyings{0, 1, 2};
    lp.two_sided = c.two_sided;
    Draw d = q.draw({}, BlendMode::kNone, false);
    d.attributes = normals;
    d.attribute_count = 3;
    d.varyings = varyings;
    d.shader = lambert_shader(lp);
    const Draw draws[] = {d};
    for (Isa isa : available_isas()) {
      const Image img = render(draws, 16, 16, 4, false, isa);
      for (const Rgba8& p : img.color) ASSERT_EQ(p, c.expected) << to_string(isa);
    }
  }
}

TEST(Shaders, LambertNormalisesTheInterpolatedNormal) {
  // Normals (0, 0, 1) and (0, 0, 9) at the corners of one triangle: interpolated, every pixel's
  // normal points along z at some length, so normalised n·l = 1 everywhere: rgb = albedo.
  std::vector<glm::vec4> p{{0, 0, 0.5f, 1}, {64, 0, 0.5f, 1}, {0, 64, 0.5f, 1}};
  std::vector<float> normals{0, 0, 1, 0, 0, 9, 0, 0, 4};
  const std::vector<std::uint32_t> varyings{0, 1, 2};
  Draw d;
  d.space = Space::kScreen;
  d.positions = p;
  d.attributes = normals;
  d.attribute_count = 3;
  d.varyings = varyings;
  Lambert lp;
  lp.albedo = {100 / 255.0f, 50 / 255.0f, 200 / 255.0f};
  lp.ambient = 0;
  lp.diffuse = 1;
  d.shader = lambert_shader(lp);
  const Draw draws[] = {d};
  const Image img = render(draws, 64, 64, 1, false, Isa::kReference, 1);
  std::size_t lit = 0;
  for (const Rgba8& c : img.color) {
    if (c == kBackground) continue;
    ++lit;
    ASSERT_EQ(c, (Rgba8{100, 50, 200, 255}));
  }
  EXPECT_GT(lit, 1500u);
}

TEST(Shaders, BuiltInColourShadersMatchTheColourSourcesTheyReplace) {
  // flat_color_shader against ColorSource::kConstant: identical. vertex_color_shader (colour
  // attributes in 0..1) against ColorSource::kPerVertex (0..255 planes): both perspective-correct,
  // within one step of 8 bits (the planes round differently).
  const int w = 160, h = 120;
  const GroundPlane plane(w, h);
  std::vector<Rgba8> colors{
      {255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {250, 250, 0, 255}};
  std::vector<float> attributes;
  for (const Rgba8& c : colors) {
    const glm::vec4 u = to_unit(c);
    attributes.insert(attributes.end(), {u.r, u.g, u.b, u.a});
  }
  const std::vector<std::uint32_t> varyings{0, 1, 2, 3};
  Draw source = plane.draw();
  source.shader = {};
  source.varyings = {};
  source.attributes = {};
  source.attribute_count = 0;
  Draw shaded = source;
  source.color_source = ColorSource::kConstant;
  source.color = {12, 34, 56, 255};
  shaded.shader = flat_color_shader(to_unit(source.color));
  for (Isa isa : available_isas()) {
    const Draw a[] = {source}, b[] = {shaded};
    EXPECT_EQ(render(a, w, h, 4, false, isa).color, render(b, w, h, 4, false, isa).color)
        << to_string(isa);
  }
  source.color_source = ColorSource::kPerVertex;
  source.colors = colors;
  shaded.attributes = attributes;
  shaded.attribute_count = 4;
  shaded.varyings = varyings;
  shaded.shader = vertex_color_shader();
  const Draw a[] = {source}, b[] = {shaded};
  const Image ia = render(a, w, h, 1, false, Isa::kReference, 1);
  const Image ib = render(b, w, h, 1, false, Isa::kReference, 1);
  int worst = 0;
  std::size_t covered = 0;
  for (std::size_t i = 0; i < ia.color.size(); ++i) {
    covered += !(ia.color[i] == kBackground);
    worst = std::max({worst, std::abs(ia.color[i].r - ib.color[i].r),
                      std::abs(ia.color[i].g - ib.color[i].g),
                      std::abs(ia.color[i].b - ib.color[i].b)});
  }
  EXPECT_LE(worst, 1);
  EXPECT_GT(covered, ia.color.size() / 3);
}

// --- Random clip-space scenes with many varyings
// ---------------------------------------------------

/// A shader mixing five varyings nonlinearly (a product, a sine, a square root), with an alpha
/// that varies, so that any lane-order or interpolation difference shows.
Shader mixing_shader() {
  return make_shader(
      [](const Fragment& f) {
        const float a = f.varying(0), b = f.varying(1), c = f.varying(2), d = f.varying(3),
                    e = f.varying(4);
        return glm::vec4(a * b, 0.5f + 0.5f * std::sin(3.0f * c), std::sqrt(std::abs(d)),
                         0.25f + 0.5f * std::abs(e));
      },
      5);
}

TEST(Shaders, RandomClipSpaceScenesMatchTheReferenceOnEveryPath) {
  // Triangles in front of and behind the camera (clipped), 7 attributes per vertex of which 5
  // are read in a shuffled order, every sample count, MSAA and SSAA, with and without blending.
  const int w = 157, h = 131;
  test::Rng rng(2024);
  std::vector<glm::vec4> positions;
  std::vector<float> attributes;
  constexpr std::uint32_t kAttrs = 7;
  for (int i = 0; i < 150 * 3; ++i) {
    const double wv = rng.uniform(-0.5, 3.0);
    positions.emplace_back(static_cast<float>(rng.uniform(-1.5, 1.5) * std::abs(wv)),
                           static_cast<float>(rng.uniform(-1.5, 1.5) * std::abs(wv)),
                           static_cast<float>(rng.uniform(-0.2, 1.2) * wv), static_cast<float>(wv));
    for (std::uint32_t a = 0; a < kAttrs; ++a)
      attributes.push_back(static_cast<float>(rng.uniform(-2, 2)));
  }
  const std::vector<std::uint32_t> varyings{6, 0, 3, 1, 5};
  for (BlendMode blend : {BlendMode::kNone, BlendMode::kSourceOver}) {
    Draw d;
    d.positions = positions;
    d.attributes = attributes;
    d.attribute_count = kAttrs;
    d.varyings = varyings;
    d.shader = mixing_shader();
    d.state.blend = blend;
    const Draw draws[] = {d};
    for (int samples : {1, 4, 16}) {
      for (bool ssaa : {false, true}) {
        const Image ref = render(draws, w, h, samples, ssaa, Isa::kReference, 1);
        EXPECT_GT(ref.stats.triangles_clipped, 0u);
        for (Isa isa : simd_isas())
          expect_same(ref, render(draws, w, h, samples, ssaa, isa),
                      "random " + std::to_string(samples) + "x ssaa " + std::to_string(ssaa) +
                          " blend " + std::to_string(int(blend)) + " " + to_string(isa));
      }
    }
  }
}

TEST(Shaders, PainterSortedTranslucentShadedDrawsMatchTheReference) {
  // The classic use of blending: translucent triangles sorted back to front (Frame::painter),
  // shaded with varyings, in two draws whose triangles the sort interleaves.
  const int w = 120, h = 90;
  test::Rng rng(31);
  std::vector<glm::vec4> positions[2];
  std::vector<float> attributes[2];
  for (int d = 0; d < 2; ++d)
    for (int i = 0; i < 200 * 3; ++i) {
      const double wv = rng.uniform(0.5, 3.0);
      positions[d].emplace_back(static_cast<float>(rng.uniform(-1, 1) * wv),
                                static_cast<float>(rng.uniform(-1, 1) * wv),
                                static_cast<float>(rng.uniform(0, 1) * wv), static_cast<float>(wv));
      for (int a = 0; a < 5; ++a) attributes[d].push_back(static_cast<float>(rng.uniform(-1, 1)));
    }
  const std::vector<std::uint32_t> varyings{4, 3, 2, 1, 0};
  std::vector<Draw> draws(2);
  for (int d = 0; d < 2; ++d) {
    draws[d].positions = positions[d];
    draws[d].attributes = attributes[d];
    draws[d].attribute_count = 5;
    draws[d].varyings = varyings;
    draws[d].shader = mixing_shader();
    draws[d].state.blend = BlendMode::kSourceOver;
  }
  for (int samples : {1, 4}) {
    const Image ref = render(draws, w, h, samples, false, Isa::kReference, 1, true);
    for (Isa isa : simd_isas())
      expect_same(ref, render(draws, w, h, samples, false, isa, 2, true),
                  "painter " + std::to_string(samples) + "x " + to_string(isa));
  }
}

// The kernels pack a shader's partly covered batches (16 pixels of a block: two of its rows)
// from many triangles into one call, and shade a whole batch at once after writing what was
// packed before. In screen space, per 8×8 block:
//  - a rectangle exactly over rows 0-1 (a whole batch), and one a pixel short (15 pixels);
//  - 40 tiny triangles stacked on the same few pixels (the queue holds one pixel many times,
//    fills past 16 entries, and must blend, or overwrite when the draws do not blend, in order);
//  - a flat-colour draw between two shaded ones (the queue is written before the next draw);
//  - a triangle over a whole block and queued pixels, in the same draw (whole batches after
//    partial ones);
//  - a sliver across a dozen blocks: one triangle's queued pixels fill several calls, and its
//    varyings are made for its pixels of many blocks at once.
// Colour is a non-linear function of the varyings and of the facing (the stacked triangles
// face either way), so a pixel given another's lane shows. Every ISA, sample count, SSAA, the
// painter's order, 1 and 2 threads and two tile sizes, against the reference.
TEST(Shaders, PackedBatchesMatchTheReferenceAtTheirThresholds) {
  constexpr int kW = 48, kH = 40;
  std::vector<glm::vec4> pos;
  std::vector<float> attr;
  const auto vertex = [&](float x, float y, float z, float a, float b) {
    pos.emplace_back(x, y, z, 1.0f);
    attr.insert(attr.end(), {a, b, 0.6f});
  };
  const auto rect = [&](float x0, float y0, float x1, float y1, float z) {
    vertex(x0, y0, z, x0 * 0.37f, y0 * 0.11f);
    vertex(x1, y0, z, x1 * 0.37f, y0 * 0.11f);
    vertex(x1, y1, z, x1 * 0.37f, y1 * 0.11f);
    vertex(x0, y0, z, x0 * 0.37f, y0 * 0.11f);
    vertex(x1, y1, z, x1 * 0.37f, y1 * 0.11f);
    vertex(x0, y1, z, x0 * 0.37f, y1 * 0.11f);
  };
  rect(8, 8, 16, 10, 0.5f);  // rows 0-1 of block (1, 1): a whole batch
  rect(24, 8, 32, 9, 0.5f);  // 8 + 7 pixels of block (3, 1)'s first batch
  rect(24, 9, 31, 10, 0.5f);
  vertex(1.3f, 33.6f, 0.4f, 0.2f, 0.9f);  // the sliver, about 1.5 px wide
  vertex(46.2f, 2.7f, 0.4f, 3.1f, 0.1f);
  vertex(46.9f, 4.4f, 0.4f, 2.7f, 2.3f);
  const auto first_draw = static_cast<std::uint32_t>(pos.size());
  std::uint32_t seed = 7;
  const auto next = [&] {
    seed = seed * 1664525u + 1013904223u;
    return static_cast<float>(seed >> 8) / static_cast<float>(1u << 24);
  };
  for (int i = 0; i < 40; ++i) {  // stacked tiny triangles around (13, 21) and (35, 30)
    const float cx = i % 2 ? 13.0f : 35.0f, cy = i % 2 ? 21.0f : 30.0f;
    for (int k = 0; k < 3; ++k)
      vertex(cx + 3.0f * next() - 1.5f, cy + 3.0f * next() - 1.5f,
             0.9f - 0.01f * static_cast<float>(i), next() * 5, next() * 3);
  }
  const auto stack = static_cast<std::uint32_t>(pos.size()) - first_draw;
  // One triangle over all of block (4, 3), in front of the queued pixels at (35, 30).
  vertex(32, 24, 0.2f, 1.0f, 2.0f);
  vertex(56, 24, 0.2f, 4.0f, 2.5f);
  vertex(32, 48, 0.2f, 1.5f, 7.0f);
  const std::uint32_t last = 3;
  const std::span<const glm::vec4> all(pos);
  const std::span<const float> all_attr(attr);

  const std::vector<std::uint32_t> varyings{0, 1, 2};
  const Shader wavy = make_shader(
      [](const Fragment& f) {
        const float a = f.varying(0), b = f.varying(1);
        return glm::vec4(a * a - std::floor(a * a), b - std::floor(b),
                         f.front_facing() ? f.varying(2) : 1.0f - f.varying(2), 0.3f + 0.1f * a);
      },
      3);
  const auto shaded = [&](std::size_t first, std::size_t count, bool blend) {
    Draw d;
    d.space = Space::kScreen;
    d.positions = all.subspan(first, count);
    d.attributes = all_attr.subspan(3 * first, 3 * count);
    d.attribute_count = 3;
    d.varyings = varyings;
    d.shader = wavy;
    d.state.blend = blend ? BlendMode::kSourceOver : BlendMode::kNone;
    d.state.depth_test = DepthTest::kLessEqual;
    return d;
  };
  Draw flat;
  flat.space = Space::kScreen;
  flat.positions = all.subspan(first_draw, 6);  // the stack's first two triangles again, flat
  flat.color = {200, 10, 10, 255};
  flat.state.depth_test = DepthTest::kAlways;
  flat.state.depth_write = false;
  // The stack and the block over it are one draw: the block's whole batches come after the
  // stack's queued pixels.
  // Without blending, a later entry of a sample overwrites an earlier one in the same batch; the
  // stack is then drawn once, so that no redraw hides the order its first drawing wrote in.
  const auto scene = [&](bool blend) {
    std::vector<Draw> d{shaded(0, first_draw, blend), shaded(first_draw, stack + last, blend),
                        flat};
    if (blend) d.push_back(shaded(first_draw, stack, blend));
    return d;
  };
  const std::vector<Draw> draws = scene(true);
  struct Mode {
    int samples;
    bool ssaa;
  };
  for (const bool blend : {true, false}) {
    const std::vector<Draw> these = scene(blend);
    for (const bool painter : {false, true}) {
      for (const Mode m :
           {Mode{1, false}, Mode{4, false}, Mode{4, true}, Mode{8, false}, Mode{16, false}}) {
        const Image ref = render(these, kW, kH, m.samples, m.ssaa, Isa::kReference, 1, painter);
        for (const Isa isa : simd_isas())
          for (const int threads : {1, 2})
            expect_same(ref, render(these, kW, kH, m.samples, m.ssaa, isa, threads, painter),
                        std::to_string(m.samples) + "x ssaa " + std::to_string(m.ssaa) + " " +
                            to_string(isa) + " threads " + std::to_string(threads) + " painter " +
                            std::to_string(painter) + " blend " + std::to_string(blend));
      }
    }
  }
  // 8 px tiles: the stacks straddle tiles, and a tile's queue holds fewer triangles.
  RenderTarget small(kW, kH, 4, TargetOptions{true, true});
  const Image ref = render(draws, kW, kH, 4, false, Isa::kReference, 1);
  RendererOptions options;
  options.threads = 2;
  options.tile_size = 8;
  Renderer r(options);
  Frame frame;
  frame.draws = draws;
  small.set_clear(kBackground);
  expect_same(ref, test::capture(r, frame, small), "8 px tiles");
}

TEST(Shaders, DeterministicAcrossThreadCounts) {
  const int w = 300, h = 200;
  const GroundPlane plane(w, h);
  // The plane under many small translucent shaded triangles.
  test::Rng rng(5);
  std::vector<glm::vec4> tris;
  std::vector<float> attributes;
  for (int i = 0; i < 3000 * 3; ++i) {
    tris.emplace_back(static_cast<float>(rng.uniform(-1, 1)),
                      static_cast<float>(rng.uniform(-1, 1)), static_cast<float>(rng.uniform(0, 1)),
                      1.0f);
    for (int a = 0; a < 5; ++a) attributes.push_back(static_cast<float>(rng.uniform(-1, 1)));
  }
  const std::vector<std::uint32_t> varyings{0, 1, 2, 3, 4};
  Draw small;
  small.positions = tris;
  small.attributes = attributes;
  small.attribute_count = 5;
  small.varyings = varyings;
  small.shader = mixing_shader();
  small.state.blend = BlendMode::kSourceOver;
  const Draw draws[] = {plane.draw(), small};
  for (Isa isa : simd_isas()) {
    const Image one = render(draws, w, h, 4, false, isa, 1);
    for (int threads : {2, 7})
      expect_same(one, render(draws, w, h, 4, false, isa, threads),
                  std::to_string(threads) + " threads " + to_string(isa));
  }
}

// Varyings to the last bit: a shader that shows the low byte of each varying's float bits, so
// that a one-ulp difference from the reference's interpolation changes a channel. Perspective
// triangles (each corner its own w, so q varies) with boxes of one to a few pixels, which the
// kernels queue one pixel at a time (the few-pixel path, varyings made in scalar), among larger
// ones whose pixels share vectors; every ISA, 1x and 4x, 1 and 2 threads, against the reference.
TEST(Shaders, VaryingsOfTinyAndLargerTrianglesMatchTheReferenceBitForBit) {
  const int w = 96, h = 80;
  test::Rng rng(31);
  std::vector<glm::vec4> positions;
  std::vector<float> attributes;
  for (int i = 0; i < 1200; ++i) {
    // Boxes of about a pixel for most, up to 12 px for one in eight.
    const double r = i % 8 == 0 ? rng.uniform(3, 12) : rng.uniform(0.3, 1.6);
    const double cx = rng.uniform(0, w), cy = rng.uniform(0, h), z = rng.uniform(0.05, 0.95);
    for (int k = 0; k < 3; ++k) {
      const double px = cx + rng.uniform(-r, r), py = cy + rng.uniform(-r, r);
      const double wv = rng.uniform(0.5, 3.0);
      positions.emplace_back(static_cast<float>((2 * px / w - 1) * wv),
                             static_cast<float>((2 * py / h - 1) * wv), static_cast<float>(z * wv),
                             static_cast<float>(wv));
      for (int a = 0; a < 3; ++a) attributes.push_back(static_cast<float>(rng.uniform(-3, 3)));
    }
  }
  const std::vector<std::uint32_t> varyings{0, 1, 2};
  const auto low_byte = [](float v) {
    return static_cast<float>(std::bit_cast<std::uint32_t>(v) & 0xffu) / 255.0f;
  };
  Draw d;
  d.positions = positions;
  d.attributes = attributes;
  d.attribute_count = 3;
  d.varyings = varyings;
  d.state.cull = CullMode::kNone;
  d.shader = make_shader(
      [=](const Fragment& f) {
        return glm::vec4(low_byte(f.varying(0)), low_byte(f.varying(1)), low_byte(f.varying(2)),
                         1.0f);
      },
      3);
  const Draw draws[] = {d};
  for (int samples : {1, 4}) {
    const Image ref = render(draws, w, h, samples, false, Isa::kReference, 1);
    EXPECT_GT(ref.stats.samples_written, 0u);
    for (Isa isa : simd_isas())
      for (int threads : {1, 2})
        expect_same(ref, render(draws, w, h, samples, false, isa, threads),
                    std::to_string(samples) + "x " + to_string(isa) + " threads " +
                        std::to_string(threads));
  }
}

// --- Bad input
// -------------------------------------------------------------------------------------

TEST(Shaders, BadShaderInputIsRejectedAndLeavesTheTargetAlone) {
  const Quad q(0, 0, 8, 8);
  const std::vector<float> attrs(6 * 3, 0.5f);
  const std::vector<std::uint32_t> three{0, 1, 2}, two{0, 1}, past{0, 3, 1};
  const std::vector<std::uint32_t> many(kMaxVaryings + 1, 0);
  const std::vector<float> attrs1(6, 0.5f);
  const Shader lambert = lambert_shader({});
  struct Bad {
    const char* what;
    std::span<const float> attributes;
    std::uint32_t count;
    std::span<const std::uint32_t> varyings;
    Shader shader;
  };
  const Bad bad[] = {
      {"attribute buffer too short", std::span<const float>(attrs).first(17), 3, three, lambert},
      {"varying past the attributes", attrs, 3, past, lambert},
      {"more than kMaxVaryings", attrs1, 1, many, lambert},
      {"fewer varyings than the shader reads", attrs, 3, two, lambert},
      {"no varyings for a shader that reads some", attrs, 3, {}, lambert},
      {"varyings without a shader", attrs, 3, three, Shader{}},
  };
  for (Isa isa : available_isas()) {
    RenderTarget target(8, 8, 4);
    target.set_clear({1, 2, 3, 4});
    Renderer r({1, isa});
    const Draw good = q.draw({9, 9, 9, 255}, BlendMode::kNone, false);
    r.render(Frame{std::span<const Draw>(&good, 1)}, target);
    const std::vector<Rgba8> before(target.color().begin(), target.color().end());
    for (const Bad& b : bad) {
      Draw d = q.draw({200, 0, 0, 255}, BlendMode::kSourceOver, false);
      d.attributes = b.attributes;
      d.attribute_count = b.count;
      d.varyings = b.varyings;
      d.shader = b.shader;
      const Draw draws[] = {good, d};
      try {
        r.render(Frame{draws}, target);
        ADD_FAILURE() << b.what << ": not rejected";
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), Errc::kInvalidDraw) << b.what << ": " << e.what();
        EXPECT_NE(std::string(e.what()).find("draw 1"), std::string::npos) << e.what();
      }
      EXPECT_EQ(std::vector<Rgba8>(target.color().begin(), target.color().end()), before) << b.what;
    }
  }
}

TEST(Shaders, NonFiniteAttributesDoNotCrashAndMatchTheReference) {
  const Quad q(0, 0, 40, 24);
  const float inf = std::numeric_limits<float>::infinity(),
              nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> attrs;
  for (int v = 0; v < 6; ++v)
    attrs.insert(attrs.end(),
                 {v == 1 ? nan : 0.5f, v == 2 ? inf : 0.25f, v == 4 ? -inf : 1e38f, 1.0f, 0.5f});
  const std::vector<std::uint32_t> varyings{0, 1, 2, 3, 4};
  Draw d = q.draw({}, BlendMode::kSourceOver, false);
  d.attributes = attrs;
  d.attribute_count = 5;
  d.varyings = varyings;
  d.shader = mixing_shader();
  const Draw draws[] = {d};
  const Image ref = render(draws, 40, 24, 4, false, Isa::kReference, 1);
  for (Isa isa : simd_isas())
    expect_same(ref, render(draws, 40, 24, 4, false, isa), to_string(isa));
}

}  // namespace
}  // namespace mosaic
