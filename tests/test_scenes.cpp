// The built-in scenes (scenes/builtin.cpp): determinism, the counts, areas and lengths their
// documentation states (measured here from the positions), the fan's centre on a 4x sample,
// the star's tiling, the knot's closed mesh and projected sizes, and regression goldens of their
// reference renders.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <numbers>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "raster/sample_patterns.hpp"

namespace mosaic {
namespace {

/// Small sizes keep the reference renders fast; 16:9 like the default 1920x1080.
constexpr int kW = 320, kH = 180;

/// FNV-1a over every byte a Scene holds, eight bytes a step (the knot scenes hold 23 MB), to
/// compare two scenes for bit equality.
class ContentHash {
 public:
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      std::uint64_t word;
      std::memcpy(&word, b + i, 8);
      step(word);
    }
    for (; i < n; ++i) step(b[i]);
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof(v));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    value(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  std::uint64_t get() const { return h_; }

 private:
  void step(std::uint64_t v) {
    h_ ^= v;
    h_ *= 1099511628211ull;
  }

  std::uint64_t h_ = 14695981039346656037ull;
};

std::uint64_t content_hash(const Scene& s) {
  ContentHash h;
  h.value(s.width);
  h.value(s.height);
  h.value(s.clear_color);
  h.value(s.clear_depth);
  for (const Mesh& m : s.meshes) {
    h.value(m.space);
    h.vec(m.positions);
    h.vec(m.indices);
    h.value(m.color_source);
    h.value(m.color);
    h.vec(m.colors);
  }
  return h.get();
}

/// Vertex `k` of triangle `t` of a non-indexed mesh, in pixels (screen space).
glm::dvec2 xy(const Mesh& m, std::size_t t, int k) {
  const glm::vec4 p = m.positions[3 * t + k];
  return {p.x, p.y};
}

double cross(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
}

double area(const Mesh& m, std::size_t t) {
  return 0.5 * std::fabs(cross(xy(m, t, 0), xy(m, t, 1), xy(m, t, 2)));
}

/// The screen-space shape every random scene shares: one mesh, flat colours, w = 1, depth in
/// [0, 1], vertices on the 1/256 px grid.
void expect_flat_screen_mesh(const Scene& s, std::size_t triangles) {
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  EXPECT_EQ(m.space, Space::kScreen);
  EXPECT_EQ(m.color_source, ColorSource::kPerTriangle);
  EXPECT_TRUE(m.indices.empty());
  ASSERT_EQ(m.positions.size(), 3 * triangles);
  EXPECT_EQ(m.colors.size(), triangles);
  EXPECT_EQ(s.triangle_count(), triangles);
  for (const glm::vec4& p : m.positions) {
    ASSERT_EQ(p.w, 1.0f);
    ASSERT_GE(p.z, 0.0f);
    ASSERT_LE(p.z, 1.0f);
    ASSERT_EQ(p.x * 256.0f, std::round(p.x * 256.0f)) << p.x;
    ASSERT_EQ(p.y * 256.0f, std::round(p.y * 256.0f)) << p.y;
  }
}

TEST(BuiltinScenes, NamesAreTheDocumentedEleven) {
  const std::vector<std::string> expected{"default",   "random-small", "random-large", "slivers",
                                          "star",      "fan",          "knot",         "knot-100px",
                                          "knot-30px", "knot-65k",     "knot-2m"};
  EXPECT_EQ(builtin_scene_names(), expected);
}

TEST(BuiltinScenes, EveryScenePassesValidationAndKeepsItsSize) {
  for (const std::string& name : builtin_scene_names()) {
    const Scene s = builtin_scene(name, 200, 120, 3);
    EXPECT_EQ(s.name, name);
    EXPECT_EQ(s.width, 200);
    EXPECT_EQ(s.height, 120);
    EXPECT_GT(s.triangle_count(), 0u) << name;
    const std::vector<Draw> draws = s.draws();
    ASSERT_EQ(draws.size(), s.meshes.size());
    EXPECT_NO_THROW(validate(Frame{draws}, RenderTarget(s.width, s.height))) << name;
  }
}

TEST(BuiltinScenes, DeterministicForNameSizeAndSeed) {
  for (const std::string& name : builtin_scene_names()) {
    const Scene a = builtin_scene(name, 640, 360, 7);
    const Scene b = builtin_scene(name, 640, 360, 7);
    EXPECT_EQ(content_hash(a), content_hash(b)) << name;
    // The size changes every scene (the clip-space one through its aspect ratio).
    EXPECT_NE(content_hash(a), content_hash(builtin_scene(name, 600, 360, 7))) << name;
  }
}

TEST(BuiltinScenes, SeedChangesOnlyTheRandomScenes) {
  const std::set<std::string> random{"random-small", "random-large", "slivers"};
  for (const std::string& name : builtin_scene_names()) {
    const bool differs = content_hash(builtin_scene(name, 320, 180, 1)) !=
                         content_hash(builtin_scene(name, 320, 180, 2));
    EXPECT_EQ(differs, random.count(name) == 1) << name;
  }
}

TEST(BuiltinScenes, RandomSmallHasTheStatedCountAreasAndSpread) {
  const Scene s = builtin_scene("random-small", 1920, 1080, 1);
  expect_flat_screen_mesh(s, 100'000);
  const Mesh& m = s.meshes[0];
  std::array<int, 4> quadrant{};
  std::set<std::uint32_t> colors;
  for (std::size_t t = 0; t < 100'000; ++t) {
    const double a = area(m, t);
    ASSERT_GE(a, 10.0) << t;
    ASSERT_LE(a, 50.0) << t;
    const glm::dvec2 c = (xy(m, t, 0) + xy(m, t, 1) + xy(m, t, 2)) / 3.0;
    // Centres are uniform over the screen; a 50 px² triangle reaches a few px beyond its centre.
    ASSERT_GT(c.x, -16.0);
    ASSERT_LT(c.x, 1920 + 16.0);
    ASSERT_GT(c.y, -16.0);
    ASSERT_LT(c.y, 1080 + 16.0);
    ++quadrant[(c.x >= 960 ? 1 : 0) + (c.y >= 540 ? 2 : 0)];
    const Rgba8 col = m.colors[t];
    EXPECT_EQ(col.a, 255);
    colors.insert(std::uint32_t{col.r} << 16 | std::uint32_t{col.g} << 8 | col.b);
  }
  // Uniform positions: each quadrant gets a quarter, within 1 % of the total (25 standard
  // deviations of a binomial with n = 100000, p = 1/4, so only a real bias fails).
  for (const int q : quadrant) EXPECT_NEAR(q, 25'000, 1'000);
  // Random colours: almost all distinct (2^24 possible).
  EXPECT_GT(colors.size(), 99'000u);
}

TEST(BuiltinScenes, RandomLargeTrianglesCoverFiveToTwentyPercent) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1920, 1080}, {320, 180}, {50, 400}}) {
    const Scene s = builtin_scene("random-large", w, h, 5);
    expect_flat_screen_mesh(s, 1'000);
    double lo = 1, hi = 0;
    for (std::size_t t = 0; t < 1'000; ++t) {
      const double f = area(s.meshes[0], t) / (double(w) * h);
      lo = std::min(lo, f);
      hi = std::max(hi, f);
    }
    EXPECT_GE(lo, 0.05) << w << "x" << h;
    EXPECT_LE(hi, 0.20) << w << "x" << h;
    // The whole range is used, not a sliver of it.
    EXPECT_LT(lo, 0.06);
    EXPECT_GT(hi, 0.19);
  }
}

