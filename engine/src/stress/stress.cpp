// stress/stress.cpp — the random cases, checks, reducer and run loop of `mosaic stress`
// (stress/stress.hpp says what each takes and gives).
#include "stress/stress.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <ostream>
#include <sstream>

#include "front/fixed_point.hpp"
#include "mosaic/errors.hpp"
#include "raster/sample_patterns.hpp"
#include "scenes/rng.hpp"

namespace mosaic::stress {
namespace {

using Rng = mosaic::SplitMix64;

// ---- Constants ---------------------------------------------------------------------------------

/// The clear colour of every check: alpha 4 is never used by a generated triangle (alpha 255).
constexpr Rgba8 kClear{1, 2, 3, 4};
/// Largest number of vertices of a generated grid (twice as many triangles): keeps one reference
/// render well under a second.
constexpr int kMaxGridVertices = 6000;
/// Largest number of triangles in a soup.
constexpr int kMaxSoup = 2500;
/// Subpixel steps per pixel of the 16.8 format (the .tris specification's 1/256 px).
constexpr double kUnits = 256;
/// The far end of the random "far away" factors: coordinates stay below float's 3.4e38.
constexpr double kMaxFarFactor = 1e30;
/// A grid cell stays convex while each of its vertices moves less than this fraction of a cell
/// along both lattice axes: a diagonal's far vertices start half a diagonal from it, and each of
/// the four may move 1/4 of that towards it.
constexpr double kMaxCellDisplacement = 0.25;
/// How far the engine's own rounding moves a grid vertex along an axis, in px: float32 at below
/// 2^15 px (half an ulp, 2^-10) plus snapping to 1/256 px (half a step).
constexpr double kRoundingSlackPx = 1.0 / 1024 + 1.0 / 512;
/// A 10,000 px needle, the longest sliver the issue names.
constexpr double kNeedleLengthPx = 10000;

// A sample's offset in 1/16 px from the pixel centre (raster/sample_patterns.hpp), so that fans
// can be centred exactly on samples.
std::array<int, 2> sample_offset16(int samples, int s) {
  const raster::SampleOffset o = raster::sample_pattern(samples)[static_cast<std::size_t>(s)];
  return {o.dx, o.dy};
}

// Rounds to the 1/256 px grid or the 1/16 px grid (where samples lie), or leaves the value.
double quantize(double v, int mode) {
  if (mode == 0) return v;
  const double q = mode == 1 ? kUnits : 16.0;
  return std::round(v * q) / q;
}
// The most quantize() moves a value, in px.
double quantize_error(int mode) { return mode == 0 ? 0.0 : mode == 1 ? 0.5 / kUnits : 0.5 / 16; }

Rgba8 color_id(std::uint32_t i) {
  return {static_cast<std::uint8_t>(i & 0xff), static_cast<std::uint8_t>((i >> 8) & 0xff),
          static_cast<std::uint8_t>((i >> 16) & 0xff), 255};
}

void add_vertex(Mesh& m, double x, double y, double z) {
  m.positions.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z),
                           1.0f);
}

void add_indexed(Mesh& m, Rng& rng, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (rng.chance(0.5)) std::swap(b, c);  // winding does not matter with culling off
  m.indices.insert(m.indices.end(), {a, b, c});
  m.colors.push_back(color_id(static_cast<std::uint32_t>(m.colors.size())));
}

// ---- Generators --------------------------------------------------------------------------------

