// The SIMD front end (front/setup_simd.hpp, one per ISA through simd::front_end) against the
// scalar one (front::run_front_end), the oracle: the same TriangleSetups field by field and bit
// for bit, the same out-of-line planes (colour and varyings), the same counters, on every ISA
// this CPU runs.
//
// The inputs cover what the lanes do (random screen-space triangles of every size, both windings,
// each cull mode, front face and fill rule, flat and per-vertex colours, signed zeros) and what
// they must hand to the scalar code in order (triangles crossing the near and far planes and the
// guard band, non-finite vertices, W = 0), in chunk ranges whose length is no multiple of the
// lane count.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <vector>

#include "front/front_end.hpp"
#include "isa_dispatch.hpp"

namespace mosaic {
namespace {

constexpr int kWidth = 320, kHeight = 200;  // small: many triangles reach past the edges
constexpr double kInf = std::numeric_limits<double>::infinity();

// Floats compare by their bits: NaN planes (kept in a set-up triangle that fell back to flat)
// must match too, and so must the sign of a zero.
void expect_bits(float a, float b, const char* what, std::size_t i) {
  EXPECT_EQ(std::bit_cast<std::uint32_t>(a), std::bit_cast<std::uint32_t>(b))
      << what << " of triangle " << i << ": " << a << " vs " << b;
}

void expect_plane(const front::Plane& a, const front::Plane& b, const char* what, std::size_t i) {
  expect_bits(a.base, b.base, what, i);
  expect_bits(a.ddx, b.ddx, what, i);
  expect_bits(a.ddy, b.ddy, what, i);
}

// Field by field: the struct has padding, so memcmp of the whole would compare garbage.
void expect_same_setup(const front::TriangleSetup& a, const front::TriangleSetup& b,
                       std::size_t i) {
  for (int e = 0; e < 3; ++e) {
    EXPECT_EQ(a.edge[e].a, b.edge[e].a) << "edge " << e << " of triangle " << i;
    EXPECT_EQ(a.edge[e].b, b.edge[e].b) << "edge " << e << " of triangle " << i;
    EXPECT_EQ(a.edge[e].c, b.edge[e].c) << "edge " << e << " of triangle " << i;
  }
  expect_bits(a.x0, b.x0, "x0", i);
  expect_bits(a.y0, b.y0, "y0", i);
  EXPECT_EQ(a.bx0, b.bx0) << i;
  EXPECT_EQ(a.by0, b.by0) << i;
  EXPECT_EQ(a.bx1, b.bx1) << i;
  EXPECT_EQ(a.by1, b.by1) << i;
  expect_plane(a.z, b.z, "z", i);
  expect_bits(a.z_min, b.z_min, "z_min", i);
  expect_bits(a.z_max, b.z_max, "z_max", i);
  EXPECT_EQ(a.color, b.color) << i;
  EXPECT_EQ(a.draw_word, b.draw_word) << i;  // the draw and the facing
  // The planes themselves (q and colour·q, or q and the varyings) are compared in the arrays.
  EXPECT_EQ(a.planes_base, b.planes_base) << i;
}

struct Output {
  std::vector<front::TriangleSetup> tris;
  front::PlaneArray planes;
  front::FrontStats stats;
};

// Runs `fe` on [begin, end) after a prefix already in the outputs (a chunk's vectors are reused,
// and planes_base counts from what is there).
Output run(front::FrontEnd fe, const Draw& d, std::uint32_t begin, std::uint32_t end,
           bool with_planes, int samples, const front::VertexCache* cache = nullptr) {
  Output o;
  o.planes.resize(3, front::Plane{});
  fe(d, 7, begin, end, kWidth, kHeight, o.tris, o.stats, with_planes ? &o.planes : nullptr, samples,
     cache);
  return o;
}

// The vertex stage of `isa` over all of d's vertices into `records`, in blocks of `block` (the
// last one short), as the frame runs it.
front::VertexCache vertex_cache(Isa isa, const Draw& d, std::uint32_t block,
                                front::VertexRecords& records) {
  const auto n = static_cast<std::uint32_t>(front::vertex_count(d));
  records.reserve(n);
  const front::VertexCache cache{records.data(), n};
  std::fill(cache.data, cache.data + n, front::ProjectedVertex{-1, -1, -1, 0xff, -1, ~0u, 0});
  const front::VertexStage stage = dispatch::vertex_stage(isa);
  EXPECT_NE(stage, nullptr);
  for (std::uint32_t v = 0; v < n; v += block)
    stage(d, kWidth, kHeight, v, std::min(n, v + block), cache);
  return cache;
}

// Compares every runnable ISA's front end with the scalar one on `d`, over the whole draw and over
// ranges that start and end off the lane grid; `whole` gets the scalar counters of the whole draw.
void expect_same_into(const Draw& d, front::FrontStats& whole) {
  const std::uint32_t n = front::triangle_count(d);
  ASSERT_GE(n, 13u) << "the ranges below need 13 triangles";
  const std::vector<std::pair<std::uint32_t, std::uint32_t>> ranges{
      {0, n}, {1, n}, {0, n - 1}, {3, n - 2}, {5, 6}, {9, 9}, {2, 13}};
  for (Isa isa : dispatch::runnable_isas()) {
    SCOPED_TRACE(to_string(isa));
    const front::FrontEnd fe = dispatch::front_end(isa);
    ASSERT_NE(fe, nullptr);
    // Every draw is also set up from the vertex stage's cache (an unindexed draw's vertex of a
    // corner is 3t + k), projected in blocks that end off the lane grid.
    front::VertexRecords records;
    const front::VertexCache cache = vertex_cache(isa, d, 13, records);
    for (const auto& [b, e] : ranges) {
      // Sample count 0 culls no box; 1, 4 and 16 cull those that hold none of their positions.
      for (const auto& [with_planes, samples] :
           {std::pair{true, 0}, std::pair{false, 0}, std::pair{true, 1}, std::pair{true, 4},
            std::pair{false, 16}}) {
        SCOPED_TRACE(testing::Message() << "range [" << b << ", " << e << ") planes " << with_planes
                                        << " samples " << samples);
        const Output want = run(&front::run_front_end, d, b, e, with_planes, samples);
        for (const front::VertexCache* c :
             {static_cast<const front::VertexCache*>(nullptr), &cache}) {
          SCOPED_TRACE(c ? "from the vertex stage" : "from the draw");
          const Output got = run(fe, d, b, e, with_planes, samples, c);
          EXPECT_EQ(got.stats.in, want.stats.in);
          EXPECT_EQ(got.stats.nonfinite, want.stats.nonfinite);
          EXPECT_EQ(got.stats.culled_face, want.stats.culled_face);
          EXPECT_EQ(got.stats.degenerate, want.stats.degenerate);
          EXPECT_EQ(got.stats.outside, want.stats.outside);
          EXPECT_EQ(got.stats.clipped, want.stats.clipped);
          EXPECT_EQ(got.stats.drawn, want.stats.drawn);
          EXPECT_EQ(got.stats.no_sample, want.stats.no_sample);
          ASSERT_EQ(got.tris.size(), want.tris.size());
          for (std::size_t i = 0; i < want.tris.size(); ++i)
            expect_same_setup(got.tris[i], want.tris[i], i);
          ASSERT_EQ(got.planes.size(), want.planes.size());
          for (std::size_t i = 0; i < want.planes.size(); ++i)
            expect_plane(got.planes[i], want.planes[i], "out-of-line plane", i);
        }
        if (b == 0 && e == n && samples == 0) whole = want.stats;
      }
    }
  }
}

front::FrontStats expect_same(const Draw& d) {
  front::FrontStats whole;
  expect_same_into(d, whole);
  return whole;
}

// A screen-space scene: triangles of sizes from a hundredth of a pixel to thousands, centred in
// and around the target, with depths including signed zeros and float subnormals.
struct ScreenScene {
  std::vector<glm::vec4> positions;
  std::vector<Rgba8> tri_colors, vertex_colors;

