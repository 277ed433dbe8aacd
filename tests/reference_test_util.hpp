// tests/reference_test_util.hpp — helpers shared by the stage tests and the fast-path comparisons.
//
// Takes: hand-made triangles. Gives: owned meshes, frames rendered by the exact reference through
// the public API, per-sample coverage read back from the target, captures of a frame and their
// bit-for-bit comparison (fast path against reference), and an independent coverage oracle. The
// oracle and the sample tables are written here again from the specification (the D3D / Vulkan
// rules and DESIGN.md), not taken from the engine, so that a wrong engine table or a wrong
// fill-rule bias makes the tests fail instead of agreeing with itself.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"

namespace mosaic::test {

/// Subpixel steps per pixel of the 16.8 vertex format (the specification's value).
inline constexpr int kUnits = 256;
/// Subpixel steps per 1/16 px sample-offset step (256 / 16).
inline constexpr int kOffsetUnits = 16;

/// A point in 1/256 px, y down.
struct Fx {
  std::int64_t x = 0, y = 0;
};

/// A standard sample offset in 1/16 px from the pixel centre, y down.
struct Offset16 {
  int dx = 0, dy = 0;
};

/// The standard sample positions (DESIGN.md "Facts to build on"; Vulkan standard locations).
inline std::span<const Offset16> standard_pattern(int samples) {
  // clang-format off
  static const std::array<Offset16, 1> k1{{{0, 0}}};
  static const std::array<Offset16, 4> k4{{{-2, -6}, {6, -2}, {-6, 2}, {2, 6}}};
  static const std::array<Offset16, 8> k8{
      {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}}};
  static const std::array<Offset16, 16> k16{
      {{1, 1}, {-1, -3}, {-3, 2}, {4, -1}, {-5, -2}, {2, 5}, {5, 3}, {3, -5}, {-2, 6}, {0, -7},
       {-4, -6}, {-6, 4}, {-8, 0}, {7, -4}, {6, 7}, {-7, -8}}};
  // clang-format on
  switch (samples) {
    case 1:
      return k1;
    case 4:
      return k4;
    case 8:
      return k8;
    default:
      return k16;
  }
}

/// Sample `s` of pixel (px, py) in 1/256 px.
inline Fx sample_fx(int px, int py, int s, int samples) {
  const Offset16 o = standard_pattern(samples)[static_cast<std::size_t>(s)];
  return {std::int64_t{px} * kUnits + kUnits / 2 + o.dx * kOffsetUnits,
          std::int64_t{py} * kUnits + kUnits / 2 + o.dy * kOffsetUnits};
}

/// The same sample in pixels.
inline glm::dvec2 sample_px(int px, int py, int s, int samples) {
  const Fx f = sample_fx(px, py, s, samples);
  return {static_cast<double>(f.x) / kUnits, static_cast<double>(f.y) / kUnits};
}

/// Round to the nearest 1/256 px, a tie to the even step (IEEE's default rounding): the
/// specification of snapping, written without the engine's formula.
inline std::int64_t snap_units(double px) {
  return static_cast<std::int64_t>(std::nearbyint(px * kUnits));
}
inline Fx snap_fx(glm::dvec2 p) { return {snap_units(p.x), snap_units(p.y)}; }
inline glm::dvec2 fx_to_px(Fx p) {
  return {static_cast<double>(p.x) / kUnits, static_cast<double>(p.y) / kUnits};
}

/// The coverage oracle for a convex polygon of either winding, in exact integers.
///
/// A sample on an edge is decided as if it were nudged by an infinitesimal: D3D's top-left rule is
/// the nudge (+ε, +ε²) (right, then down, y down), OpenGL's bottom-left rule the nudge (+ε, -ε²).
/// This is an independent statement of the rule: it also decides vertices (both edges must accept
/// the nudge), and it makes any triangulation of a polygon cover the same samples.
/// Coordinates must stay below 2^30 units so that the products fit in int64.
inline bool oracle_covers(std::span<const Fx> poly, Fx p, FillRule rule) {
  const std::size_t n = poly.size();
  std::int64_t area2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Fx a = poly[i], b = poly[(i + 1) % n];
    area2 += a.x * b.y - b.x * a.y;
  }
  if (area2 == 0) return false;
  const std::int64_t orient = area2 > 0 ? 1 : -1;
  const std::int64_t vertical_nudge = rule == FillRule::kD3D ? 1 : -1;
  for (std::size_t i = 0; i < n; ++i) {
    const Fx a = poly[i], b = poly[(i + 1) % n];
    const std::int64_t e = orient * ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x));
    if (e > 0) continue;
    if (e < 0) return false;
    const std::int64_t de_dx = -orient * (b.y - a.y);
    const std::int64_t de_dy = orient * (b.x - a.x);
    if (de_dx > 0) continue;
    if (de_dx == 0 && vertical_nudge * de_dy > 0) continue;
    return false;
  }
  return true;
}

