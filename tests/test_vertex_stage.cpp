// The vertex stage (front/vertex_stage.hpp) through Renderer::render(): indexed meshes whose
// vertices are each projected once equal the reference bit for bit on every SIMD path and
// thread count, on both sides of the stage's threshold (a draw takes it when its indices
// outnumber its vertices), with hard vertices (behind the eye, past the guard band, NaN) shared
// by many triangles, through positions and through positions_xyz with a transform, flat,
// per-vertex coloured and shaded. (test_front_simd compares the stage's cache with the scalar
// front end setup by setup.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "front/vertex_stage.hpp"
#include "mosaic/mosaic.hpp"
#include "reference_test_util.hpp"

namespace {

using namespace mosaic;

constexpr int kWidth = 160, kHeight = 120;
/// Grid cells per side: (kCells + 1)^2 = 441 vertices, a multiple of 3, so that an index buffer
/// can hold exactly as many indices as there are vertices.
constexpr int kCells = 20;
constexpr int kVertices = (kCells + 1) * (kCells + 1);
static_assert(kVertices % 3 == 0);

/// A wavy grid in world space, seen through a perspective camera from close by, so that its
/// rows run from behind the eye, across the near plane, to far off; one vertex far past the
/// guard band and one NaN, each shared by up to six triangles.
struct Grid {
  std::vector<glm::vec3> world;
  std::vector<glm::vec4> clip;
  std::vector<glm::vec3> normals;
  std::vector<float> attributes;  // the normals, three floats a vertex
  std::vector<std::uint32_t> indices;
  std::vector<Rgba8> colors;
  glm::mat4 view_projection{1.0f};
};

Grid make_grid() {
  Grid g;
  g.view_projection =
      glm::perspective(glm::radians(70.0f), float(kWidth) / float(kHeight), 0.5f, 60.0f) *
      glm::lookAt(glm::vec3(0.3f, 0.25f, 1.5f), glm::vec3(0.0f, 0.0f, -6.0f), glm::vec3(0, 1, 0));
  // Depth z/w in [0, 1]: glm::perspective gives [-1, 1].
  const glm::mat4 to_unit_depth(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 1);
  g.view_projection = to_unit_depth * g.view_projection;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const float x = -8.0f + 16.0f * float(i) / kCells;
      const float z = 4.0f - 30.0f * float(j) / kCells;
      g.world.emplace_back(x, 0.6f * std::sin(1.3f * x) * std::cos(0.7f * z), z);
      g.colors.push_back(test::distinct_color(static_cast<std::uint32_t>(g.world.size())));
    }
  g.world[static_cast<std::size_t>(3 * (kCells + 1) + 8)].x = 1e9f;  // past the guard band
  g.world[static_cast<std::size_t>(2 * (kCells + 1) + 9)].y =
      std::numeric_limits<float>::quiet_NaN();
  for (const glm::vec3& p : g.world) {
    g.clip.push_back(g.view_projection * glm::vec4(p, 1.0f));
    const glm::vec3 n = glm::normalize(glm::vec3(-0.4f * p.x, 1.0f, 0.2f * p.z));
    g.normals.push_back(n);
    g.attributes.insert(g.attributes.end(), {n.x, n.y, n.z});
  }
  g.indices = test::grid_indices(kCells);
  return g;
}

/// The kinds of draw the stage serves, each with its own fetch of a vertex.
enum class Kind { kClipFlat, kClipPerVertex, kWorldTransformed, kShaded };

const std::uint32_t kNormalVaryings[] = {0, 1, 2};

Draw grid_draw(const Grid& g, Kind kind, std::span<const std::uint32_t> indices) {
  Draw d;
  d.indices = indices;
  d.state.cull = CullMode::kNone;
  d.color = {200, 120, 40, 255};
  if (kind == Kind::kWorldTransformed) {
    d.positions_xyz = g.world;
    d.transform = g.view_projection;
  } else {
    d.positions = g.clip;
  }
  if (kind == Kind::kClipPerVertex || kind == Kind::kWorldTransformed) {
    d.color_source = ColorSource::kPerVertex;
    d.colors = g.colors;
  }
  if (kind == Kind::kShaded) {
    d.attributes = g.attributes;
    d.attribute_count = 3;
    d.varyings = kNormalVaryings;
    d.shader = normal_color_shader();
  }
  return d;
}