// A rotated, jittered lattice covering the target, its border rows and columns optionally pushed
// far out (up to 1e30 px) along the lattice axes. Every cell stays convex, so the triangulation
// covers each sample exactly once.
void make_grid(StressCase& c, Rng& rng) {
  Mesh& m = c.mesh;
  const double angle = rng.chance(0.3) ? 0.0 : rng.uniform(0, 2 * std::numbers::pi);
  const double ca = std::cos(angle), sa = std::sin(angle);
  const double cx = c.width * rng.uniform(0.3, 0.7), cy = c.height * rng.uniform(0.3, 0.7);
  const double half = std::hypot(c.width, c.height) + 2;
  double step = rng.log_uniform(0.4, 300);
  int n = static_cast<int>(std::ceil(2 * half / step)) + 1;
  if (double(n) * n > kMaxGridVertices) {  // in double: n * n overflows int for tiny steps
    n = static_cast<int>(std::sqrt(double(kMaxGridVertices)));
    step = 2 * half / (n - 1);
  }
  n = std::max(n, 2);
  const double far = rng.chance(0.5) ? 1.0 : rng.log_uniform(10, kMaxFarFactor);
  const int qmode = rng.range(0, 2);
  // The jitter leaves room for the rounding that follows, so that no cell folds: a folded cell
  // overlaps its neighbour, and exact coverage then writes a sample twice.
  const double max_jitter =
      std::max(0.0, kMaxCellDisplacement * step - quantize_error(qmode) - kRoundingSlackPx);
  const double jitter = rng.chance(0.3) ? 0.0 : rng.uniform(0, 0.99) * max_jitter;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      double u = -half + i * step, v = -half + j * step;
      const bool border_i = i == 0 || i == n - 1, border_j = j == 0 || j == n - 1;
      if (!border_i && !border_j) {
        u += rng.uniform(-jitter, jitter);
        v += rng.uniform(-jitter, jitter);
      }
      if (border_i) u *= far;
      if (border_j) v *= far;
      add_vertex(m, quantize(cx + ca * u - sa * v, qmode), quantize(cy + sa * u + ca * v, qmode),
                 0.5);
    }
  }
  const auto un = static_cast<std::uint32_t>(n);
  for (std::uint32_t j = 0; j + 1 < un; ++j)
    for (std::uint32_t i = 0; i + 1 < un; ++i) {
      const std::uint32_t a = j * un + i, b = a + 1, d = a + un, e = d + 1;
      if (rng.chance(0.5)) {
        add_indexed(m, rng, a, b, e);
        add_indexed(m, rng, a, e, d);
      } else {
        add_indexed(m, rng, a, b, d);
        add_indexed(m, rng, b, e, d);
      }
    }
}

// Rings of a polar fan around a centre on a sample position, a pixel corner or anywhere; the
// outer ring encloses the target, sometimes from 1e30 px away.
void make_fan(StressCase& c, Rng& rng) {
  Mesh& m = c.mesh;
  double cx = 0, cy = 0;
  const int px = rng.range(0, c.width - 1), py = rng.range(0, c.height - 1);
  switch (rng.range(0, 2)) {
    case 0: {
      const auto o = sample_offset16(c.samples, rng.range(0, c.samples - 1));
      cx = px + 0.5 + o[0] / 16.0;
      cy = py + 0.5 + o[1] / 16.0;
      break;
    }
    case 1:
      cx = px;
      cy = py;
      break;
    default:
      cx = px + rng.range(0, 255) / kUnits;
      cy = py + rng.range(0, 255) / kUnits;
  }
  const int spokes = rng.range(4, 48);
  std::vector<double> angles;
  for (int i = 0; i < spokes; ++i)
    angles.push_back(2 * std::numbers::pi * (i + (rng.chance(0.3) ? 0.0 : rng.uniform(0, 0.8))) /
                     spokes);
  // With each spoke in its own sector no gap exceeds 1.8 / spokes turns <= 0.45 turns, so the
  // outer ring contains the circle of radius cos(0.45 pi) * r = 0.156 r around the centre.
  double reach = 0;
  for (double x : {0.0, double(c.width)})
    for (double y : {0.0, double(c.height)}) reach = std::max(reach, std::hypot(x - cx, y - cy));
  const double outer = (reach + 1) / 0.15 * (rng.chance(0.5) ? 1.0 : rng.log_uniform(1, 1e28));
  const int rings = rng.range(1, 4);
  std::vector<double> radii;
  const double inner = rng.log_uniform(0.01, std::max(0.02, reach + 1));
  for (int r = 0; r < rings; ++r)
    radii.push_back(rings == 1 ? outer : inner * std::pow(outer / inner, double(r) / (rings - 1)));
  add_vertex(m, cx, cy, 0.5);
  for (double r : radii)
    for (double a : angles) add_vertex(m, cx + r * std::cos(a), cy + r * std::sin(a), 0.5);
  const auto us = static_cast<std::uint32_t>(spokes);
  auto id = [&](int ring, std::uint32_t k) {
    return 1 + static_cast<std::uint32_t>(ring) * us + k % us;
  };
  for (std::uint32_t k = 0; k < us; ++k) add_indexed(m, rng, 0, id(0, k), id(0, k + 1));
  for (int r = 0; r + 1 < rings; ++r)
    for (std::uint32_t k = 0; k < us; ++k) {
      if (rng.chance(0.5)) {
        add_indexed(m, rng, id(r, k), id(r + 1, k), id(r + 1, k + 1));
        add_indexed(m, rng, id(r, k), id(r + 1, k + 1), id(r, k + 1));
      } else {
        add_indexed(m, rng, id(r, k), id(r + 1, k), id(r, k + 1));
        add_indexed(m, rng, id(r, k + 1), id(r + 1, k), id(r + 1, k + 1));
      }
    }
}