TEST(BuiltinScenes, SliversHaveTheStatedLengthsAndWidths) {
  const Scene s = builtin_scene("slivers", 1920, 1080, 1);
  expect_flat_screen_mesh(s, 10'000);
  const Mesh& m = s.meshes[0];
  double min_len = 1e9, max_len = 0, min_w = 1e9, max_w = 0;
  std::array<int, 4> direction{};  // orientation of the long edge, in 45° sectors mod 180°
  for (std::size_t t = 0; t < 10'000; ++t) {
    std::array<glm::dvec2, 3> v{xy(m, t, 0), xy(m, t, 1), xy(m, t, 2)};
    int longest = 0;
    double len = 0;
    for (int e = 0; e < 3; ++e) {
      const double l = glm::length(v[(e + 1) % 3] - v[e]);
      if (l > len) len = l, longest = e;
    }
    const double width = 2 * area(m, t) / len;
    min_len = std::min(min_len, len);
    max_len = std::max(max_len, len);
    min_w = std::min(min_w, width);
    max_w = std::max(max_w, width);
    const glm::dvec2 d = v[(longest + 1) % 3] - v[longest];
    double angle = std::atan2(d.y, d.x);
    if (angle < 0) angle += std::numbers::pi;
    ++direction[std::min(3, static_cast<int>(angle / (std::numbers::pi / 4)))];
  }
  EXPECT_GE(min_len, 100.0);
  EXPECT_LE(max_len, 800.0);
  EXPECT_GE(min_w, 0.5);
  EXPECT_LE(max_w, 3.0);
  EXPECT_LT(min_len, 105.0);
  EXPECT_GT(max_len, 795.0);
  EXPECT_LT(min_w, 0.55);
  EXPECT_GT(max_w, 2.95);
  // Random orientation: every 45° sector holds about a quarter.
  for (const int d : direction) EXPECT_NEAR(d, 2'500, 300);
}

TEST(BuiltinScenes, StarIsAnAlternatingTilingOfTheDisc) {
  const Scene s = builtin_scene("star", kW, kH, 1);
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  EXPECT_EQ(m.space, Space::kScreen);
  EXPECT_EQ(m.color_source, ColorSource::kPerTriangle);
  const std::size_t n = s.triangle_count();
  ASSERT_GE(n, 36u);
  ASSERT_EQ(n % 2, 0u);
  const glm::dvec2 centre = xy(m, 0, 0);
  EXPECT_NEAR(centre.x, kW / 2.0, 1.0 / 256);
  EXPECT_NEAR(centre.y, kH / 2.0, 1.0 / 256);
  double sum = 0, shoelace = 0;
  const double sign = cross(xy(m, 0, 0), xy(m, 0, 1), xy(m, 0, 2)) > 0 ? 1 : -1;
  for (std::size_t t = 0; t < n; ++t) {
    // Every wedge starts at the centre where the previous one ended: no gap, no overlap...
    EXPECT_EQ(xy(m, t, 0), centre);
    EXPECT_EQ(xy(m, t, 1), xy(m, (t + n - 1) % n, 2));
    // ...and turns the same way.
    EXPECT_GT(sign * cross(xy(m, t, 0), xy(m, t, 1), xy(m, t, 2)), 0) << t;
    sum += area(m, t);
    const glm::dvec2 a = xy(m, t, 1), b = xy(m, t, 2);
    shoelace += a.x * b.y - b.x * a.y;
    // Alternating black and white, depth constant.
    const Rgba8 expected = t % 2 == 0 ? Rgba8{255, 255, 255, 255} : Rgba8{0, 0, 0, 255};
    EXPECT_EQ(m.colors[t], expected) << t;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.positions[3 * t + k].z, m.positions[0].z);
  }
  // The wedges' areas add up to the rim polygon's area, so they wind around the centre exactly
  // once: a second turn, or wedges folding back over each other, would add more.
  EXPECT_NEAR(sum, std::fabs(shoelace) / 2, 1e-6 * sum);
  // The disc is large: radius at least 40 % of the shorter side.
  EXPECT_GT(glm::length(xy(m, 0, 1) - centre), 0.4 * kH);
}

TEST(BuiltinScenes, FanCentreIsExactlyOnA4xSamplePosition) {
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{kW, kH}, {64, 48}, {1, 1}, {1920, 1080}}) {
    const Scene s = builtin_scene("fan", w, h, 1);
    ASSERT_EQ(s.meshes.size(), 1u);
    const Mesh& m = s.meshes[0];
    EXPECT_EQ(m.space, Space::kScreen);
    EXPECT_EQ(m.color_source, ColorSource::kPerTriangle);
    ASSERT_GE(s.triangle_count(), 8u);
    const glm::dvec2 c = xy(m, 0, 0);
    for (std::size_t t = 0; t < s.triangle_count(); ++t) EXPECT_EQ(xy(m, t, 0), c);
    // c in 16.8 units must be sample_x_fixed(px, o), sample_y_fixed(py, o) for one sample o of
    // the 4x pattern and some pixel (px, py) (exact: c is on the 1/256 grid).
    const auto cx = static_cast<std::int64_t>(c.x * 256), cy = static_cast<std::int64_t>(c.y * 256);
    ASSERT_EQ(double(cx), c.x * 256);
    ASSERT_EQ(double(cy), c.y * 256);
    int matches = 0;
    for (const raster::SampleOffset o : raster::kPattern4) {
      const std::int64_t px = (cx - raster::sample_x_fixed(0, o)) / 256;
      const std::int64_t py = (cy - raster::sample_y_fixed(0, o)) / 256;
      if (raster::sample_x_fixed(int(px), o) == cx && raster::sample_y_fixed(int(py), o) == cy) {
        ++matches;
        EXPECT_GE(px, 0);
        EXPECT_LT(px, w);
        EXPECT_GE(py, 0);
        EXPECT_LT(py, h);
      }
    }
    EXPECT_EQ(matches, 1) << w << "x" << h;
  }
}