test::Captured render_with(const std::vector<Draw>& draws, RendererOptions options,
                           bool reserve = false) {
  RenderTarget target(kWidth, kHeight, 4, TargetOptions{true, true});
  target.set_clear(test::kClear, 1.0f);
  Renderer r(options);
  if (reserve) r.reserve({kWidth, kHeight, 4, 4 * kCells * kCells, 2 * kVertices});
  Frame frame;
  frame.draws = draws;
  return test::capture(r, frame, target);
}

void expect_same_counts(const FrameStats& ref, const FrameStats& got, const std::string& what) {
  EXPECT_EQ(ref.triangles_in, got.triangles_in) << what;
  EXPECT_EQ(ref.triangles_nonfinite, got.triangles_nonfinite) << what;
  EXPECT_EQ(ref.triangles_clipped, got.triangles_clipped) << what;
  EXPECT_EQ(ref.triangles_outside, got.triangles_outside) << what;
  EXPECT_EQ(ref.triangles_degenerate, got.triangles_degenerate) << what;
  EXPECT_EQ(ref.triangles_no_sample, got.triangles_no_sample) << what;
  EXPECT_EQ(ref.triangles_culled_face, got.triangles_culled_face) << what;
  EXPECT_EQ(ref.triangles_drawn, got.triangles_drawn) << what;
}

std::vector<Isa> simd_isas() {
  std::vector<Isa> v;
  for (Isa i : available_isas())
    if (i != Isa::kReference) v.push_back(i);
  return v;
}

// Every kind of draw, indexed (the stage), de-indexed (the front end's own fetch), and with
// index buffers exactly as long as the vertex buffer (no stage) and one triangle longer (the
// stage): each equals the reference on every ISA at 1, 2 and 3 threads.
TEST(VertexStage, IndexedMeshesMatchTheReferenceOnBothSidesOfTheThreshold) {
  const Grid g = make_grid();
  const std::vector<std::uint32_t> at_threshold(g.indices.begin(), g.indices.begin() + kVertices);
  const std::vector<std::uint32_t> past_threshold(g.indices.begin(),
                                                  g.indices.begin() + kVertices + 3);
  ASSERT_FALSE(front::wants_vertex_stage(grid_draw(g, Kind::kClipFlat, at_threshold)));
  ASSERT_TRUE(front::wants_vertex_stage(grid_draw(g, Kind::kClipFlat, past_threshold)));
  for (Kind kind : {Kind::kClipFlat, Kind::kClipPerVertex, Kind::kWorldTransformed, Kind::kShaded})
    for (const auto* indices : {&g.indices, &at_threshold, &past_threshold}) {
      const std::vector<Draw> draws{grid_draw(g, kind, *indices)};
      const std::string what = "kind " + std::to_string(static_cast<int>(kind)) + ", " +
                               std::to_string(indices->size()) + " indices";
      const test::Captured ref = render_with(draws, {.isa = Isa::kReference});
      EXPECT_GT(ref.stats.triangles_nonfinite, 0u) << what;
      EXPECT_GT(ref.stats.triangles_clipped, 0u) << what;
      EXPECT_GT(ref.stats.triangles_drawn, 20u) << what;
      for (Isa isa : simd_isas())
        for (int threads : {1, 2, 3}) {
          const std::string w =
              what + ", " + std::string(to_string(isa)) + ", " + std::to_string(threads);
          const test::Captured got = render_with(draws, {.threads = threads, .isa = isa});
          expect_same(ref, got, w);
          expect_same_counts(ref.stats, got.stats, w);
        }
    }
}