inline bool oracle_covers_tri(Fx a, Fx b, Fx c, Fx p, FillRule rule) {
  const std::array<Fx, 3> t{a, b, c};
  return oracle_covers(t, p, rule);
}

/// Value at q of the plane through (p[k], f[k]), in double (barycentric form).
inline double plane_at(const std::array<glm::dvec2, 3>& p, const std::array<double, 3>& f,
                       glm::dvec2 q) {
  const double d = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
  const double l1 = ((q.x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (q.y - p[0].y)) / d;
  const double l2 = ((p[1].x - p[0].x) * (q.y - p[0].y) - (q.x - p[0].x) * (p[1].y - p[0].y)) / d;
  return f[0] + l1 * (f[1] - f[0]) + l2 * (f[2] - f[0]);
}

/// How far a float32 evaluation of that plane may stray from the double value at q: the plane
/// is f0 + gx (x - x0) + gy (y - y0) with float coefficients, so a few roundings (2^-24 each) of
/// each term's magnitude. Any real mistake (unsnapped vertices, a swapped slope) is far larger.
inline double depth_tolerance(const std::array<glm::dvec2, 3>& p, const std::array<double, 3>& f,
                              glm::dvec2 q) {
  constexpr double kFloatEpsilon = 0x1p-24;  // half an ulp of 1.0f
  constexpr double kRoundings = 4;           // slope, product, sum, sum
  const double f0 = plane_at(p, f, p[0]);
  const double gx = plane_at(p, f, p[0] + glm::dvec2(1, 0)) - f0;
  const double gy = plane_at(p, f, p[0] + glm::dvec2(0, 1)) - f0;
  const double magnitude =
      std::abs(f0) + std::abs(gx * (q.x - p[0].x)) + std::abs(gy * (q.y - p[0].y)) + 1.0;
  return kRoundings * kFloatEpsilon * magnitude;
}

/// Window-homogeneous coordinates (X, Y, W) of a clip-space point for a width × height target:
/// the pixel it shows is (X / W, Y / W), y down.
inline glm::dvec3 window_homogeneous(glm::dvec4 clip, int width, int height) {
  return {(clip.x + clip.w) * width / 2.0, (clip.w - clip.y) * height / 2.0, clip.w};
}

/// Barycentric weights (summing to 1) of the point of a clip-space triangle that pixel position p
/// shows, found without clipping or dividing: sum b_i (X_i - p.x W_i) = 0,
/// sum b_i (Y_i - p.y W_i) = 0, sum b_i = 1, solved by Cramer's rule. Valid for vertices behind
/// the eye too; a perspective-correct attribute at p is sum b_i a_i.
inline std::array<double, 3> homogeneous_barycentrics(const std::array<glm::dvec4, 3>& clip,
                                                      int width, int height, glm::dvec2 p) {
  std::array<double, 3> u, v;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 h = window_homogeneous(clip[static_cast<std::size_t>(i)], width, height);
    u[static_cast<std::size_t>(i)] = h.x - p.x * h.z;
    v[static_cast<std::size_t>(i)] = h.y - p.y * h.z;
  }
  // Rows (u), (v), (1 1 1); right-hand side (0, 0, 1): b_i is the cofactor along the last row.
  const double c0 = u[1] * v[2] - u[2] * v[1];
  const double c1 = u[2] * v[0] - u[0] * v[2];
  const double c2 = u[0] * v[1] - u[1] * v[0];
  const double det = c0 + c1 + c2;
  return {c0 / det, c1 / det, c2 / det};
}

/// A screen-space mesh of flat-coloured triangles, drawn with `state`.
inline Mesh screen_mesh(DrawState state = {}) {
  Mesh m;
  m.space = Space::kScreen;
  m.color_source = ColorSource::kPerTriangle;
  m.state = state;
  return m;
}