TEST(BuiltinScenes, FanCentreSampleIsCoveredByExactlyOneTriangle) {
  // The fan exists for this tie: every triangle has a vertex on the sample, and the fill rule
  // must hand it to exactly one of them, under either rule.
  const int w = 64, h = 48;
  const Scene s = builtin_scene("fan", w, h, 1);
  const Mesh& m = s.meshes[0];
  const glm::dvec2 c = xy(m, 0, 0);
  const int px = static_cast<int>(std::floor(c.x)), py = static_cast<int>(std::floor(c.y));
  int sample = -1;
  for (int k = 0; k < 4; ++k)
    if (raster::sample_x_px(px, raster::kPattern4[k]) == c.x &&
        raster::sample_y_px(py, raster::kPattern4[k]) == c.y)
      sample = k;
  ASSERT_GE(sample, 0);
  Renderer renderer({1, Isa::kReference});
  for (const FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
    int covering = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
      Mesh one = m;
      one.positions.assign(m.positions.begin() + 3 * t, m.positions.begin() + 3 * t + 3);
      one.colors.assign(1, Rgba8{255, 255, 255, 255});
      one.state.fill_rule = rule;
      const std::vector<Draw> draws{one.draw()};
      RenderTarget target(w, h, 4, {.keep_sample_depth = false, .keep_sample_color = true});
      target.set_clear({0, 0, 0, 255});
      renderer.render(Frame{draws}, target);
      const Rgba8 got = target.sample_color()[(static_cast<std::size_t>(py) * w + px) * 4 + sample];
      if (got.r == 255) ++covering;
    }
    EXPECT_EQ(covering, 1) << (rule == FillRule::kD3D ? "D3D" : "OpenGL");
  }
}