// A sphere, box or torus with consistent outward winding, rotated at random and projected with a
// perspective camera that sees it from outside; drawn with back faces culled (check_case draws
// the front faces too).
void make_closed(StressCase& c, Rng& rng) {
  std::vector<glm::dvec3> p;
  std::vector<std::array<std::uint32_t, 3>> tris;
  const int shape = rng.range(0, 2);
  if (shape == 0) {  // UV sphere; the pole rows repeat the pole (degenerate triangles there)
    const int seg = rng.range(3, 40), rings = rng.range(2, 20);
    for (int r = 0; r <= rings; ++r)
      for (int s = 0; s < seg; ++s) {
        const double th = std::numbers::pi * r / rings, ph = 2 * std::numbers::pi * s / seg;
        p.push_back({std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)});
      }
    auto id = [&](int r, int s) { return static_cast<std::uint32_t>(r * seg + s % seg); };
    for (int r = 0; r < rings; ++r)
      for (int s = 0; s < seg; ++s) {
        tris.push_back({id(r, s), id(r + 1, s + 1), id(r + 1, s)});
        tris.push_back({id(r, s), id(r, s + 1), id(r + 1, s + 1)});
      }
  } else if (shape == 1) {  // box with n x n faces
    const int n = rng.range(1, 8);
    const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a)
      for (int sign : {-1, 1}) {
        const glm::dvec3 normal = axes[a] * double(sign), u = axes[(a + 1) % 3] * double(sign),
                         v = axes[(a + 2) % 3];
        const auto base = static_cast<std::uint32_t>(p.size());
        for (int j = 0; j <= n; ++j)
          for (int i = 0; i <= n; ++i)
            p.push_back(normal + u * (2.0 * i / n - 1) + v * (2.0 * j / n - 1));
        const auto row = static_cast<std::uint32_t>(n + 1);
        for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j)
          for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
            const std::uint32_t q = base + j * row + i;
            tris.push_back({q, q + 1, q + row + 1});
            tris.push_back({q, q + row + 1, q + row});
          }
      }
  } else {  // torus
    const int seg = rng.range(3, 32), tube = rng.range(3, 16);
    const double minor = rng.uniform(0.1, 0.45);
    for (int i = 0; i < seg; ++i)
      for (int j = 0; j < tube; ++j) {
        const double a = 2 * std::numbers::pi * i / seg, b = 2 * std::numbers::pi * j / tube;
        const double r = 1 - minor + minor * std::cos(b);
        p.push_back({r * std::cos(a), minor * std::sin(b), r * std::sin(a)});
      }
    auto id = [&](int i, int j) {
      return static_cast<std::uint32_t>((i % seg) * tube + (j % tube));
    };
    for (int i = 0; i < seg; ++i)
      for (int j = 0; j < tube; ++j) {
        tris.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
        tris.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
      }
  }
  // Random rotation (an exact axis-aligned view a third of the time, for edge-on faces).
  glm::dmat3 rot(1.0);
  if (!rng.chance(1.0 / 3)) {
    const glm::dvec3 axis = glm::normalize(
        glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)) + 1e-9);
    const double a = rng.uniform(0, 2 * std::numbers::pi), co = std::cos(a), si = std::sin(a);
    const glm::dmat3 k(0, axis.z, -axis.y, -axis.z, 0, axis.x, axis.y, -axis.x, 0);
    rot = glm::dmat3(1.0) + si * k + (1 - co) * (k * k);
  }
  // Camera: the mesh (radius <= sqrt(3)) at a distance of 2 to 20 radii, a focal length that
  // makes it cover 0.05 to 3 times the target, and a random subpixel offset.
  const double dist = std::sqrt(3.0) * rng.uniform(2, 20);
  const double focal = rng.log_uniform(0.05, 3) * std::min(c.width, c.height) * dist / 2;
  const double ox = c.width * rng.uniform(0.2, 0.8), oy = c.height * rng.uniform(0.2, 0.8);
  Mesh& m = c.mesh;
  for (const glm::dvec3& q : p) {
    const glm::dvec3 v = rot * q;
    const double depth = dist - v.z;  // > 0: the eye is outside the mesh
    add_vertex(m, ox + focal * v.x / depth, oy - focal * v.y / depth,
               (depth - dist + 2) / 4);  // depth in (0, 1)
  }
  for (const auto& t : tris) {
    m.indices.insert(m.indices.end(), t.begin(), t.end());
    m.colors.push_back(color_id(static_cast<std::uint32_t>(m.colors.size())));
  }
  m.state.cull = CullMode::kBack;
}