/// Appends a screen-space triangle (pixels, y down) with one colour and one depth.
inline void add_tri(Mesh& m, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, Rgba8 color,
                    float z = 0.5f) {
  for (const glm::dvec2& p : {a, b, c})
    m.positions.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y), z, 1.0f);
  m.colors.push_back(color);
}
inline void add_tri_fx(Mesh& m, Fx a, Fx b, Fx c, Rgba8 color, float z = 0.5f) {
  add_tri(m, fx_to_px(a), fx_to_px(b), fx_to_px(c), color, z);
}

/// Frame-level switches of a test render.
struct FrameOptions {
  bool painter = false;
  bool ssaa = false;
};

/// Renders `meshes` as one frame with the exact reference, through the public API.
/// Draws viewing each of `meshes`, in order (valid while the meshes live).
inline std::vector<Draw> draws_of(const std::vector<Mesh>& meshes) {
  std::vector<Draw> draws;
  draws.reserve(meshes.size());
  for (const Mesh& m : meshes) draws.push_back(m.draw());
  return draws;
}

inline FrameStats render_reference(const std::vector<Mesh>& meshes, RenderTarget& target,
                                   FrameOptions options = {}) {
  const std::vector<Draw> draws = draws_of(meshes);
  Frame frame;
  frame.draws = draws;
  frame.painter = options.painter;
  frame.ssaa = options.ssaa;
  RendererOptions ro;
  ro.threads = 1;
  ro.isa = Isa::kReference;
  Renderer renderer(ro);
  return renderer.render(frame, target);
}
inline FrameStats render_reference(const Mesh& mesh, RenderTarget& target,
                                   FrameOptions options = {}) {
  return render_reference(std::vector<Mesh>{mesh}, target, options);
}

/// A clear colour that no test triangle uses (its alpha is never 255).
inline constexpr Rgba8 kClear{1, 2, 3, 4};

/// A target that keeps per-sample colour and depth, cleared to kClear.
inline RenderTarget sample_target(int width, int height, int samples) {
  RenderTarget t(width, height, samples, TargetOptions{true, true});
  t.set_clear(kClear);
  return t;
}

/// Colour number `i` (up to 2^16 of them), never equal to kClear.
inline Rgba8 distinct_color(std::uint32_t i) {
  return {static_cast<std::uint8_t>(i & 0xff), static_cast<std::uint8_t>((i >> 8) & 0xff), 200,
          255};
}

/// Index of sample s of pixel (x, y) in the per-sample buffers.
inline std::size_t sample_index(const RenderTarget& t, int x, int y, int s) {
  return (static_cast<std::size_t>(y) * static_cast<std::size_t>(t.width()) +
          static_cast<std::size_t>(x)) *
             static_cast<std::size_t>(t.samples()) +
         static_cast<std::size_t>(s);
}