TEST(BuiltinScenes, DefaultIsAPerspectiveClipSpaceScene) {
  const Scene s = builtin_scene("default", kW, kH, 1);
  ASSERT_GE(s.meshes.size(), 3u);
  bool per_vertex = false;
  std::size_t in_front = 0, total = 0;
  std::set<float> ws;
  for (const Mesh& m : s.meshes) {
    EXPECT_EQ(m.space, Space::kClip);
    per_vertex = per_vertex || m.color_source == ColorSource::kPerVertex;
    for (const glm::vec4& p : m.positions) {
      ++total;
      ws.insert(p.w);
      // Depth z/w in [0, 1] for vertices in the view volume.
      if (p.w > 0 && std::fabs(p.x) <= p.w && std::fabs(p.y) <= p.w) {
        ++in_front;
        EXPECT_GE(p.z / p.w, 0.0f);
        EXPECT_LE(p.z / p.w, 1.0f);
      }
    }
  }
  EXPECT_TRUE(per_vertex);
  EXPECT_GT(in_front, total / 4);  // most of the scene is in view
  EXPECT_GT(ws.size(), 10u);       // a perspective projection: w varies with distance

  // Rendered, the z-buffer has work to do: some samples fail the depth test (objects overlap)
  // and nearly every triangle survives setup.
  Renderer renderer({1, Isa::kReference});
  RenderTarget target(kW, kH, 1);
  target.set_clear(s.clear_color, s.clear_depth);
  const std::vector<Draw> draws = s.draws();
  const FrameStats st = renderer.render(Frame{draws}, target);
  EXPECT_GT(st.triangles_drawn, s.triangle_count() / 2);
  EXPECT_GT(st.samples_tested, st.samples_written);
  // Many colours: interpolated vertex colours, not a few flat ones.
  std::set<std::uint32_t> colors;
  for (const Rgba8 c : target.color()) colors.insert(std::uint32_t{c.r} << 16 | c.g << 8 | c.b);
  EXPECT_GT(colors.size(), 500u);
}

TEST(BuiltinScenes, UnknownNameAndBadSizeAreRejected) {
  try {
    builtin_scene("nope");
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), Errc::kInvalidArgument);
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unknown scene 'nope'"), std::string::npos) << msg;
    for (const std::string& n : builtin_scene_names())
      EXPECT_NE(msg.find(n), std::string::npos) << msg;
  }
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{0, 10}, {10, 0}, {16385, 10}, {-1, -1}}) {
    try {
      builtin_scene("star", w, h);
      FAIL() << "no exception for " << w << "x" << h;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kInvalidTargetSize);
    }
  }
}

// Regression goldens: FNV-1a image hashes (RenderTarget::image_hash) of every built-in scene but
// the knots (KnotRender below has theirs) rendered at 320x180 by the reference rasterizer
// (Isa::kReference). They were produced once by this test at commit e55f9b2 (the reference of
// the skeleton, 020eb17) and are not derived independently: a change here means the scene
// generator or the reference changed, which must be deliberate.
struct Golden {
  const char* scene;
  int samples;
  std::uint64_t hash;
};
constexpr Golden kGoldens[] = {
    {"default", 1, 0x0c56378269214648ull},      {"default", 4, 0x26ad8c6c9233f489ull},
    {"random-small", 1, 0x6f144d57f159056bull}, {"random-small", 4, 0x8184cec063d8bcb7ull},
    {"random-large", 1, 0x33ab70d21bb43789ull}, {"random-large", 4, 0x46978fe304f4b658ull},
    {"slivers", 1, 0xe0d28ddb8d4a8d89ull},      {"slivers", 4, 0x493601c6f8006eb9ull},
    {"star", 1, 0x2427578ba7937ae6ull},         {"star", 4, 0x4d5401d4b77a0f8eull},
    {"fan", 1, 0x7ca6d72cef1a27cbull},          {"fan", 4, 0x5943ba3ccb1ce2f6ull},
};