// Unrelated triangles of every awkward kind, with a random depth state.
void make_soup(StressCase& c, Rng& rng) {
  Mesh& m = c.mesh;
  const int count = rng.range(1, kMaxSoup);
  const double w = c.width, h = c.height;
  for (int t = 0; t < count; ++t) {
    const double x = rng.uniform(-0.2 * w, 1.2 * w), y = rng.uniform(-0.2 * h, 1.2 * h);
    std::array<glm::dvec2, 3> v;
    switch (rng.range(0, 6)) {
      case 0:  // tiny: below 1/65536 px², next to a 1/16 px grid point
        v[0] = {std::round(x * 16) / 16, std::round(y * 16) / 16};
        v[1] = v[0] + glm::dvec2(rng.range(1, 3), 0) / kUnits;
        v[2] = v[0] + glm::dvec2(rng.range(-2, 2), 1) / kUnits;
        break;
      case 1: {  // sliver
        const double a = rng.uniform(0, 2 * std::numbers::pi), len = rng.log_uniform(2, 500);
        const glm::dvec2 d{std::cos(a), std::sin(a)};
        v = {glm::dvec2(x, y) - d * len, glm::dvec2(x, y) + d * len,
             glm::dvec2(x, y) + glm::dvec2(-d.y, d.x) * rng.log_uniform(1 / kUnits, 1)};
        break;
      }
      case 2: {  // needle: 10,000 px long, one 1/256 px step wide, on the 1/256 grid
        const glm::dvec2 d = glm::dvec2(rng.range(-64, 64), rng.range(-64, 64)) / kUnits;
        const double len = kNeedleLengthPx / std::max(1e-9, std::max(std::abs(d.x), std::abs(d.y)));
        const glm::dvec2 a0{std::round(x * kUnits) / kUnits, std::round(y * kUnits) / kUnits};
        v = {a0 - d * (len / 2), a0 + d * (len / 2),
             a0 + d * (len / 2) + glm::dvec2(0, 1 / kUnits)};
        break;
      }
      case 3: {  // huge: vertices up to 1e30 px away
        for (auto& q : v)
          q = glm::dvec2(x, y) + glm::dvec2(rng.uniform(-1, 1), rng.uniform(-1, 1)) *
                                     rng.log_uniform(10, kMaxFarFactor);
        break;
      }
      case 4: {  // degenerate: collinear or repeated
        const glm::dvec2 d{rng.range(-20, 20) / 16.0, rng.range(-20, 20) / 16.0};
        const glm::dvec2 a0{std::round(x * 16) / 16, std::round(y * 16) / 16};
        v = {a0, a0 + d * double(rng.range(-5, 5)), a0 + d * double(rng.range(-5, 5))};
        break;
      }
      default:  // ordinary, sometimes on the 1/16 px grid
        for (auto& q : v)
          q = glm::dvec2(quantize(x + rng.uniform(-40, 40), rng.range(0, 2)),
                         quantize(y + rng.uniform(-40, 40), rng.range(0, 2)));
    }
    const double z = rng.unit();
    for (const auto& q : v)
      add_vertex(m, q.x, q.y, std::clamp(z + rng.uniform(-0.1, 0.1), 0.0, 1.0));
    m.colors.push_back(color_id(static_cast<std::uint32_t>(t)));
  }
  static constexpr DepthTest kTests[] = {DepthTest::kLess, DepthTest::kLessEqual,
                                         DepthTest::kGreater, DepthTest::kGreaterEqual,
                                         DepthTest::kAlways};
  m.state.depth_test = kTests[rng.range(0, 4)];
  m.state.depth_write = rng.chance(0.8);
  m.state.cull = static_cast<CullMode>(rng.range(0, 2));
  m.state.front_face = rng.chance(0.5) ? FrontFace::kClockwise : FrontFace::kCounterClockwise;
}

// ---- Rendering and comparing --------------------------------------------------------------------

struct Image {
  std::vector<Rgba8> color, sample_color;
  std::vector<float> sample_depth;
  FrameStats stats;
};

Image render(const Mesh& mesh, int w, int h, int samples, Renderer& renderer) {
  RenderTarget target(w, h, samples, TargetOptions{true, true});
  target.set_clear(kClear);
  const Draw d = mesh.draw();
  Frame frame;
  frame.draws = std::span<const Draw>(&d, 1);
  Image out;
  out.stats = renderer.render(frame, target);
  out.color.assign(target.color().begin(), target.color().end());
  out.sample_color.assign(target.sample_color().begin(), target.sample_color().end());
  out.sample_depth.assign(target.sample_depth().begin(), target.sample_depth().end());
  return out;
}