  ScreenScene(int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float sizes[] = {0.01f, 0.3f, 1.0f, 4.0f, 20.0f, 150.0f, 3000.0f, 70000.0f};
    const float depths[] = {0.0f, -0.0f, 1e-40f, 1.0f, 0.25f};
    for (int t = 0; t < count; ++t) {
      const float size = sizes[rng() % std::size(sizes)];
      const float cx = -40.0f + u(rng) * (kWidth + 80.0f), cy = -40.0f + u(rng) * (kHeight + 80.0f);
      for (int k = 0; k < 3; ++k) {
        const float z = rng() % 4 == 0 ? depths[rng() % std::size(depths)] : u(rng);
        positions.emplace_back(cx + (u(rng) - 0.5f) * size, cy + (u(rng) - 0.5f) * size, z, 1.0f);
        // Three of four triangles get one colour at all corners (the flat shortcut).
        const auto c = static_cast<std::uint8_t>(t % 4 == 0 ? rng() : t);
        vertex_colors.push_back({c, static_cast<std::uint8_t>(c + k * (t % 4 == 0)), 9, 255});
      }
      tri_colors.push_back(
          {static_cast<std::uint8_t>(t), static_cast<std::uint8_t>(rng()), 3, 200});
    }
  }

  Draw draw(ColorSource source) const {
    Draw d;
    d.space = Space::kScreen;
    d.positions = positions;
    d.color_source = source;
    d.color = {1, 2, 3, 4};
    if (source == ColorSource::kPerTriangle) d.colors = tri_colors;
    if (source == ColorSource::kPerVertex) d.colors = vertex_colors;
    return d;
  }
};

TEST(FrontSimd, ScreenSpaceEveryStateAndColourSource) {
  const ScreenScene scene(601, 1);
  for (ColorSource source :
       {ColorSource::kConstant, ColorSource::kPerTriangle, ColorSource::kPerVertex})
    for (CullMode cull : {CullMode::kNone, CullMode::kBack, CullMode::kFront})
      for (FrontFace face : {FrontFace::kCounterClockwise, FrontFace::kClockwise})
        for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
          SCOPED_TRACE(testing::Message() << "source " << int(source) << " cull " << int(cull)
                                          << " face " << int(face) << " rule " << int(rule));
          Draw d = scene.draw(source);
          d.state.cull = cull;
          d.state.front_face = face;
          d.state.fill_rule = rule;
          const front::FrontStats s = expect_same(d);
          EXPECT_GT(s.drawn, 0u);
          if (cull != CullMode::kNone) {
            EXPECT_GT(s.culled_face, 0u);
          }
        }
}

TEST(FrontSimd, ZeroAreaTinyAndOffScreenTriangles) {
  std::vector<glm::vec4> p;
  const auto tri = [&](glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    for (glm::vec2 v : {a, b, c}) p.emplace_back(v.x, v.y, 0.5f, 1.0f);
  };
  tri({1, 1}, {1, 1}, {1, 1});              // a point
  tri({1, 1}, {5, 5}, {9, 9});              // collinear
  tri({1, 1}, {1.001f, 1}, {1, 1.001f});    // snaps to a point
  tri({-0.001f, -0.001f}, {4, 0}, {0, 4});  // a corner snapping to -0
  tri({-9, -9}, {-5, -9}, {-9, -5});        // beyond the left and top edges: culled
  tri({-9, 0.5f}, {-0.2f, 4}, {-9, 8});     // box empty after snapping, not culled by clipping
  tri({330, 10}, {340, 10}, {330, 20});     // right of the target
  tri({2, 2}, {2, 9}, {9, 2});              // clockwise on screen
  tri({2, 2}, {9, 2}, {2, 9});              // counter-clockwise on screen
  tri({0, 0}, {320, 0}, {0, 200});          // the whole target's half
  tri({3, 3}, {3, 3}, {8, 8});              // degenerate again, for the tail
  tri({4, 4}, {4, 4}, {9, 9});              // and twice more, for 13 triangles
  tri({6, 6}, {7, 7}, {8, 8});
  Draw d;
  d.space = Space::kScreen;
  d.positions = p;
  for (CullMode cull : {CullMode::kNone, CullMode::kBack, CullMode::kFront})
    for (FillRule rule : {FillRule::kD3D, FillRule::kOpenGL}) {
      d.state.cull = cull;
      d.state.fill_rule = rule;
      const front::FrontStats s = expect_same(d);
      EXPECT_GT(s.degenerate, 0u);
      EXPECT_GT(s.outside, 0u);
    }
}

// Clip-space draws through a perspective camera: objects behind the eye, across the near and far
// planes, far off to the side (past the guard band), and in view. The clipped ones go to the
// scalar code; the counters show that every kind occurred.
TEST(FrontSimd, ClipSpaceThroughPerspectiveFallsBackWhereClipped) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> xyz;
  std::vector<Rgba8> colors;
  for (int t = 0; t < 1500; ++t) {
    const float spread = (t % 3 == 0) ? 400.0f : 6.0f;
    const glm::vec3 c(u(rng) * spread, u(rng) * spread, -u(rng) * 120.0f - 20.0f);
    const float size = (t % 5 == 0) ? 60.0f : 1.5f;
    for (int k = 0; k < 3; ++k) {
      xyz.push_back(c + size * glm::vec3(u(rng), u(rng), u(rng)));
      colors.push_back({static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()),
                        static_cast<std::uint8_t>(t % 2 ? 7 : rng()), 255});
    }
  }
  // Every vertex used twice, in a different order: an indexed draw.
  std::vector<std::uint32_t> indices;
  for (std::uint32_t i = 0; i + 2 < xyz.size(); i += 3)
    for (std::uint32_t k : {0u, 1u, 2u, 2u, 1u, 0u}) indices.push_back(i + k);

  glm::mat4 proj = glm::perspective(1.2f, float(kWidth) / kHeight, 0.5f, 100.0f);
  // To the renderer's depth range [0, 1] (clip.hpp: near Z >= 0, far Z <= W).
  const glm::mat4 to_unit_depth(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 1);
  const glm::mat4 transform = to_unit_depth * proj;
  // The same vertices already in clip space (Draw::positions, which the lanes fetch themselves).
  std::vector<glm::vec4> clip;
  for (const glm::vec3& p : xyz) clip.push_back(transform * glm::vec4(p, 1.0f));
  for (bool pretransformed : {false, true}) {
    Draw d;
    d.space = Space::kClip;
    if (pretransformed) {
      d.positions = clip;
    } else {
      d.positions_xyz = xyz;
      d.transform = transform;
    }
    for (ColorSource source : {ColorSource::kConstant, ColorSource::kPerVertex}) {
      d.color_source = source;
      d.colors = source == ColorSource::kPerVertex ? std::span<const Rgba8>(colors)
                                                   : std::span<const Rgba8>();
      for (bool indexed : {false, true}) {
        SCOPED_TRACE(testing::Message() << "source " << int(source) << " indexed " << indexed
                                        << " pretransformed " << pretransformed);
        d.indices =
            indexed ? std::span<const std::uint32_t>(indices) : std::span<const std::uint32_t>();
        const front::FrontStats s = expect_same(d);
        EXPECT_GT(s.clipped, 0u);
        EXPECT_GT(s.outside, 0u);
        EXPECT_GT(s.drawn, s.clipped);
      }
    }
  }
}