TEST(BuiltinScenes, ReferenceRendersMatchGoldens) {
  Renderer renderer({1, Isa::kReference});
  for (const Golden& g : kGoldens) {
    const Scene s = builtin_scene(g.scene, kW, kH, 1);
    RenderTarget target(kW, kH, g.samples);
    target.set_clear(s.clear_color, s.clear_depth);
    const std::vector<Draw> draws = s.draws();
    renderer.render(Frame{draws}, target);
    EXPECT_EQ(target.image_hash(), g.hash)
        << g.scene << " x" << g.samples << ": 0x" << std::hex << target.image_hash();
  }
}

// ---- the knot scenes: one closed mesh of 1 M triangles at three sizes, 65k and 2 M ----

/// The knot's documented parameters (scenes/builtin.cpp): a (2, 3) torus knot, tube radius 0.4.
constexpr int kKnotTriangles = 1'048'576, kKnotVertices = 524'288;
constexpr double kKnotTube = 0.4;

/// Screen-space box of a clip-space mesh's vertices (all in front of the camera), in pixels.
struct Box {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
};

Box projected_box(const Scene& s) {
  Box b;
  for (const glm::vec4& p : s.meshes.at(0).positions) {
    const double x = (double(p.x) / p.w + 1) * 0.5 * s.width;
    const double y = (1 - double(p.y) / p.w) * 0.5 * s.height;
    b.x0 = std::min(b.x0, x);
    b.x1 = std::max(b.x1, x);
    b.y0 = std::min(b.y0, y);
    b.y1 = std::max(b.y1, y);
  }
  return b;
}

/// An indexed torus grid: `vertices` shared vertices, each used by six triangles (a regular
/// quad grid cut into triangles, two triangles per vertex as on a closed surface of genus 1); with
/// `edges`, also closed and consistently wound (each directed edge once, and its reverse once).
void expect_closed_grid(const Mesh& m, std::size_t vertices, bool edges_too) {
  const std::size_t triangles = m.triangle_count();
  ASSERT_EQ(triangles, 2 * vertices);
  ASSERT_EQ(m.positions.size(), vertices);
  ASSERT_EQ(m.colors.size(), m.positions.size());
  ASSERT_EQ(m.normals.size(), m.positions.size());
  ASSERT_EQ(m.indices.size(), 3 * triangles);
  std::vector<std::uint32_t> uses(m.positions.size());
  for (const std::uint32_t i : m.indices) {
    ASSERT_LT(i, m.positions.size());
    ++uses[i];
  }
  EXPECT_EQ(*std::min_element(uses.begin(), uses.end()), 6u);
  EXPECT_EQ(*std::max_element(uses.begin(), uses.end()), 6u);
  if (!edges_too) return;
  // Then every undirected edge has exactly two triangles, which traverse it in opposite
  // directions.
  std::vector<std::uint64_t> edges;
  edges.reserve(m.indices.size());
  for (std::size_t t = 0; t < triangles; ++t) {
    const std::uint32_t* v = &m.indices[3 * t];
    ASSERT_TRUE(v[0] != v[1] && v[1] != v[2] && v[2] != v[0]) << t;
    for (int k = 0; k < 3; ++k) edges.push_back(std::uint64_t{v[k]} << 32 | v[(k + 1) % 3]);
  }
  std::sort(edges.begin(), edges.end());
  EXPECT_EQ(std::adjacent_find(edges.begin(), edges.end()), edges.end()) << "a repeated edge";
  std::size_t unmatched = 0;
  for (const std::uint64_t e : edges)
    if (!std::binary_search(edges.begin(), edges.end(), (e << 32) | (e >> 32))) ++unmatched;
  EXPECT_EQ(unmatched, 0u) << "edges with one triangle only (a hole)";
}