// The first difference between two renders of the same frame, or "".
std::string difference(const Image& a, const Image& b) {
  if (a.stats.samples_written != b.stats.samples_written)
    return "samples_written " + std::to_string(a.stats.samples_written) + " vs " +
           std::to_string(b.stats.samples_written);
  if (a.stats.triangles_drawn != b.stats.triangles_drawn) return "triangles_drawn differs";
  for (std::size_t i = 0; i < a.sample_color.size(); ++i) {
    if (!(a.sample_color[i] == b.sample_color[i]) ||
        std::memcmp(&a.sample_depth[i], &b.sample_depth[i], sizeof(float)) != 0)
      return "sample " + std::to_string(i) + " differs";
  }
  if (a.color != b.color) return "resolved image differs";
  return "";
}

std::size_t covered(const Image& im) {
  return static_cast<std::size_t>(std::count_if(im.sample_color.begin(), im.sample_color.end(),
                                                [](const Rgba8& c) { return !(c == kClear); }));
}

// ---- The exact coverage oracle used to reduce coverage failures ---------------------------------

// Round to the nearest 1/256 px, a tie to the even step: the snapping rule of the .tris
// specification.
std::int64_t snap_units(double px) {
  const double s = px * kUnits;
  const double below = std::floor(s), frac = s - below;
  const bool up = frac > 0.5 || (frac == 0.5 && std::fmod(below, 2.0) != 0.0);
  return static_cast<std::int64_t>(up ? below + 1 : below);
}

// Per-sample coverage counts of `tris` drawn with `state` (fill rule and culling), exactly, in
// integers: a sample on an edge is decided as if nudged right and (D3D) down or (OpenGL) up.
// Valid while every vertex lies within the 16.8 range, where the engine neither clips nor clamps.
std::vector<std::uint32_t> oracle_counts(const std::vector<Triangle>& tris, const DrawState& state,
                                         int w, int h, int samples) {
  std::vector<std::uint32_t> count(static_cast<std::size_t>(w) * h * samples, 0);
  const std::int64_t nudge_y = state.fill_rule == FillRule::kD3D ? 1 : -1;
  for (const Triangle& t : tris) {
    std::array<std::int64_t, 3> X, Y;
    for (int k = 0; k < 3; ++k) {
      X[k] = snap_units(t.v[k].x);
      Y[k] = snap_units(t.v[k].y);
    }
    const std::int64_t area2 = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area2 == 0) continue;
    // y down: negative area is counter-clockwise on screen.
    const bool front = (state.front_face == FrontFace::kCounterClockwise) == (area2 < 0);
    if ((state.cull == CullMode::kBack && !front) || (state.cull == CullMode::kFront && front))
      continue;
    const std::int64_t orient = area2 > 0 ? 1 : -1;
    const auto [x0, x1] = std::minmax({X[0], X[1], X[2]});
    const auto [y0, y1] = std::minmax({Y[0], Y[1], Y[2]});
    const int px0 = static_cast<int>(std::max<std::int64_t>(0, x0 / 256 - 1));
    const int py0 = static_cast<int>(std::max<std::int64_t>(0, y0 / 256 - 1));
    const int px1 = static_cast<int>(std::min<std::int64_t>(w - 1, x1 / 256 + 1));
    const int py1 = static_cast<int>(std::min<std::int64_t>(h - 1, y1 / 256 + 1));
    for (int py = py0; py <= py1; ++py)
      for (int px = px0; px <= px1; ++px)
        for (int s = 0; s < samples; ++s) {
          const auto o = sample_offset16(samples, s);
          const std::int64_t sx = std::int64_t{px} * 256 + 128 + o[0] * 16;
          const std::int64_t sy = std::int64_t{py} * 256 + 128 + o[1] * 16;
          bool inside = true;
          for (int e = 0; e < 3 && inside; ++e) {
            const std::int64_t ax = X[e], ay = Y[e], bx = X[(e + 1) % 3], by = Y[(e + 1) % 3];
            const std::int64_t f = orient * ((bx - ax) * (sy - ay) - (by - ay) * (sx - ax));
            if (f > 0) continue;
            if (f < 0) {
              inside = false;
              continue;
            }
            const std::int64_t dfdx = -orient * (by - ay), dfdy = orient * (bx - ax);
            inside = dfdx > 0 || (dfdx == 0 && nudge_y * dfdy > 0);
          }
          if (inside) ++count[(static_cast<std::size_t>(py) * w + px) * samples + s];
        }
  }
  return count;
}

bool within_fixed_point_range(const std::vector<Triangle>& tris) {
  constexpr float kLimit = static_cast<float>(front::kGuardBandPx) - 1;
  for (const Triangle& t : tris)
    for (const glm::vec4& v : t.v)
      if (!(std::abs(v.x) <= kLimit && std::abs(v.y) <= kLimit)) return false;
  return true;
}