/// Per-sample coverage of the last frame: samples whose colour is not kClear.
inline std::vector<bool> covered_samples(const RenderTarget& t) {
  std::vector<bool> out(t.sample_color().size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = !(t.sample_color()[i] == kClear);
  return out;
}
inline std::size_t count_covered(const RenderTarget& t) {
  std::size_t n = 0;
  for (const Rgba8& c : t.sample_color()) n += c == kClear ? 0 : 1;
  return n;
}

/// A small deterministic random source (raw mt19937_64 bits, so results do not depend on the
/// standard library's distributions).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : gen_(seed) {}
  /// Uniform integer in [lo, hi].
  std::int64_t range(std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(gen_() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  /// Uniform double in [0, 1).
  double unit() { return static_cast<double>(gen_() >> 11) * 0x1p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  bool coin() { return (gen_() >> 63) != 0; }

 private:
  std::mt19937_64 gen_;
};

/// Everything a frame left in a target that keeps its samples, and its stats: what the fast
/// path must reproduce bit for bit.
struct Captured {
  std::vector<Rgba8> color, sample_color;
  std::vector<float> sample_depth;
  FrameStats stats;
};

/// Renders `frame` with `renderer` into `target` (made with TargetOptions{true, true}) and copies
/// out what it holds.
inline Captured capture(Renderer& renderer, const Frame& frame, RenderTarget& target) {
  Captured out;
  out.stats = renderer.render(frame, target);
  out.color.assign(target.color().begin(), target.color().end());
  out.sample_color.assign(target.sample_color().begin(), target.sample_color().end());
  out.sample_depth.assign(target.sample_depth().begin(), target.sample_depth().end());
  return out;
}

/// Every SIMD path this CPU and build can run: available_isas() without the reference.
inline std::vector<Isa> simd_isas() {
  std::vector<Isa> v;
  for (Isa i : available_isas())
    if (i != Isa::kReference) v.push_back(i);
  return v;
}

/// How render_draws() renders.
struct RenderSetup {
  int samples = 1;
  bool ssaa = false;
  Isa isa = Isa::kReference;
  int threads = 1;
  bool painter = false;
};

/// `draws` rendered into a new width × height target that keeps sample colour and depth, cleared
/// to `clear`, by a new Renderer: a capture for expect_same().
inline Captured render_draws(std::span<const Draw> draws, int width, int height,
                             const RenderSetup& how, Rgba8 clear) {
  RenderTarget target(width, height, how.samples, TargetOptions{true, true});
  target.set_clear(clear);
  Frame frame;
  frame.draws = draws;
  frame.ssaa = how.ssaa;
  frame.painter = how.painter;
  Renderer r({how.threads, how.isa});
  return capture(r, frame, target);
}

/// Bit equality of the buffers of two captures of the same frame (depth compared as bits, so -0
/// and NaN payloads count), whatever their counters; `what` names the case in failures.
inline void expect_same_buffers(const Captured& ref, const Captured& fast,
                                const std::string& what) {
  ASSERT_EQ(ref.sample_depth.size(), fast.sample_depth.size()) << what;
  ASSERT_EQ(ref.sample_color.size(), fast.sample_color.size()) << what;
  ASSERT_EQ(ref.color.size(), fast.color.size()) << what;
  std::size_t bad_depth = 0, bad_color = 0, bad_pixel = 0;
  for (std::size_t i = 0; i < ref.sample_depth.size(); ++i)
    if (std::memcmp(&ref.sample_depth[i], &fast.sample_depth[i], sizeof(float)) != 0) ++bad_depth;
  for (std::size_t i = 0; i < ref.sample_color.size(); ++i)
    if (!(ref.sample_color[i] == fast.sample_color[i])) ++bad_color;
  for (std::size_t i = 0; i < ref.color.size(); ++i)
    if (!(ref.color[i] == fast.color[i])) ++bad_pixel;
  EXPECT_EQ(bad_depth, 0u) << what;
  EXPECT_EQ(bad_color, 0u) << what;
  EXPECT_EQ(bad_pixel, 0u) << what;
}

/// expect_same_buffers, with the counters every path shares.
inline void expect_same(const Captured& ref, const Captured& fast, const std::string& what) {
  ASSERT_EQ(ref.stats.samples_written, fast.stats.samples_written) << what;
  ASSERT_EQ(ref.stats.triangles_drawn, fast.stats.triangles_drawn) << what;
  expect_same_buffers(ref, fast, what);
}

/// The indices of a grid of cells × cells quads over (cells + 1)² row-major vertices, two
/// triangles a quad, every interior vertex shared by six triangles.
inline std::vector<std::uint32_t> grid_indices(int cells) {
  const auto at = [cells](int i, int j) { return static_cast<std::uint32_t>(j * (cells + 1) + i); };
  std::vector<std::uint32_t> out;
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      out.insert(out.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
      out.insert(out.end(), {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return out;
}

/// Random screen-space triangles over a width × height target (and past its edges) at random
/// depths, per-vertex colours with alpha, depth test kLess; every third draw blends.
inline std::vector<Mesh> random_draws(int width, int height, int draws, int triangles, Rng& rng) {
  std::vector<Mesh> out;
  for (int d = 0; d < draws; ++d) {
    DrawState s;
    if (d % 3 == 2) s.blend = BlendMode::kSourceOver;
    Mesh m = screen_mesh(s);
    m.color_source = ColorSource::kPerVertex;
    for (int t = 0; t < triangles; ++t) {
      const float z = static_cast<float>(rng.uniform(0.05, 0.95));
      const glm::dvec2 c(rng.uniform(-10, width + 10), rng.uniform(-10, height + 10));
      const double r = rng.uniform(2, 30);
      for (int k = 0; k < 3; ++k) {
        m.positions.emplace_back(static_cast<float>(c.x + rng.uniform(-r, r)),
                                 static_cast<float>(c.y + rng.uniform(-r, r)),
                                 z + static_cast<float>(rng.uniform(-0.04, 0.04)), 1.0f);
        m.colors.push_back({static_cast<std::uint8_t>(rng.range(0, 255)),
                            static_cast<std::uint8_t>(rng.range(0, 255)),
                            static_cast<std::uint8_t>(rng.range(0, 255)),
                            static_cast<std::uint8_t>(rng.range(64, 255))});
      }
    }
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace mosaic::test