TEST(KnotScenes, OneIndexedClosedConsistentlyWoundMeshOfAMillionTriangles) {
  const Scene s = builtin_scene("knot", 1920, 1080, 1);
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  EXPECT_EQ(m.space, Space::kClip);
  EXPECT_EQ(m.color_source, ColorSource::kPerVertex);
  ASSERT_EQ(s.triangle_count(), std::size_t{kKnotTriangles});
  ASSERT_GE(s.triangle_count(), 1'000'000u);
  expect_closed_grid(m, kKnotVertices, true);

  // In front of the camera, depth in [0, 1], and a perspective projection (w varies).
  float w_min = 1e30f, w_max = 0;
  for (const glm::vec4& p : m.positions) {
    ASSERT_GT(p.w, 0.0f);
    ASSERT_GE(p.z / p.w, 0.0f);
    ASSERT_LE(p.z / p.w, 1.0f);
    w_min = std::min(w_min, p.w);
    w_max = std::max(w_max, p.w);
  }
  EXPECT_GT(w_max, 1.5f * w_min);
  // Lit: opaque, many shades (a Lambert term baked per vertex), dark and bright ones.
  std::set<std::uint32_t> colors;
  int darkest = 255, brightest = 0;
  for (const Rgba8 c : m.colors) {
    ASSERT_EQ(c.a, 255);
    colors.insert(std::uint32_t{c.r} << 16 | c.g << 8 | c.b);
    darkest = std::min<int>(darkest, c.r);
    brightest = std::max<int>(brightest, c.r);
  }
  EXPECT_GT(colors.size(), 150u);
  EXPECT_LT(darkest, 50);
  EXPECT_GT(brightest, 200);
}

TEST(KnotScenes, TheSmallAndTheLargeKnotAreClosedGridsOfTheirCounts) {
  // knot-65k: 512 x 64 segments; knot-2m: 4096 x 256 (its edges are not sorted: the 1 M knot's
  // are, and the generator is the same).
  const Scene small = builtin_scene("knot-65k", kW, kH, 1);
  ASSERT_EQ(small.meshes.size(), 1u);
  EXPECT_EQ(small.triangle_count(), 65'536u);
  expect_closed_grid(small.meshes[0], 32'768, true);
  const Scene large = builtin_scene("knot-2m", kW, kH, 1);
  ASSERT_EQ(large.meshes.size(), 1u);
  EXPECT_EQ(large.triangle_count(), 2'097'152u);
  expect_closed_grid(large.meshes[0], 1'048'576, false);
}

TEST(KnotScenes, OutwardFacingTubeOfTheStatedRadius) {
  // World space back through the scene's camera: the signed volume (divergence theorem) is
  // positive only if the triangles turn counter-clockwise seen from outside, and equals the
  // tube's volume, pi r² times the curve's length (Pappus).
  const Scene s = builtin_scene("knot", 1920, 1080, 1);
  const Mesh& m = s.meshes.at(0);
  const glm::dmat4 to_world = glm::inverse(glm::dmat4(s.camera.view_projection));
  std::vector<glm::dvec3> world;
  world.reserve(m.positions.size());
  for (const glm::vec4& p : m.positions) {
    const glm::dvec4 q = to_world * glm::dvec4(p);
    world.emplace_back(glm::dvec3(q) / q.w);
  }
  double volume = 0;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const glm::dvec3 a = world[m.indices[3 * t]], b = world[m.indices[3 * t + 1]],
                     c = world[m.indices[3 * t + 2]];
    volume += glm::dot(a, glm::cross(b, c)) / 6;
  }
  double length = 0;
  constexpr int kSteps = 100'000;
  auto curve = [](double t) {
    const double r = 2 + std::cos(3 * t);
    return glm::dvec3(r * std::cos(2 * t), std::sin(3 * t), r * std::sin(2 * t));
  };
  for (int i = 0; i < kSteps; ++i)
    length += glm::length(curve(2 * std::numbers::pi * (i + 1) / kSteps) -
                          curve(2 * std::numbers::pi * i / kSteps));
  const double tube = std::numbers::pi * kKnotTube * kKnotTube * length;
  EXPECT_GT(volume, 0) << "the triangles face inwards";
  EXPECT_NEAR(volume, tube, 0.002 * tube);
}

TEST(KnotScenes, TrianglesFacingTheCameraAreCounterClockwiseOnScreen) {
  // FrontFace::kCounterClockwise, mosaic's default front face, is counter-clockwise on screen:
  // a negative area in y-down pixels (front/setup.cpp). Facing is decided in world space, from
  // the camera's position and each triangle's normal, on triangles not nearly edge-on.
  for (const char* name : {"knot", "knot-100px", "knot-30px", "knot-65k"}) {
    const Scene s = builtin_scene(name, kW, kH, 1);
    const Mesh& m = s.meshes.at(0);
    const glm::dmat4 to_world = glm::inverse(glm::dmat4(s.camera.view_projection));
    const glm::dvec4 e = to_world * glm::dvec4(0, 0, 1, 0);  // the eye: w = 0 in clip space
    const glm::dvec3 eye = glm::dvec3(e) / e.w;
    std::size_t facing = 0, decided = 0, wrong = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
      std::array<glm::dvec3, 3> world;
      std::array<glm::dvec2, 3> screen;
      for (int k = 0; k < 3; ++k) {
        const glm::vec4 p = m.positions[m.indices[3 * t + k]];
        const glm::dvec4 q = to_world * glm::dvec4(p);
        world[k] = glm::dvec3(q) / q.w;
        screen[k] = {(double(p.x) / p.w + 1) * 0.5 * s.width,
                     (1 - double(p.y) / p.w) * 0.5 * s.height};
      }
      const glm::dvec3 n = glm::normalize(glm::cross(world[1] - world[0], world[2] - world[0]));
      const double towards = glm::dot(n, glm::normalize(eye - world[0]));
      if (std::fabs(towards) < 0.05) continue;
      ++decided;
      facing += towards > 0;
      const bool ccw_on_screen = cross(screen[0], screen[1], screen[2]) < 0;
      wrong += ccw_on_screen != (towards > 0);
    }
    EXPECT_GT(decided, m.triangle_count() * 4 / 5) << name;
    EXPECT_EQ(wrong, 0u) << name;
    EXPECT_GT(facing, decided * 2 / 5) << name;
    EXPECT_LT(facing, decided * 3 / 5) << name;
  }
}