// Non-finite coordinates, W = 0 on the eye point (inside every plane, then no screen position),
// negative W, and a W so small that the divide overflows: all for the scalar code.
TEST(FrontSimd, NonFiniteAndEyePointVerticesFallBack) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = static_cast<float>(kInf);
  std::vector<glm::vec4> p;
  const auto tri = [&](glm::vec4 a, glm::vec4 b, glm::vec4 c) {
    for (glm::vec4 v : {a, b, c}) p.push_back(v);
  };
  const glm::vec4 in0(10, 10, 0.5f, 1), in1(60, 10, 0.5f, 1), in2(10, 60, 0.5f, 1);
  for (int rep = 0; rep < 3; ++rep) {  // the same cases at other lane positions
    tri(in0, in1, in2);
    tri(in0, glm::vec4(nan, 10, 0.5f, 1), in2);
    tri(glm::vec4(inf, 10, 0.5f, 1), in1, in2);
    tri(in0, in1, glm::vec4(10, 60, 0.5f, -inf));
    tri(glm::vec4(0, 0, 0, 0), in1, in2);                      // W = 0 on the eye point
    tri(in0, glm::vec4(10, 10, 0.5f, -1), in2);                // behind the eye
    tri(in0, in1, glm::vec4(1e-30f, 1e-30f, 1e-40f, 1e-40f));  // the divide overflows
    tri(in2, in1, in0);
  }
  Draw d;
  d.space = Space::kScreen;
  d.positions = p;
  d.space = Space::kScreen;
  const front::FrontStats screen = expect_same(d);
  EXPECT_GT(screen.nonfinite, 0u);
  EXPECT_GT(screen.degenerate, 0u);
  d.space = Space::kClip;
  const front::FrontStats clip = expect_same(d);
  EXPECT_GT(clip.nonfinite, 0u);
}