// Whether the engine's coverage of `tris` (depth off) disagrees with the oracle's: a covered
// sample the oracle leaves empty or the reverse, or a different number of writes.
bool coverage_disagrees(const std::vector<Triangle>& tris, const StressCase& c, DrawState state,
                        Renderer& renderer) {
  state.depth_test = DepthTest::kAlways;
  const Image im = render(mesh_of(tris, state), c.width, c.height, c.samples, renderer);
  const auto counts = oracle_counts(tris, state, c.width, c.height, c.samples);
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    total += counts[i];
    if ((counts[i] > 0) != !(im.sample_color[i] == kClear)) return true;
  }
  return total != im.stats.samples_written;
}

const char* depth_test_name(DepthTest t) {
  switch (t) {
    case DepthTest::kLess:
      return "less";
    case DepthTest::kLessEqual:
      return "less-equal";
    case DepthTest::kGreater:
      return "greater";
    case DepthTest::kGreaterEqual:
      return "greater-equal";
    default:
      return "always";
  }
}

}  // namespace

// ---- Public entry points -----------------------------------------------------------------------

const char* to_string(CaseKind kind) noexcept {
  switch (kind) {
    case CaseKind::kClosed:
      return "closed";
    case CaseKind::kGrid:
      return "grid";
    case CaseKind::kFan:
      return "fan";
    default:
      return "soup";
  }
}

StressCase generate_case(std::uint64_t seed, std::uint64_t index, int msaa) {
  Rng rng(seed * 0x9e3779b97f4a7c15ull ^ (index + 1) * 0xd1b54a32d192ed03ull);
  StressCase c;
  c.kind = static_cast<CaseKind>(rng.range(0, 3));
  static constexpr int kSampleCounts[] = {1, 4, 8, 16};
  c.samples = msaa != 0 ? msaa : kSampleCounts[rng.range(0, 3)];
  const int size_kind = rng.range(0, 19);
  if (size_kind == 0) {
    c.width = c.height = 1;
  } else if (size_kind == 1) {  // the widest target, a few rows
    c.width = kMaxTargetSize;
    c.height = rng.range(1, 16);
    if (msaa == 0) c.samples = std::min(c.samples, 4);  // keeps the reference render quick
  } else if (size_kind == 2) {                          // a thin column
    c.width = rng.range(1, 16);
    c.height = rng.range(1, 2048);
  } else if (size_kind < 6) {
    c.width = rng.range(1, 700);
    c.height = rng.range(1, 500);
  } else {
    c.width = rng.range(1, 200);
    c.height = rng.range(1, 200);
  }
  c.mesh.space = Space::kScreen;
  c.mesh.color_source = ColorSource::kPerTriangle;
  c.mesh.state.fill_rule = rng.chance(0.5) ? FillRule::kD3D : FillRule::kOpenGL;
  c.mesh.state.depth_test = DepthTest::kAlways;
  switch (c.kind) {
    case CaseKind::kClosed:
      make_closed(c, rng);
      break;
    case CaseKind::kGrid:
      make_grid(c, rng);
      break;
    case CaseKind::kFan:
      make_fan(c, rng);
      break;
    default:
      make_soup(c, rng);
  }
  return c;
}

std::vector<Triangle> triangles_of(const StressCase& c) {
  const Mesh& m = c.mesh;
  std::vector<Triangle> out;
  const std::size_t n = m.triangle_count();
  for (std::size_t t = 0; t < n; ++t) {
    Triangle tri;
    for (std::size_t k = 0; k < 3; ++k)
      tri.v[k] = m.positions[m.indices.empty() ? 3 * t + k : m.indices[3 * t + k]];
    tri.color = m.colors[t];
    out.push_back(tri);
  }
  return out;
}

Mesh mesh_of(const std::vector<Triangle>& tris, const DrawState& state) {
  Mesh m;
  m.space = Space::kScreen;
  m.color_source = ColorSource::kPerTriangle;
  m.state = state;
  for (const Triangle& t : tris) {
    m.positions.insert(m.positions.end(), std::begin(t.v), std::end(t.v));
    m.colors.push_back(t.color);
  }
  return m;
}