TEST(KnotScenes, OneMeshMovedToThreeSizes) {
  const Scene full = builtin_scene("knot", kW, kH, 1);
  for (const char* name : {"knot-100px", "knot-30px"}) {
    const Scene s = builtin_scene(name, kW, kH, 1);
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].indices, full.meshes[0].indices) << name;
    EXPECT_EQ(s.meshes[0].colors, full.meshes[0].colors) << name;
    EXPECT_NE(s.meshes[0].positions, full.meshes[0].positions) << name;
  }
}

TEST(KnotScenes, ProjectionsHaveTheStatedSizeAndAreCentred) {
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{1920, 1080}, {640, 480}, {333, 201}, {3840, 2160}}) {
    struct Size {
      const char* name;
      double width;  ///< px, or 0: the scene fills `fill` of the side that binds first
      double fill;
    };
    for (const auto& [name, width, fill] : std::vector<Size>{{"knot-100px", 100.0, 0.0},
                                                             {"knot-30px", 30.0, 0.0},
                                                             {"knot", 0.0, 0.9},
                                                             {"knot-65k", 0.0, 0.72}}) {
      SCOPED_TRACE(std::string(name) + " at " + std::to_string(w) + "x" + std::to_string(h));
      const Scene s = builtin_scene(name, w, h, 1);
      const Box b = projected_box(s);
      EXPECT_NEAR(0.5 * (b.x0 + b.x1), w / 2.0, 0.01);
      EXPECT_NEAR(0.5 * (b.y0 + b.y1), h / 2.0, 0.01);
      if (width > 0) {
        // The same width on every target size: exact by construction, up to float rounding.
        EXPECT_NEAR(b.width(), width, 0.002 * width);
        EXPECT_GT(b.height(), 0.5 * width);
        EXPECT_LT(b.height(), 1.5 * width);
      } else {
        // It fills `fill` of the side that binds first, and fits the other.
        EXPECT_NEAR(std::max(b.width() / w, b.height() / h), fill, 1e-3);
        EXPECT_LE(b.width(), (fill + 1e-4) * w);
        EXPECT_LE(b.height(), (fill + 1e-4) * h);
      }
    }
  }
}

/// Goldens of the knot scenes' bits (content_hash at 320x180, seed 1; made by this test at the
/// commit that added them): generation uses only IEEE +, *, / and sqrt, so no platform differs.
TEST(KnotScenes, SceneBitsMatchGoldens) {
  const std::pair<const char*, std::uint64_t> kHashes[] = {{"knot", 0x54e83cc5198b14eeull},
                                                           {"knot-100px", 0x73de2669d9c9361eull},
                                                           {"knot-30px", 0xf72d5d702edb879cull},
                                                           {"knot-65k", 0xc51bc5cefe70a585ull},
                                                           {"knot-2m", 0x1607ffabec822fa2ull}};
  for (const auto& [name, hash] : kHashes) {
    const std::uint64_t got = content_hash(builtin_scene(name, kW, kH, 1));
    EXPECT_EQ(got, hash) << name << ": 0x" << std::hex << got;
  }
}

