// scenes/builtin.cpp — the built-in scenes: a showcase, stress cases, test patterns, and a dense
// closed mesh (a torus knot): 1 M triangles at three sizes, 65k filling a third of the frame, and
// 2 M filling it.
//
// Takes: a scene name, a target size and a seed. Gives: a Scene whose bits depend only on those
// three (every platform, every standard library): randomness comes from splitmix64
// (scenes/rng.hpp), and angles from a Taylor series that uses only IEEE + and * (std::sin's last
// bit depends on the libm; the build disables FMA contraction). Screen-space vertices are snapped
// to 1/256 px, as the renderer snaps them, so the stated areas and lengths hold exactly for what is
// drawn and a .tris of the scene reproduces it bit for bit.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <utility>
#include <vector>

#include "front/fixed_point.hpp"
#include "front/setup.hpp"
#include "mosaic/errors.hpp"
#include "mosaic/scene.hpp"
#include "raster/sample_patterns.hpp"
#include "scenes/rng.hpp"

namespace mosaic {
namespace {

using Rng = mosaic::SplitMix64;

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
/// Terms of the sine and cosine series: for |x| <= pi the 20th term is below 1e-30.
constexpr int kSeriesTerms = 20;
/// Alpha of every built-in colour: the renderer does not blend.
constexpr std::uint8_t kOpaque = 255;

/// sin and cos of x (any finite x), the same bits on every platform; accurate to ~1e-15.
glm::dvec2 cos_sin(double x) {
  x -= kTwoPi * std::floor(x / kTwoPi + 0.5);  // to [-pi, pi]: floor is exact
  double c = 0, s = 0, term_c = 1, term_s = x;
  const double x2 = x * x;
  for (int n = 0; n < kSeriesTerms; ++n) {
    c += term_c;
    s += term_s;
    term_c *= -x2 / ((2.0 * n + 1) * (2.0 * n + 2));
    term_s *= -x2 / ((2.0 * n + 2) * (2.0 * n + 3));
  }
  return {c, s};
}

Rgba8 rgb(int r, int g, int b) {
  return {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b),
          kOpaque};
}

/// A fully saturated colour at hue `h` in [0, 1) (the HSV hexcone, value and saturation 1).
Rgba8 hue(double h) {
  const double x = 6.0 * (h - std::floor(h));
  const int sector = std::min(5, static_cast<int>(x));
  const int up = static_cast<int>(std::lround(255.0 * (x - sector)));
  const int down = 255 - up;
  switch (sector) {
    case 0:
      return rgb(255, up, 0);
    case 1:
      return rgb(down, 255, 0);
    case 2:
      return rgb(0, 255, up);
    case 3:
      return rgb(0, down, 255);
    case 4:
      return rgb(up, 0, 255);
    default:
      return rgb(255, 0, down);
  }
}

// ---- screen-space helpers ----

/// A point snapped to the renderer's 16.8 grid, in 1/256 px units.
struct Fixed {
  std::int64_t x = 0, y = 0;
};

Fixed snap(glm::dvec2 p) { return {front::snap(p.x), front::snap(p.y)}; }

/// Twice the signed area of a snapped triangle, in (1/256 px)².
std::int64_t area2(const std::array<Fixed, 3>& p) {
  return (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
}

/// Area of a snapped triangle in px².
double area_px2(const std::array<Fixed, 3>& p) {
  constexpr double kUnitsPerPx2 = double{front::kSubpixelOne} * front::kSubpixelOne;
  return std::fabs(static_cast<double>(area2(p))) / (2.0 * kUnitsPerPx2);
}

double length_px(Fixed a, Fixed b) {
  const double dx = static_cast<double>(b.x - a.x), dy = static_cast<double>(b.y - a.y);
  return std::sqrt(dx * dx + dy * dy) / front::kSubpixelOne;
}

glm::vec4 to_position(Fixed p, float z) {
  return {static_cast<float>(p.x) / front::kSubpixelOne,
          static_cast<float>(p.y) / front::kSubpixelOne, z, 1.0f};
}

/// A screen-space mesh with one flat colour per triangle.
Mesh flat_screen_mesh() {
  Mesh m;
  m.space = Space::kScreen;
  m.color_source = ColorSource::kPerTriangle;
  return m;
}

void add_triangle(Mesh& m, const std::array<Fixed, 3>& p, const std::array<float, 3>& z,
                  Rgba8 color) {
  for (int k = 0; k < 3; ++k) m.positions.push_back(to_position(p[k], z[k]));
  m.colors.push_back(color);
}

/// A "fat" random triangle of the given area around `centre`: corners about 120° apart at
/// about the same radius (jittered so no two are alike), scaled by (sx, sy) after the area is
/// set, so the area becomes area * sx * sy.
std::array<glm::dvec2, 3> random_triangle(Rng& rng, glm::dvec2 centre, double area, double sx,
                                          double sy) {
  // Jitter of the corner angles (radians) and radii (fraction): enough for variety, too little
  // for slivers.
  constexpr double kAngleJitter = 0.5;
  constexpr double kRadiusJitter = 0.4;
  const double theta0 = rng.uniform(0, kTwoPi);
  std::array<glm::dvec2, 3> v;
  for (int k = 0; k < 3; ++k) {
    const double theta = theta0 + k * kTwoPi / 3 + rng.uniform(-kAngleJitter, kAngleJitter);
    v[k] = cos_sin(theta) * rng.uniform(1 - kRadiusJitter, 1 + kRadiusJitter);
  }
  const double a0 = 0.5 * std::fabs((v[1].x - v[0].x) * (v[2].y - v[0].y) -
                                    (v[2].x - v[0].x) * (v[1].y - v[0].y));
  const double scale = std::sqrt(area / a0);
  for (glm::dvec2& p : v) p = centre + glm::dvec2(p.x * scale * sx, p.y * scale * sy);
  return v;
}

/// Draws snapped triangles until `accept` holds (snapping moves areas and lengths slightly,
/// so a triangle generated at the edge of its range can fall out of it).
std::array<Fixed, 3> generate(const std::function<std::array<glm::dvec2, 3>()>& make,
                              const std::function<bool(const std::array<Fixed, 3>&)>& accept) {
  while (true) {
    const std::array<glm::dvec2, 3> v = make();
    const std::array<Fixed, 3> p{snap(v[0]), snap(v[1]), snap(v[2])};
    if (accept(p)) return p;
  }
}

// ---- the scenes ----

/// Triangles and areas of `random-small`.
constexpr std::size_t kSmallCount = 100'000;
constexpr double kSmallMinArea = 10, kSmallMaxArea = 50;  // px²

Scene random_small(Scene scene, Rng& rng) {
  Mesh m = flat_screen_mesh();
  m.positions.reserve(3 * kSmallCount);
  m.colors.reserve(kSmallCount);
  const double w = scene.width, h = scene.height;
  for (std::size_t i = 0; i < kSmallCount; ++i) {
    const auto p = generate(
        [&] {
          const glm::dvec2 c(rng.uniform(0, w), rng.uniform(0, h));
          return random_triangle(rng, c, rng.uniform(kSmallMinArea, kSmallMaxArea), 1, 1);
        },
        [](const std::array<Fixed, 3>& q) {
          const double a = area_px2(q);
          return a >= kSmallMinArea && a <= kSmallMaxArea;
        });
    add_triangle(m, p, {rng.depth(), rng.depth(), rng.depth()}, rng.color());
  }
  scene.meshes.push_back(std::move(m));
  return scene;
}

/// Triangles of `random-large` and their areas as fractions of the screen area.
constexpr std::size_t kLargeCount = 1'000;
constexpr double kLargeMinFraction = 0.05, kLargeMaxFraction = 0.20;

Scene random_large(Scene scene, Rng& rng) {
  Mesh m = flat_screen_mesh();
  const double w = scene.width, h = scene.height;
  const double screen = w * h;
  for (std::size_t i = 0; i < kLargeCount; ++i) {
    const auto p = generate(
        [&] {
          // Built in the unit square and stretched to the screen, so the shapes follow its
          // aspect ratio and the area fraction is kept.
          const glm::dvec2 c(rng.uniform(0, w), rng.uniform(0, h));
          return random_triangle(rng, c, rng.uniform(kLargeMinFraction, kLargeMaxFraction), w, h);
        },
        [&](const std::array<Fixed, 3>& q) {
          const double f = area_px2(q) / screen;
          return f >= kLargeMinFraction && f <= kLargeMaxFraction;
        });
    add_triangle(m, p, {rng.depth(), rng.depth(), rng.depth()}, rng.color());
  }
  scene.meshes.push_back(std::move(m));
  return scene;
}

/// Triangles of `slivers`, their length (longest edge) and width (height over that edge).
constexpr std::size_t kSliverCount = 10'000;
constexpr double kSliverMinLength = 100, kSliverMaxLength = 800;  // px
constexpr double kSliverMinWidth = 0.5, kSliverMaxWidth = 3;      // px
/// The apex lies over the middle 80 % of the long edge, so that edge stays the longest.
constexpr double kSliverApexSpan = 0.8;

Scene slivers(Scene scene, Rng& rng) {
  Mesh m = flat_screen_mesh();
  const double w = scene.width, h = scene.height;
  for (std::size_t i = 0; i < kSliverCount; ++i) {
    const auto p = generate(
        [&] {
          const glm::dvec2 c(rng.uniform(0, w), rng.uniform(0, h));
          const double len = rng.uniform(kSliverMinLength, kSliverMaxLength);
          const double width = rng.uniform(kSliverMinWidth, kSliverMaxWidth);
          const glm::dvec2 d = cos_sin(rng.uniform(0, kTwoPi));
          const glm::dvec2 n(-d.y, d.x);
          const double t = rng.uniform(-kSliverApexSpan, kSliverApexSpan);
          return std::array<glm::dvec2, 3>{c - d * (len / 2), c + d * (len / 2),
                                           c + d * (t * len / 2) + n * width};
        },
        [](const std::array<Fixed, 3>& q) {
          const double len =
              std::max({length_px(q[0], q[1]), length_px(q[1], q[2]), length_px(q[2], q[0])});
          const double width = 2 * area_px2(q) / len;
          return len >= kSliverMinLength && len <= kSliverMaxLength && width >= kSliverMinWidth &&
                 width <= kSliverMaxWidth;
        });
    add_triangle(m, p, {rng.depth(), rng.depth(), rng.depth()}, rng.color());
  }
  scene.meshes.push_back(std::move(m));
  return scene;
}

/// Wedges of the Siemens star (half black, half white) and its radius over the shorter side.
constexpr int kStarWedges = 72;
constexpr double kStarRadius = 0.45;
/// Depth of the star and the fan: any value the default depth test passes against clear depth.
constexpr float kFlatDepth = 0.5f;

/// A fan of `count` triangles around the snapped `centre` out to `radius` px, every outer
/// vertex shared by its two neighbours, so the fan has neither overlaps nor gaps.
void add_fan(Mesh& m, Fixed centre, double radius, int count,
             const std::function<Rgba8(int)>& color) {
  const glm::dvec2 c(static_cast<double>(centre.x) / front::kSubpixelOne,
                     static_cast<double>(centre.y) / front::kSubpixelOne);
  std::vector<Fixed> rim(count + 1);
  for (int k = 0; k < count; ++k) rim[k] = snap(c + cos_sin(kTwoPi * k / count) * radius);
  rim[count] = rim[0];
  for (int k = 0; k < count; ++k)
    add_triangle(m, {centre, rim[k], rim[k + 1]}, {kFlatDepth, kFlatDepth, kFlatDepth}, color(k));
}

Scene star(Scene scene) {
  // Grey background, so the silhouette of the black wedges shows.
  constexpr std::uint8_t kGrey = 128;
  scene.clear_color = {kGrey, kGrey, kGrey, kOpaque};
  Mesh m = flat_screen_mesh();
  const Fixed centre = snap({scene.width / 2.0, scene.height / 2.0});
  const double radius = kStarRadius * std::min(scene.width, scene.height);
  add_fan(m, centre, radius, kStarWedges,
          [](int k) { return k % 2 == 0 ? rgb(255, 255, 255) : rgb(0, 0, 0); });
  scene.meshes.push_back(std::move(m));
  return scene;
}

/// Triangles of the fan and its radius over the shorter side.
constexpr int kFanTriangles = 24;
constexpr double kFanRadius = 0.4;

Scene fan(Scene scene) {
  // The centre is sample 0 of the standard 4x pattern in the middle pixel: every triangle has
  // a vertex exactly on that sample, and the fill rule must give it to exactly one of them.
  const int px = scene.width / 2, py = scene.height / 2;
  const raster::SampleOffset o = raster::kPattern4[0];
  const Fixed centre{raster::sample_x_fixed(px, o), raster::sample_y_fixed(py, o)};
  Mesh m = flat_screen_mesh();
  const double radius = kFanRadius * std::min(scene.width, scene.height);
  add_fan(m, centre, radius, kFanTriangles,
          [](int k) { return hue(static_cast<double>(k) / kFanTriangles); });
  scene.meshes.push_back(std::move(m));
  return scene;
}

// ---- the 3-D showcase ----

/// A rotation about the y axis (angle in radians), from the portable cos_sin.
glm::dmat4 rotate_y(double angle) {
  const glm::dvec2 cs = cos_sin(angle);
  glm::dmat4 r(1.0);
  r[0][0] = cs.x;
  r[0][2] = -cs.y;
  r[2][0] = cs.y;
  r[2][2] = cs.x;
  return r;
}

/// A rotation about the x axis (angle in radians).
glm::dmat4 rotate_x(double angle) {
  const glm::dvec2 cs = cos_sin(angle);
  glm::dmat4 r(1.0);
  r[1][1] = cs.x;
  r[1][2] = cs.y;
  r[2][1] = -cs.y;
  r[2][2] = cs.x;
  return r;
}

glm::dmat4 translate(glm::dvec3 t) {
  glm::dmat4 m(1.0);
  m[3] = glm::dvec4(t, 1.0);
  return m;
}

/// Right-handed look-at view (as glm::lookAtRH), built here so no libm call is involved.
glm::dmat4 look_at(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up) {
  const glm::dvec3 f = glm::normalize(target - eye);
  const glm::dvec3 s = glm::normalize(glm::cross(f, up));
  const glm::dvec3 u = glm::cross(s, f);
  glm::dmat4 v(1.0);
  for (int i = 0; i < 3; ++i) {
    v[i][0] = s[i];
    v[i][1] = u[i];
    v[i][2] = -f[i];
  }
  v[3][0] = -glm::dot(s, eye);
  v[3][1] = -glm::dot(u, eye);
  v[3][2] = glm::dot(f, eye);
  return v;
}

/// Perspective projection with depth z/w in [0, 1], 0 at the near plane (as
/// glm::perspectiveRH_ZO), from the focal length 1 / tan(fovy / 2).
glm::dmat4 perspective(double focal, double aspect, double near_plane, double far_plane) {
  glm::dmat4 p(0.0);
  p[0][0] = focal / aspect;
  p[1][1] = focal;
  p[2][2] = far_plane / (near_plane - far_plane);
  p[2][3] = -1.0;
  p[3][2] = -(far_plane * near_plane) / (far_plane - near_plane);
  return p;
}

/// A clip-space mesh from world-space vertices.
Mesh clip_mesh(const glm::dmat4& view_projection, const std::vector<glm::dvec3>& world) {
  Mesh m;
  m.space = Space::kClip;
  m.positions.reserve(world.size());
  for (const glm::dvec3& p : world)
    m.positions.push_back(glm::vec4(view_projection * glm::dvec4(p, 1.0)));
  return m;
}

std::vector<glm::dvec3> transformed(const glm::dmat4& model, std::vector<glm::dvec3> points) {
  for (glm::dvec3& p : points) p = glm::dvec3(model * glm::dvec4(p, 1.0));
  return points;
}

Scene showcase(Scene scene) {
  // Camera: a little above the objects, looking slightly down; a 58° vertical field of view.
  constexpr double kFocal = 1.8;
  constexpr double kNear = 0.5, kFar = 40.0;  // world units; the scene spans about 20
  const glm::dmat4 vp =
      perspective(kFocal, static_cast<double>(scene.width) / scene.height, kNear, kFar) *
      look_at({0.0, 2.5, 7.0}, {0.0, 0.2, 0.0}, {0.0, 1.0, 0.0});
  scene.clear_color = rgb(24, 28, 44);  // night blue: every object stands out from it
  scene.camera.view_projection = glm::mat4(vp);

  // Ground: a checkerboard at y = -1 whose receding edges show aliasing plainly.
  constexpr int kTilesX = 16, kTilesZ = 18;
  constexpr double kGroundX0 = -8.0, kGroundZ0 = -12.0, kGroundY = -1.0;  // one unit per tile
  {
    std::vector<glm::dvec3> v;
    Mesh ground;
    for (int j = 0; j < kTilesZ; ++j) {
      for (int i = 0; i < kTilesX; ++i) {
        const double x = kGroundX0 + i, z = kGroundZ0 + j;
        const glm::dvec3 a(x, kGroundY, z), b(x + 1, kGroundY, z), c(x + 1, kGroundY, z + 1),
            d(x, kGroundY, z + 1);
        v.insert(v.end(), {a, b, c, a, c, d});
        const Rgba8 col = (i + j) % 2 == 0 ? rgb(196, 196, 186) : rgb(58, 62, 72);
        ground.colors.insert(ground.colors.end(), {col, col});
      }
    }
    Mesh m = clip_mesh(vp, v);
    m.color_source = ColorSource::kPerTriangle;
    m.colors = std::move(ground.colors);
    scene.meshes.push_back(std::move(m));
  }

  // A colour cube resting on the ground, turned 30° about y.
  {
    std::vector<glm::dvec3> v;
    Mesh cube;
    for (int k = 0; k < 8; ++k) {
      v.emplace_back(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0);
      cube.colors.push_back(rgb(k & 1 ? 255 : 20, k & 2 ? 255 : 20, k & 4 ? 255 : 20));
    }
    Mesh m = clip_mesh(vp, transformed(translate({-1.3, 0.0, 0.0}) * rotate_y(kPi / 6), v));
    m.color_source = ColorSource::kPerVertex;
    m.colors = std::move(cube.colors);
    // Two triangles per face of the cube (vertex k has x = bit 0, y = bit 1, z = bit 2).
    m.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 4, 6, 0, 6, 2,
                 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3};
    scene.meshes.push_back(std::move(m));
  }

  // An octahedron that pierces the cube and the ground: the z-buffer draws where they cross.
  {
    const std::vector<glm::dvec3> v{{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                    {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    constexpr double kSize = 1.3;
    glm::dmat4 scale(kSize);
    scale[3][3] = 1.0;
    Mesh m = clip_mesh(
        vp, transformed(translate({0.1, 0.15, 0.4}) * rotate_y(0.35) * rotate_x(0.6) * scale, v));
    m.color_source = ColorSource::kPerVertex;
    m.colors = {rgb(255, 140, 0),  rgb(255, 230, 40), rgb(250, 60, 200),
                rgb(40, 220, 230), rgb(60, 230, 90),  rgb(70, 90, 255)};
    m.indices = {0, 2, 4, 4, 2, 1, 1, 2, 5, 5, 2, 0, 0, 4, 3, 4, 1, 3, 1, 5, 3, 5, 0, 3};
    scene.meshes.push_back(std::move(m));
  }

  // Two large triangles crossing each other in an X (seen from above).
  {
    const std::vector<glm::dvec3> v{{2.0, -1.0, 1.4},  {4.2, -1.0, -1.2}, {3.1, 2.2, 0.1},
                                    {2.0, -1.0, -1.2}, {4.2, -1.0, 1.4},  {3.1, 1.8, 0.1}};
    Mesh m = clip_mesh(vp, v);
    m.color_source = ColorSource::kPerVertex;
    m.colors = {rgb(230, 40, 40), rgb(250, 200, 40), rgb(255, 255, 255),
                rgb(30, 60, 220), rgb(30, 200, 220), rgb(200, 230, 255)};
    scene.meshes.push_back(std::move(m));
  }

  // Needles: thin tapering spokes behind everything, about a pixel wide at 1080p, so that
  // antialiasing (or its absence) shows on long near-horizontal and near-vertical edges.
  {
    constexpr int kNeedles = 16;
    constexpr double kNeedleLength = 4.5, kNeedleHalfWidth = 0.008;
    const glm::dvec3 hub(0.0, 2.8, -6.0);
    std::vector<glm::dvec3> v;
    for (int k = 0; k < kNeedles; ++k) {
      // Offset by a quarter step so no spoke is exactly axis-aligned.
      const glm::dvec2 d = cos_sin(kTwoPi * (k + 0.25) / kNeedles);
      const glm::dvec3 dir(d.x, d.y, 0.0), side(-d.y, d.x, 0.0);
      v.insert(v.end(), {hub + side * kNeedleHalfWidth, hub - side * kNeedleHalfWidth,
                         hub + dir * kNeedleLength});
    }
    Mesh m = clip_mesh(vp, v);
    m.color_source = ColorSource::kConstant;
    m.color = rgb(255, 236, 200);
    scene.meshes.push_back(std::move(m));
  }
  return scene;
}

// ---- the torus knot: a dense closed mesh ----

/// The (p, q) torus knot of the `knot` scenes: p turns about the y axis, q through the hole.
constexpr int kKnotP = 2, kKnotQ = 3;
/// Segments along the curve (u) and around the tube (v): 2·u·v triangles on u·v shared
/// vertices. `knot`: 1,048,576 triangles; `knot-65k` a scanned-model-sized 65,536 (a sixteenth,
/// each side a quarter as many segments); `knot-2m` 2,097,152 (twice the segments along).
struct KnotMesh {
  int u, v;
};
constexpr KnotMesh kKnot1M{2048, 256}, kKnot65k{512, 64}, kKnot2M{4096, 256};
/// Tube radius against a curve radius of 2 ± 1 (thick, yet the strands never touch), and the
/// radial noise of every vertex as a fraction of it (about a fifth of the shorter edge).
constexpr double kKnotTube = 0.4, kKnotNoise = 0.005;
/// Radius of a sphere about the origin that holds the whole mesh: |curve| <= 3.
constexpr double kKnotBound = 3.0 + kKnotTube * (1.0 + kKnotNoise);
/// Seed of the noise: fixed, so the mesh does not depend on the scene seed.
constexpr std::uint64_t kKnotSeed = 0x6b6e6f74;  // "knot"
/// The camera looks down at the knot from this angle above its plane (radians, 50°).
constexpr double kKnotElevation = 50.0 * kPi / 180.0;
/// `knot` and `knot-2m` fill this fraction of the target's width or height, whichever binds
/// first; `knot-65k` fills kKnotThirdFill: its box is then a third of a 16:9 target's area.
constexpr double kKnotFill = 0.9, kKnotThirdFill = 0.72;
/// The camera is never nearer than this many bounding radii: near plane well clear of the mesh.
constexpr double kKnotMinDistance = 3.0;
/// Vertical focal length that sets the camera distance of the px-sized scenes (58° field).
constexpr double kKnotFocal = 1.8;

/// Calls f(position, normal) for every vertex of the knot in world space, ring by ring along
/// the curve (vertex i·V + j is ring i, side j). The noise restarts from kKnotSeed on every
/// call, so two calls give the same vertices: the scene walks them twice instead of storing them.
template <class F>
void for_each_knot_vertex(KnotMesh mesh, const std::vector<glm::dvec2>& around, F&& f) {
  Rng rng(kKnotSeed);
  for (int i = 0; i < mesh.u; ++i) {
    const double t = kTwoPi * i / mesh.u;
    const glm::dvec2 cp = cos_sin(kKnotP * t), cq = cos_sin(kKnotQ * t);
    const double r = 2.0 + cq.x, dr = -kKnotQ * cq.y;
    const glm::dvec3 c(r * cp.x, cq.y, r * cp.y);
    // Frame N = T × y, B = T × N: T's horizontal part (>= p) never vanishes, so it never flips.
    const glm::dvec3 tangent = glm::normalize(
        glm::dvec3(dr * cp.x - r * kKnotP * cp.y, kKnotQ * cq.x, dr * cp.y + r * kKnotP * cp.x));
    const glm::dvec3 n = glm::normalize(glm::cross(tangent, glm::dvec3(0, 1, 0)));
    const glm::dvec3 b = glm::cross(tangent, n);
    for (int j = 0; j < mesh.v; ++j) {
      const glm::dvec3 normal = around[j].x * n + around[j].y * b;  // the exact tube normal
      const double radius = kKnotTube * (1.0 + kKnotNoise * rng.uniform(-1.0, 1.0));
      f(c + radius * normal, normal);
    }
  }
}

/// The knot seen from above at kKnotElevation, centred. width_px > 0: its projection is
/// width_px pixels wide on any target; 0: it fills `fill` of the target's width or height.
Scene knot(Scene scene, KnotMesh mesh, double width_px, double fill = kKnotFill) {
  std::vector<glm::dvec2> around(mesh.v);  // the tube's cross-section, shared by every ring
  for (int j = 0; j < mesh.v; ++j) around[j] = cos_sin(kTwoPi * j / mesh.v);
  const double w = scene.width, h = scene.height;
  // Far enough for the stated width with a natural lens, never nearer than kKnotMinDistance.
  const double distance = width_px > 0
                              ? std::max(kKnotMinDistance, kKnotFocal * h / width_px) * kKnotBound
                              : kKnotMinDistance * kKnotBound;
  const glm::dvec2 elevation = cos_sin(kKnotElevation);
  const glm::dmat4 view = look_at(glm::dvec3(0.0, elevation.y, elevation.x) * distance,
                                  glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  // First walk: the projection's extent per unit of focal length, x/-z and y/-z.
  glm::dvec2 lo(1e300), hi(-1e300);
  for_each_knot_vertex(mesh, around, [&](const glm::dvec3& p, const glm::dvec3&) {
    const glm::dvec3 v(view * glm::dvec4(p, 1.0));
    const glm::dvec2 s(v.x / -v.z, v.y / -v.z);
    lo = glm::min(lo, s);
    hi = glm::max(hi, s);
  });
  // Pixels per unit of x/-z (square pixels): the stated width, or the fill of the target.
  const glm::dvec2 extent = hi - lo;
  const double px =
      width_px > 0 ? width_px / extent.x : fill * std::min(w / extent.x, h / extent.y);
  const double near_plane = distance - 1.01 * kKnotBound, far_plane = distance + 1.01 * kKnotBound;
  glm::dmat4 proj = perspective(2.0 * px / h, w / h, near_plane, far_plane);
  // Move the box's centre to the middle of the viewport: its NDC offset times w (= -z in view).
  proj[2][0] = proj[0][0] * 0.5 * (lo.x + hi.x);
  proj[2][1] = proj[1][1] * 0.5 * (lo.y + hi.y);
  const glm::dmat4 vp = proj * view;
  scene.clear_color = rgb(20, 22, 30);  // dark blue-grey, as the orbit example's
  scene.camera.view_projection = glm::mat4(vp);

  // Second walk: clip-space positions, world-space normals, and Lambert light baked into the
  // vertex colours: albedo * (ambient + diffuse * max(0, n·l)), lit from the upper left and the
  // front. Scene::light is the same light, for drawing the normals lit per pixel instead.
  const glm::dvec3 light = glm::normalize(glm::dvec3(-0.5, 0.9, 0.6));
  const glm::dvec3 albedo(0.95, 0.55, 0.30);  // warm copper
  constexpr double kAmbient = 0.15, kDiffuse = 0.85;
  scene.light = {glm::vec3(light), glm::vec3(albedo), static_cast<float>(kAmbient),
                 static_cast<float>(kDiffuse), false};
  Mesh m;
  m.space = Space::kClip;
  m.color_source = ColorSource::kPerVertex;
  const std::size_t vertices = static_cast<std::size_t>(mesh.u) * mesh.v;
  m.positions.reserve(vertices);
  m.colors.reserve(vertices);
  m.normals.reserve(vertices);
  for_each_knot_vertex(mesh, around, [&](const glm::dvec3& p, const glm::dvec3& normal) {
    m.positions.push_back(glm::vec4(vp * glm::dvec4(p, 1.0)));
    m.normals.push_back(glm::vec3(normal));
    const double shade = kAmbient + kDiffuse * std::max(0.0, glm::dot(normal, light));
    // Round half up (shade * albedo is in [0, 1]): exact, and no libm call.
    const auto channel = [&](double a) { return static_cast<int>(255.0 * a * shade + 0.5); };
    m.colors.push_back(rgb(channel(albedo.r), channel(albedo.g), channel(albedo.b)));
  });
  // Both loops wrap, so every edge has two triangles. Along +t then +v the quad turns inward
  // (dP/dt × dP/dv = -normal), so (a, c, b) and (a, d, c) are counter-clockwise from outside.
  m.indices.reserve(6 * vertices);
  for (int i = 0; i < mesh.u; ++i) {
    const std::uint32_t row = i * mesh.v, next = (i + 1) % mesh.u * mesh.v;
    for (int j = 0; j < mesh.v; ++j) {
      const std::uint32_t j1 = (j + 1) % mesh.v;
      const std::uint32_t a = row + j, b = next + j, c = next + j1, d = row + j1;
      for (const std::uint32_t k : {a, c, b, a, d, c}) m.indices.push_back(k);
    }
  }
  scene.meshes.push_back(std::move(m));
  return scene;
}

const std::vector<std::string>& names() {
  static const std::vector<std::string> kNames{
      "default", "random-small", "random-large", "slivers",  "star",   "fan",
      "knot",    "knot-100px",   "knot-30px",    "knot-65k", "knot-2m"};
  return kNames;
}

}  // namespace

std::vector<std::string> builtin_scene_names() { return names(); }

Scene builtin_scene(const std::string& name, int width, int height, std::uint64_t seed) {
  if (width < 1 || width > kMaxTargetSize || height < 1 || height > kMaxTargetSize) {
    throw Error(Errc::kInvalidTargetSize, "scene size " + std::to_string(width) + "x" +
                                              std::to_string(height) + " is outside 1..16384");
  }
  Scene scene;
  scene.name = name;
  scene.width = width;
  scene.height = height;
  Rng rng(seed);  // only the random scenes use it
  if (name == "default") return showcase(std::move(scene));
  if (name == "random-small") return random_small(std::move(scene), rng);
  if (name == "random-large") return random_large(std::move(scene), rng);
  if (name == "slivers") return slivers(std::move(scene), rng);
  if (name == "star") return star(std::move(scene));
  if (name == "fan") return fan(std::move(scene));
  if (name == "knot") return knot(std::move(scene), kKnot1M, 0);
  if (name == "knot-100px") return knot(std::move(scene), kKnot1M, 100);
  if (name == "knot-30px") return knot(std::move(scene), kKnot1M, 30);
  if (name == "knot-65k") return knot(std::move(scene), kKnot65k, 0, kKnotThirdFill);
  if (name == "knot-2m") return knot(std::move(scene), kKnot2M, 0);
  std::string known;
  for (const std::string& n : names()) known += (known.empty() ? "" : ", ") + n;
  throw Error(Errc::kInvalidArgument, "unknown scene '" + name + "' (known: " + known + ")");
}

}  // namespace mosaic