CheckResult check_case(const StressCase& c, const CheckOptions& options) {
  auto fail = [](FailureKind k, std::string m) { return CheckResult{k, std::move(m)}; };
  try {
    Renderer reference(RendererOptions{1, Isa::kReference});
    Renderer fast(RendererOptions{options.threads, options.isa});
    Renderer other(RendererOptions{.threads = options.other_threads,
                                   .isa = options.isa,
                                   .tile_size = options.other_tile_size});
    const Image ref = render(c.mesh, c.width, c.height, c.samples, reference);
    const Image fst = render(c.mesh, c.width, c.height, c.samples, fast);
    if (const std::string d = difference(ref, fst); !d.empty())
      return fail(FailureKind::kReferenceMismatch,
                  std::string(mosaic::to_string(fast.isa())) + " differs from the reference: " + d);
    const Image oth = render(c.mesh, c.width, c.height, c.samples, other);
    if (const std::string d = difference(fst, oth); !d.empty())
      return fail(FailureKind::kThreadMismatch,
                  std::to_string(options.threads) + " threads and " +
                      std::to_string(options.other_threads) + " threads with " +
                      std::to_string(options.other_tile_size) + " px tiles differ: " + d);
    const std::size_t all = static_cast<std::size_t>(c.width) * c.height * c.samples;
    if (c.kind == CaseKind::kGrid || c.kind == CaseKind::kFan) {
      const std::size_t cov = covered(ref);
      if (cov != all || ref.stats.samples_written != all)
        return fail(FailureKind::kCoverage, std::to_string(all - cov) + " samples uncovered, " +
                                                std::to_string(ref.stats.samples_written) +
                                                " writes for " + std::to_string(all) + " samples");
    }
    if (c.kind == CaseKind::kClosed) {
      // Degree zero: every sample lies under as many front faces as back faces.
      Mesh backs = c.mesh;
      backs.state.cull = CullMode::kFront;
      const Image b = render(backs, c.width, c.height, c.samples, fast);
      bool same_set = true;
      for (std::size_t i = 0; i < all && same_set; ++i)
        same_set = (fst.sample_color[i] == kClear) == (b.sample_color[i] == kClear);
      if (!same_set || fst.stats.samples_written != b.stats.samples_written)
        return fail(FailureKind::kBalance,
                    "front faces wrote " + std::to_string(fst.stats.samples_written) +
                        " samples, back faces " + std::to_string(b.stats.samples_written) +
                        (same_set ? "" : ", over different samples"));
    }
  } catch (const std::exception& e) {
    return fail(FailureKind::kException, std::string("render threw: ") + e.what());
  }
  return {};
}

std::vector<std::size_t> ddmin(std::size_t n,
                               const std::function<bool(const std::vector<std::size_t>&)>& fails,
                               int max_tests) {
  std::vector<std::size_t> current(n);
  for (std::size_t i = 0; i < n; ++i) current[i] = i;
  int tests = 0;
  auto test = [&](const std::vector<std::size_t>& s) {
    ++tests;
    return fails(s);
  };
  std::size_t granularity = 2;
  while (current.size() >= 2 && tests < max_tests) {
    const std::size_t chunk = (current.size() + granularity - 1) / granularity;
    std::vector<std::vector<std::size_t>> parts;
    for (std::size_t b = 0; b < current.size(); b += chunk)
      parts.emplace_back(
          current.begin() + static_cast<std::ptrdiff_t>(b),
          current.begin() + static_cast<std::ptrdiff_t>(std::min(current.size(), b + chunk)));
    bool reduced = false;
    for (const auto& part : parts) {  // a part alone
      if (tests >= max_tests) break;
      if (test(part)) {
        current = part;
        granularity = 2;
        reduced = true;
        break;
      }
    }
    if (!reduced && parts.size() > 2) {
      for (std::size_t k = 0; k < parts.size() && tests < max_tests; ++k) {  // all but one part
        std::vector<std::size_t> rest;
        for (std::size_t j = 0; j < parts.size(); ++j)
          if (j != k) rest.insert(rest.end(), parts[j].begin(), parts[j].end());
        if (test(rest)) {
          current = rest;
          granularity = std::max<std::size_t>(granularity - 1, 2);
          reduced = true;
          break;
        }
      }
    }
    if (!reduced) {
      if (granularity >= current.size()) break;  // 1-minimal
      granularity = std::min(current.size(), 2 * granularity);
    }
  }
  return current;
}