// Two staged draws share the frame's vertex memory at different offsets, beside an unstaged
// one; a later, larger frame grows that memory, and reserve() sized for it changes nothing.
TEST(VertexStage, SeveralDrawsAndGrowingFramesShareTheVertexMemory) {
  const Grid g = make_grid();
  Grid near = g;
  for (glm::vec4& c : near.clip) c.z *= 0.5f;  // nearer: drawn over the first grid
  const std::vector<Draw> one{grid_draw(g, Kind::kClipPerVertex, g.indices)};
  const std::vector<Draw> three{grid_draw(g, Kind::kClipPerVertex, g.indices),
                                grid_draw(g, Kind::kClipFlat, {}),
                                grid_draw(near, Kind::kShaded, near.indices)};
  // kClipFlat without indices draws vertices 0, 1, 2, 3, 4, 5, ... as triangles.
  for (Isa isa : simd_isas()) {
    RenderTarget target(kWidth, kHeight, 4, TargetOptions{true, true});
    RenderTarget reference_target(kWidth, kHeight, 4, TargetOptions{true, true});
    Renderer r({.threads = 2, .isa = isa});
    Renderer reference({.isa = Isa::kReference});
    for (const auto* draws : {&one, &three, &one, &three}) {
      Frame frame;
      frame.draws = *draws;
      const test::Captured want = test::capture(reference, frame, reference_target);
      const test::Captured got = test::capture(r, frame, target);
      const std::string what =
          std::string(to_string(isa)) + ", " + std::to_string(draws->size()) + " draws";
      expect_same(want, got, what);
      expect_same_counts(want.stats, got.stats, what);
    }
    const test::Captured plain = render_with(three, {.threads = 2, .isa = isa});
    const test::Captured reserved = render_with(three, {.threads = 2, .isa = isa}, true);
    expect_same(plain, reserved, std::string(to_string(isa)) + " after reserve()");
  }
}

// One vertex of an interleaved buffer, as an engine lays it out: the fields the draw reads sit
// between others it does not.
struct Vertex {
  float id;
  glm::vec3 position;
  float normal[3];
  float u, v;
};
static_assert(sizeof(Vertex) % sizeof(float) == 0);

// The grid read in place from an interleaved vertex buffer, with 16-bit indices, draws what
// its packed copy with 32-bit indices draws, bit for bit, on every path; so does a clip-space
// buffer of vec4 positions read with a stride.
TEST(VertexStage, InterleavedBuffersAnd16BitIndicesDrawAsTheirPackedCopies) {
  const Grid g = make_grid();
  std::vector<Vertex> interleaved;
  for (std::size_t i = 0; i < g.world.size(); ++i)
    interleaved.push_back(
        {float(i), g.world[i], {g.normals[i].x, g.normals[i].y, g.normals[i].z}, 0.25f, 0.75f});
  const std::vector<std::uint16_t> indices16(g.indices.begin(), g.indices.end());
  struct ClipVertex {
    std::uint32_t tag;
    glm::vec4 position;
  };
  std::vector<ClipVertex> clip;
  for (const glm::vec4& p : g.clip) clip.push_back({7, p});

  for (Kind kind : {Kind::kWorldTransformed, Kind::kShaded, Kind::kClipPerVertex}) {
    const Draw packed = grid_draw(g, kind, g.indices);
    Draw in_place = packed;
    in_place.indices = indices16;
    if (kind == Kind::kWorldTransformed) {
      in_place.positions_xyz =
          StridedSpan<glm::vec3>(&interleaved[0].position, interleaved.size(), sizeof(Vertex));
    } else {
      in_place.positions =
          StridedSpan<glm::vec4>(&clip[0].position, clip.size(), sizeof(ClipVertex));
    }
    if (kind == Kind::kShaded) {
      // The normals of every vertex, sizeof(Vertex) / 4 floats apart, read from the first one's.
      in_place.attributes = std::span<const float>(
          interleaved[0].normal, (interleaved.size() - 1) * (sizeof(Vertex) / 4) + 3);
      in_place.attribute_stride = sizeof(Vertex) / sizeof(float);
    }
    const std::string what = "kind " + std::to_string(static_cast<int>(kind));
    const test::Captured ref = render_with({packed}, {.isa = Isa::kReference});
    expect_same(ref, render_with({in_place}, {.isa = Isa::kReference}), what + ", reference");
    for (Isa isa : simd_isas()) {
      const test::Captured got = render_with({in_place}, {.threads = 2, .isa = isa});
      expect_same(ref, got, what + ", " + std::string(to_string(isa)));
      expect_same_counts(ref.stats, got.stats, what);
    }
  }
}