/// One reference render per knot scene (1 M triangles cost the scalar reference about a second,
/// so each scene is its own test and runs beside the others): its golden, and the fast path bit
/// for bit. Small targets: the knot-100px and knot-30px keep their width.
struct KnotRenderCase {
  const char* scene;
  int width, height, samples;
  std::uint64_t golden;
  bool cull_back;  ///< also check that culling back faces keeps the image
  /// The near side fills whole blocks in front of the far side (not at 30 px, 4x: a block's
  /// worth of samples is never written there before the far side is drawn).
  bool hides_blocks;
};

void PrintTo(const KnotRenderCase& c, std::ostream* os) {
  *os << c.scene << " " << c.width << "x" << c.height << " " << c.samples << "x";
}

class KnotRender : public ::testing::TestWithParam<KnotRenderCase> {};

TEST_P(KnotRender, ReferenceMatchesGoldenAndTheFastPath) {
  const KnotRenderCase& c = GetParam();
  Scene s = builtin_scene(c.scene, c.width, c.height, 1);
  auto render = [&](Renderer& renderer, FrameStats* stats) {
    RenderTarget target(c.width, c.height, c.samples,
                        {.keep_sample_depth = true, .keep_sample_color = true});
    target.set_clear(s.clear_color, s.clear_depth);
    const std::vector<Draw> draws = s.draws();
    *stats = renderer.render(Frame{draws}, target);
    return target;
  };
  Renderer reference({1, Isa::kReference});
  FrameStats ref_stats{};
  const RenderTarget ref = render(reference, &ref_stats);
  EXPECT_EQ(ref.image_hash(), c.golden) << c.scene << ": 0x" << std::hex << ref.image_hash();
  EXPECT_GT(ref_stats.samples_written, 0u);

  // The best SIMD path on 2 threads: 512 chunks merged in order. Only one: under ASan a fast
  // frame of 1 M triangles takes 3-6 s, and every path is compared on other scenes.
  Renderer fast_path({2, Isa::kAuto});
  FrameStats st{};
  const RenderTarget fast = render(fast_path, &st);
  EXPECT_EQ(st.samples_written, ref_stats.samples_written);
  EXPECT_EQ(st.triangles_drawn, ref_stats.triangles_drawn);
  EXPECT_EQ(fast.image_hash(), ref.image_hash());
  EXPECT_TRUE(std::equal(fast.sample_depth().begin(), fast.sample_depth().end(),
                         ref.sample_depth().begin(), ref.sample_depth().end(),
                         [](float a, float b) { return std::memcmp(&a, &b, 4) == 0; }));
  EXPECT_TRUE(std::ranges::equal(fast.sample_color(), ref.sample_color()));
  // Drawn with cull none, the mesh's far side lies behind its near side: hierarchical z,
  // tightened from the near side's small triangles, rejects blocks of it.
  if (c.hides_blocks) {
    EXPECT_GT(st.blocks_hiz_rejected, 0u) << c.scene;
  }
  if (!c.cull_back) return;

  // The hidden faces of a closed mesh are its back faces: culling them changes no pixel beyond
  // depth ties on silhouette folds (none at this size), and culls about half the triangles.
  s.for_each_state([](DrawState& state) { state.cull = CullMode::kBack; });
  FrameStats back{};
  const RenderTarget culled = render(fast_path, &back);
  std::size_t covered = 0, differs = 0;
  for (std::size_t i = 0; i < ref.color().size(); ++i) {
    if (ref.color()[i] == s.clear_color) continue;
    ++covered;
    differs += culled.color()[i] != ref.color()[i];
  }
  ASSERT_GT(covered, ref.color().size() / 5);
  EXPECT_LE(differs, covered / 200) << differs << " of " << covered;
  const std::uint64_t n = s.triangle_count();
  EXPECT_EQ(ref_stats.triangles_culled_face, 0u);
  EXPECT_GT(back.triangles_culled_face, n * 2 / 5);
  EXPECT_LT(back.triangles_culled_face, n * 3 / 5);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, KnotRender,
    ::testing::Values(KnotRenderCase{"knot", kW, kH, 4, 0x19757d5d504d7117ull, true, true},
                      KnotRenderCase{"knot-100px", 157, 131, 1, 0x0be8ef59f6c9b3cbull, false, true},
                      KnotRenderCase{"knot-30px", 64, 48, 4, 0x96ea470f8cad7dcbull, false, false},
                      KnotRenderCase{"knot-65k", kW, kH, 4, 0xd613d51bfea7a913ull, false, true}),
    [](const ::testing::TestParamInfo<KnotRenderCase>& param) {
      std::string n = param.param.scene;
      std::replace(n.begin(), n.end(), '-', '_');
      return n;
    });

}  // namespace
}  // namespace mosaic