// Vertices drawn from awkward values: snapping ties (odd multiples of 1/512 px, either sign), the
// edges of the target and of the guard band, huge and tiny magnitudes, signed zeros, and W other
// than 1 (clip space), in random combinations, with per-vertex colours.
TEST(FrontSimd, SnapTiesGuardBandAndExtremeMagnitudes) {
  const float xs[] = {0.0f,
                      -0.0f,
                      1.0f / 512,
                      -1.0f / 512,
                      10.0f + 3.0f / 512,
                      -7.0f - 1.0f / 512,
                      319.99f,
                      320.0f,
                      320.5f,
                      199.998046875f,
                      200.0f,
                      32767.998f,
                      32768.0f,
                      -32768.0f,
                      40000.0f,
                      1e30f,
                      -1e30f,
                      1e-30f,
                      3.5f,
                      150.25f};
  const float zs[] = {0.0f, -0.0f, 0.5f, 1.0f, 1e-40f, 0.999999f};
  const float ws[] = {1.0f, 1.0f, 1.0f, 0.5f, 2.0f, 1e-3f, 1e3f};
  std::mt19937 rng(11);
  const auto pick = [&](const auto& values) { return values[rng() % std::size(values)]; };
  std::vector<glm::vec4> p;
  std::vector<Rgba8> colors;
  for (int t = 0; t < 4000; ++t) {
    for (int k = 0; k < 3; ++k) {
      // Mostly near one point, so that many triangles are small and drawn.
      const float base_x = pick(xs), base_y = pick(xs);
      p.emplace_back(k == 0 || rng() % 2 ? base_x : base_x + pick(xs) / 64,
                     k == 0 || rng() % 2 ? base_y : base_y + pick(xs) / 64, pick(zs), pick(ws));
      colors.push_back(
          {static_cast<std::uint8_t>(rng() % 3), 40, static_cast<std::uint8_t>(k), 255});
    }
  }
  for (Space space : {Space::kScreen, Space::kClip}) {
    SCOPED_TRACE(testing::Message() << "space " << int(space));
    Draw d;
    d.space = space;
    d.positions = p;
    d.color_source = ColorSource::kPerVertex;
    d.colors = colors;
    const front::FrontStats s = expect_same(d);
    EXPECT_GT(s.drawn, 0u);
    EXPECT_GT(s.clipped, 0u);
  }
}