// A distant mesh in screen space: mostly triangles far below a pixel, so that the front end's
// float pre-cull settles whole windows, with the cases it must count as setup() does. Pixel
// coordinates are multiples of 1/256 (16.8 exact). Triangle i's corners are vertices 3i..3i+2;
// the index list names every triangle twice, so that the draw takes the vertex stage.
Mesh distant_mesh(int width, int height, DrawState state, std::uint64_t seed) {
  test::Rng rng(seed);
  Mesh m = test::screen_mesh(state);
  const auto snap = [](double v) { return std::round(v * 256.0) / 256.0; };
  const auto point = [&](double x, double y) { return glm::dvec2(snap(x), snap(y)); };
  constexpr int kTriangles = 4997;  // odd: the last window is partial
  for (int i = 0; i < kTriangles; ++i) {
    // Corners up to 6 px past the target's edges: some boxes cut, some outside every sample.
    const double x = rng.uniform(-6.0, width + 6.0), y = rng.uniform(-6.0, height + 6.0);
    glm::dvec2 a = point(x, y), b, c;
    // The second chunk (triangles 2048..) starts with larger triangles: its first window
    // culls too few, and the rest of that piece is set up without the pre-cull.
    const int kind = i >= 2048 && i < 2048 + 300 ? 5 : static_cast<int>(rng.range(0, 19));
    if (i % 97 == 0) {
      // Twice the area is -1 unit², where float's products round it to 0: past the pre-cull's
      // box limit, so setup() decides it in double.
      a = point(rng.uniform(0.0, width - 33.0), rng.uniform(0.0, height - 33.0));
      b = a + glm::dvec2(8191.0, 8190.0) / 256.0;
      c = a + glm::dvec2(8190.0, 8189.0) / 256.0;
    } else if (kind < 12) {  // far below a pixel, either winding
      b = point(x + rng.uniform(-0.3, 0.3), y + rng.uniform(-0.3, 0.3));
      c = point(x + rng.uniform(-0.3, 0.3), y + rng.uniform(-0.3, 0.3));
    } else if (kind == 12) {  // zero area: collinear corners
      const glm::dvec2 d = point(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2));
      b = a + d;
      c = a + 2.0 * d;
    } else if (kind == 13) {  // zero area: a repeated corner
      b = a;
      c = point(x + rng.uniform(-0.3, 0.3), y + rng.uniform(-0.3, 0.3));
    } else if (kind <= 15) {
      // Boxes at the pre-cull's size limit: 2048 units (8 px) wide or tall, or one unit more,
      // a fraction of a pixel thick, between rows or columns of samples or across them.
      const double side = 8.0 + (rng.coin() ? 1.0 / 256.0 : 0.0);
      const double thick = rng.uniform(0.01, 0.6);
      const glm::dvec2 base = point(std::floor(x) + rng.uniform(0.0, 1.0), std::floor(y) + 0.03);
      if (kind == 14) {
        a = base;
        b = base + glm::dvec2(side, 0.0);
        c = point(base.x + rng.uniform(0.0, side), base.y + thick);
      } else {
        a = glm::dvec2(base.y, base.x);
        b = a + glm::dvec2(0.0, side);
        c = point(a.x + thick, a.y + rng.uniform(0.0, side));
      }
      if (rng.coin()) std::swap(b, c);
    } else {  // a pixel or more: nearly always covers a sample
      b = point(x + rng.uniform(-3.0, 3.0), y + rng.uniform(-3.0, 3.0));
      c = point(x + rng.uniform(-3.0, 3.0), y + rng.uniform(-3.0, 3.0));
    }
    test::add_tri(m, a, b, c, test::distinct_color(static_cast<std::uint32_t>(i)),
                  static_cast<float>(rng.uniform(0.1, 0.9)));
  }
  for (int pass = 0; pass < 2; ++pass)
    for (std::uint32_t v = 0; v < 3 * kTriangles; ++v) m.indices.push_back(v);
  const std::vector<Rgba8> once = m.colors;  // one per submitted triangle
  m.colors.insert(m.colors.end(), once.begin(), once.end());
  return m;
}