std::vector<Triangle> reduce_failure(const StressCase& c, const CheckResult& failure,
                                     const CheckOptions& options, int max_tests) {
  const std::vector<Triangle> all = triangles_of(c);
  auto subset = [&](const std::vector<std::size_t>& idx) {
    std::vector<Triangle> out;
    for (std::size_t i : idx) out.push_back(all[i]);
    return out;
  };
  Renderer reference(RendererOptions{1, Isa::kReference});
  Renderer fast(RendererOptions{options.threads, options.isa});
  Renderer other(RendererOptions{
      .threads = options.other_threads, .isa = options.isa, .tile_size = options.other_tile_size});
  std::function<bool(const std::vector<std::size_t>&)> fails;
  const DrawState state = c.mesh.state;
  auto image = [&](const std::vector<std::size_t>& idx, Renderer& r) {
    return render(mesh_of(subset(idx), state), c.width, c.height, c.samples, r);
  };
  switch (failure.kind) {
    case FailureKind::kReferenceMismatch:
      fails = [&](const auto& idx) {
        return !difference(image(idx, reference), image(idx, fast)).empty();
      };
      break;
    case FailureKind::kThreadMismatch:
      fails = [&](const auto& idx) {
        return !difference(image(idx, fast), image(idx, other)).empty();
      };
      break;
    case FailureKind::kCoverage:
    case FailureKind::kBalance: {
      if (!within_fixed_point_range(all)) return all;
      fails = [&](const auto& idx) {
        if (coverage_disagrees(subset(idx), c, state, fast)) return true;
        if (failure.kind != FailureKind::kBalance) return false;
        DrawState fronts = state;
        fronts.cull = CullMode::kFront;
        return coverage_disagrees(subset(idx), c, fronts, fast);
      };
      break;
    }
    case FailureKind::kException:
      fails = [&](const auto& idx) {
        try {
          image(idx, fast);
          image(idx, reference);
          return false;
        } catch (const std::exception&) {
          return true;
        }
      };
      break;
    default:
      return all;
  }
  std::vector<std::size_t> every(all.size());
  for (std::size_t i = 0; i < every.size(); ++i) every[i] = i;
  // The oracle may agree with the engine on the whole case (a generator whose mesh is not what
  // it claims): then there is nothing to reduce towards.
  if (!fails(every)) return all;
  return subset(ddmin(all.size(), fails, max_tests));
}

void write_failure(const StressCase& c, const std::vector<Triangle>& tris, const std::string& what,
                   const std::filesystem::path& path) {
  Scene scene;
  scene.name = path.stem().string();
  scene.width = c.width;
  scene.height = c.height;
  scene.clear_color = kClear;
  scene.meshes.push_back(mesh_of(tris, c.mesh.state));
  const std::filesystem::path body = path.string() + ".body";
  save_tris(scene, body);
  std::ifstream in(body, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  in.close();
  std::filesystem::remove(body);
  const DrawState& s = c.mesh.state;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << "# mosaic stress failure (" << to_string(c.kind) << " case): " << what << "\n"
      << "# replay: mosaic render " << path.filename().string() << " --msaa " << c.samples
      << " --fill-rule " << (s.fill_rule == FillRule::kD3D ? "d3d" : "gl") << " --depth-test "
      << (s.depth_test == DepthTest::kAlways && !s.depth_write ? "off"
                                                               : depth_test_name(s.depth_test))
      << (s.depth_test == DepthTest::kGreater || s.depth_test == DepthTest::kGreaterEqual
              ? "\n# (the CLI clears depth to 0 for greater tests; the failing frame cleared it to "
                "1)"
              : "")
      << "\n# culled triangles are left out of the file; the rest draw with culling off\n"
      << text.str();
  if (!out) throw Error(Errc::kIo, "cannot write " + path.string());
}

RunSummary run_stress(const RunOptions& options, std::ostream& log) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  const double budget = options.minutes * 60;
  RunSummary summary;
  double next_progress = options.progress_seconds;
  CheckOptions check;
  check.threads = options.threads;
  check.other_threads = options.threads == 1 ? 7 : 1;
  auto progress = [&] {
    log << "stress: frames " << summary.frames << ", triangles " << summary.triangles
        << ", failures " << summary.failures << " (" << std::fixed << std::setprecision(1)
        << elapsed() << " s)" << std::endl;
  };
  for (std::uint64_t index = 0;; ++index) {
    if (options.frames != 0 && summary.frames >= options.frames) break;
    if (elapsed() >= budget) break;
    const StressCase c = generate_case(options.seed, index, options.msaa);
    const CheckResult r = check_case(c, check);
    ++summary.frames;
    summary.triangles += c.mesh.triangle_count();
    if (!r.ok()) {
      ++summary.failures;
      const std::vector<Triangle> reduced = reduce_failure(c, r, check, options.max_reduce_tests);
      const std::filesystem::path file =
          options.out_dir /
          ("stress-" + std::to_string(options.seed) + "-" + std::to_string(index) + ".tris");
      write_failure(c, reduced, r.message, file);
      summary.files.push_back(file);
      log << "stress: FAILED frame " << index << " (" << to_string(c.kind) << ", " << c.width << "x"
          << c.height << ", " << c.samples << "x, " << c.mesh.triangle_count()
          << " triangles): " << r.message << "; reduced to " << reduced.size() << " triangles in "
          << printable(file.string()) << std::endl;
    }
    if (elapsed() >= next_progress) {
      progress();
      next_progress = elapsed() + options.progress_seconds;
    }
  }
  progress();
  return summary;
}

}  // namespace mosaic::stress