// Shader draws, with and without varyings: the lanes set up q and the varying planes.
TEST(FrontSimd, ShaderDrawsWithAndWithoutVaryings) {
  const ScreenScene scene(203, 3);
  std::vector<float> attributes;
  for (std::size_t i = 0; i < scene.positions.size(); ++i)
    for (int a = 0; a < 4; ++a)
      attributes.push_back(static_cast<float>(i % 17) * 0.25f + static_cast<float>(a));
  const std::vector<std::uint32_t> varyings{0, 1, 3, 2};
  Draw d = scene.draw(ColorSource::kPerVertex);
  d.shader = flat_color_shader({0.1f, 0.2f, 0.3f, 1.0f});
  EXPECT_GT(expect_same(d).drawn, 0u);
  d.shader = vertex_color_shader();
  d.attributes = attributes;
  d.attribute_count = 4;
  d.varyings = varyings;
  EXPECT_GT(expect_same(d).drawn, 0u);
}

// Varying planes in lanes, at their limits: a perspective (clip-space, indexed) mesh with the
// most varyings a draw may have, read in a shuffled order from a wider vertex; values that are
// signed zeros, subnormal, huge enough that a plane overflows float (the constant-plane
// fallback), infinite or NaN; per-triangle colours beside the shader; culled back faces, and
// triangles through the near plane (clipped by the scalar code between the lanes).
TEST(FrontSimd, VaryingPlanesInLanesAtTheirLimits) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> xyz;
  for (int t = 0; t < 700; ++t) {
    // One in 9 crosses the near plane (z = -1): the scalar code clips it, between lanes.
    const glm::vec3 c(u(rng) * 30.0f, u(rng) * 20.0f, t % 9 == 4 ? -1.0f : -u(rng) * 40.0f - 45.0f);
    // Mostly small triangles, some large, some slivers thinner than a 16.8 step.
    const float size = t % 7 == 0 ? 25.0f : 0.4f;
    const glm::vec3 a = c + size * glm::vec3(u(rng), u(rng), u(rng));
    const glm::vec3 b = c + size * glm::vec3(u(rng), u(rng), u(rng));
    xyz.insert(xyz.end(), {a, b,
                           t % 11 == 0 ? a + (b - a) * 0.5f + glm::vec3(0, 1e-4f, 0)
                                       : c + size * glm::vec3(u(rng), u(rng), u(rng))});
  }
  std::vector<std::uint32_t> indices;
  for (std::uint32_t i = 0; i + 2 < xyz.size(); i += 3)
    for (std::uint32_t k : {0u, 1u, 2u, 2u, 1u, 0u}) indices.push_back(i + k);
  const glm::mat4 proj = glm::perspective(1.0f, float(kWidth) / kHeight, 1.0f, 200.0f);
  const glm::mat4 to_unit_depth(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 1);

  constexpr std::uint32_t kStride = kMaxVaryings + 3;  // wider than what is read
  const float specials[] = {0.0f,
                            -0.0f,
                            1e-40f,
                            3e38f,
                            -3e38f,
                            std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(),
                            1.0f};
  std::vector<float> attributes;
  for (std::size_t v = 0; v < xyz.size(); ++v)
    for (std::uint32_t a = 0; a < kStride; ++a)
      attributes.push_back(rng() % 16 == 0 ? specials[rng() % std::size(specials)]
                                           : u(rng) * static_cast<float>(1 + a));
  std::vector<std::uint32_t> varyings;
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(kMaxVaryings); ++k)
    varyings.push_back((k * 7 + 2) % kStride);
  std::vector<Rgba8> tri_colors;
  for (std::size_t t = 0; t < indices.size() / 3; ++t)
    tri_colors.push_back({static_cast<std::uint8_t>(t), 1, 2, 3});

  Draw d;
  d.space = Space::kClip;
  d.positions_xyz = xyz;
  d.transform = to_unit_depth * proj;
  d.indices = indices;
  d.attributes = attributes;
  d.attribute_count = kStride;
  d.shader = vertex_color_shader();
  for (const std::size_t count : {std::size_t{4}, std::size_t{5}, varyings.size()}) {
    for (const CullMode cull : {CullMode::kNone, CullMode::kBack}) {
      SCOPED_TRACE(testing::Message() << count << " varyings, cull " << int(cull));
      d.varyings = std::span<const std::uint32_t>(varyings).first(count);
      d.state.cull = cull;
      d.color_source = cull == CullMode::kBack ? ColorSource::kPerTriangle : ColorSource::kConstant;
      d.colors =
          cull == CullMode::kBack ? std::span<const Rgba8>(tri_colors) : std::span<const Rgba8>();
      const front::FrontStats s = expect_same(d);
      EXPECT_GT(s.drawn, 500u);
      EXPECT_GT(s.clipped, 5u);
      if (cull == CullMode::kBack) {
        EXPECT_GT(s.culled_face, 500u);
      }
    }
  }
}

}  // namespace
}  // namespace mosaic