// The front end culls a distant mesh's triangles from their corners' projections in float lanes
// before setting any up. Its counts (outside, zero area, facing, no sample) and everything drawn
// equal the reference's, for every cull mode and winding, with a viewport and scissor that cut
// boxes, at 1, 4 and 16 samples, with 16- and 32-bit indices, on every SIMD path.
TEST(VertexStage, DistantMeshesCulledBeforeSetUpCountAsTheReference) {
  constexpr int kW = 96, kH = 64;
  struct Case {
    CullMode cull;
    FrontFace front;
    bool clipped;
  };
  const Case cases[] = {{CullMode::kNone, FrontFace::kCounterClockwise, false},
                        {CullMode::kBack, FrontFace::kCounterClockwise, false},
                        {CullMode::kFront, FrontFace::kClockwise, false},
                        {CullMode::kBack, FrontFace::kClockwise, true}};
  std::uint64_t seed = 11;
  for (const Case& k : cases) {
    DrawState state;
    state.cull = k.cull;
    state.front_face = k.front;
    if (k.clipped) {
      state.viewport = PixelRect{6, 3, 80, 56};
      state.scissor = PixelRect{14, 9, 50, 40};
    }
    const Mesh mesh = distant_mesh(kW, kH, state, ++seed);
    const std::vector<std::uint16_t> narrow(mesh.indices.begin(), mesh.indices.end());
    Draw wide_draw = mesh.draw();
    Draw narrow_draw = wide_draw;
    narrow_draw.indices = narrow;
    ASSERT_TRUE(front::wants_vertex_stage(wide_draw));
    for (int samples : {1, 4, 16}) {
      const std::string what = "cull " + std::to_string(static_cast<int>(k.cull)) + ", front " +
                               std::to_string(static_cast<int>(k.front)) + ", clipped " +
                               std::to_string(k.clipped) + ", " + std::to_string(samples) + "x";
      const std::vector<Draw> draws{wide_draw};
      const test::Captured ref =
          test::render_draws(draws, kW, kH, {samples, false, Isa::kReference, 1}, test::kClear);
      // The mesh has every case the pre-cull counts.
      EXPECT_GT(ref.stats.triangles_no_sample, 400u) << what;
      EXPECT_GT(ref.stats.triangles_degenerate, 400u) << what;
      EXPECT_GT(ref.stats.triangles_outside, 2000u) << what;
      EXPECT_GT(ref.stats.triangles_drawn, 200u) << what;
      if (k.cull != CullMode::kNone) {
        EXPECT_GT(ref.stats.triangles_culled_face, 2000u) << what;
      }
      for (Isa isa : simd_isas())
        for (int threads : {1, 2})
          for (const Draw* d : {&wide_draw, &narrow_draw}) {
            const std::string w = what + ", " + std::string(to_string(isa)) + ", " +
                                  std::to_string(threads) + " threads, " +
                                  (d == &narrow_draw ? "16" : "32") + "-bit";
            const std::vector<Draw> one{*d};
            const test::Captured got =
                test::render_draws(one, kW, kH, {samples, false, isa, threads}, test::kClear);
            test::expect_same(ref, got, w);
            expect_same_counts(ref.stats, got.stats, w);
          }
    }
  }
}

}  // namespace
