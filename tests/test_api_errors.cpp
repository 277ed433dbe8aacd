// Rejected input at the public API: every error is a mosaic::Error with the documented Errc and a
// one-line message, and a rejected frame leaves the render target exactly as it was. Triangles
// with NaN or infinite coordinates are not errors: they are culled, counted, and leave the other
// triangles' pixels untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "reference_test_util.hpp"

namespace mosaic {
namespace {

template <class F>
void expect_error(Errc code, F&& f) {
  try {
    f();
    ADD_FAILURE() << "no mosaic::Error thrown";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    const std::string what = e.what();
    EXPECT_FALSE(what.empty());
    EXPECT_EQ(what.find('\n'), std::string::npos) << "message is not one line: " << what;
  }
}

TEST(ApiErrors, RenderTargetSize) {
  for (int bad : {0, -1, kMaxTargetSize + 1, std::numeric_limits<int>::min()}) {
    expect_error(Errc::kInvalidTargetSize, [&] { RenderTarget t(bad, 8); });
    expect_error(Errc::kInvalidTargetSize, [&] { RenderTarget t(8, bad); });
  }
  EXPECT_EQ(kMaxTargetSize, 16384);
  EXPECT_NO_THROW(RenderTarget(kMaxTargetSize, 1));
  EXPECT_NO_THROW(RenderTarget(1, kMaxTargetSize));
  EXPECT_NO_THROW(RenderTarget(1, 1));
}

TEST(ApiErrors, RenderTargetSampleCount) {
  for (int bad : {0, 2, 3, 5, 32, -4}) {
    expect_error(Errc::kUnsupportedSampleCount, [&] { RenderTarget t(8, 8, bad); });
  }
  for (int good : {1, 4, 8, 16}) {
    RenderTarget t(8, 8, good);
    EXPECT_EQ(t.samples(), good);
  }
}

TEST(ApiErrors, ClearDepthMustBeFinite) {
  RenderTarget t(4, 4);
  t.set_clear({9, 8, 7, 6}, 0.25f);
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()}) {
    expect_error(Errc::kInvalidArgument, [&] { t.set_clear({1, 2, 3, 4}, bad); });
    EXPECT_EQ(t.clear_color(), (Rgba8{9, 8, 7, 6}));  // unchanged by the rejected call
    EXPECT_EQ(t.clear_depth(), 0.25f);
  }
}

TEST(ApiErrors, RendererOptions) {
  expect_error(Errc::kInvalidArgument, [] {
    RendererOptions o;
    o.threads = -1;
    Renderer r(o);
  });
  RendererOptions zero;
  zero.threads = 0;
  EXPECT_NO_THROW(Renderer{zero});
  // Tile sizes: 0 (the renderer's choice) or a power of two from kMinTileSize to kMaxTileSize.
  for (int size : {-8, 1, 4, 12, 24, 96, 256, 1 << 30})
    expect_error(Errc::kInvalidArgument, [&] { Renderer r({.tile_size = size}); });
  for (int size : {0, 8, 16, 32, 64, 128}) EXPECT_NO_THROW(Renderer({.tile_size = size}));
  // Every ISA that available_isas() does not list is refused.
  const std::vector<Isa> have = available_isas();
  ASSERT_FALSE(have.empty());
  EXPECT_EQ(have.front(), Isa::kReference);
  for (Isa isa : {Isa::kReference, Isa::kSse41, Isa::kAvx2, Isa::kAvx512}) {
    RendererOptions o;
    o.isa = isa;
    if (std::find(have.begin(), have.end(), isa) != have.end()) {
      EXPECT_EQ(Renderer(o).isa(), isa);
    } else {
      expect_error(Errc::kUnsupportedIsa, [&] { Renderer r(o); });
    }
  }
}

// A moved-from Renderer has given its workers away: render() is a clear error that leaves the
// target alone, its accessors answer as documented, and the Renderer it moved into still works.
TEST(ApiErrors, MovedFromRenderer) {
  for (Isa isa : available_isas()) {
    SCOPED_TRACE(to_string(isa));
    RendererOptions o;
    o.isa = isa;
    o.threads = 2;
    Renderer from(o);
    Renderer to(std::move(from));
    Mesh m = test::screen_mesh();
    test::add_tri(m, {1, 1}, {14, 2}, {3, 13}, {200, 30, 60, 255});
    const Draw d = m.draw();
    Frame f;
    f.draws = std::span<const Draw>(&d, 1);
    RenderTarget t(16, 16, 4);
    const std::uint64_t cleared = t.image_hash();
    expect_error(Errc::kInvalidArgument,
                 [&] { from.render(f, t); });  // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(t.image_hash(), cleared);
    EXPECT_EQ(from.isa(), Isa::kReference);
    EXPECT_EQ(from.threads(), 0);
    EXPECT_TRUE(from.hierarchical_z().empty());
    EXPECT_EQ(to.isa(), isa);
    EXPECT_EQ(to.render(f, t).triangles_drawn, 1u);
    EXPECT_NE(t.image_hash(), cleared);
    // Assigning a live Renderer to the moved-from one makes it whole again.
    from = Renderer(o);
    EXPECT_EQ(from.isa(), isa);
    EXPECT_EQ(from.render(f, t).triangles_drawn, 1u);
  }
}

TEST(ApiErrors, MessagesEscapeControlAndMalformedBytes) {
  // Controls, C1 controls and malformed UTF-8 (a stray continuation, overlong forms, a
  // surrogate, past U+10FFFF, a cut sequence) are escaped byte by byte; the rest is kept.
  const std::pair<std::string, std::string> cases[] = {
      {"plain \\ text", "plain \\ text"},
      {"\x1b]0;title\x07", "\\x1b]0;title\\x07"},
      {"a\nb\rc\td\x7f", "a\\x0ab\\x0dc\\x09d\\x7f"},
      {"\xc2\x9b"
       "2J \xc2\xa0",
       "\\xc2\\x9b2J \xc2\xa0"},
      {"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80", "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"},
      {"\x80\xff", "\\x80\\xff"},
      {"\xc0\xaf \xe0\x80\xaf", "\\xc0\\xaf \\xe0\\x80\\xaf"},
      {"\xed\xa0\x80", "\\xed\\xa0\\x80"},
      {"\xf4\x90\x80\x80", "\\xf4\\x90\\x80\\x80"},
      {"cut \xe2\x82", "cut \\xe2\\x82"},
  };
  for (const auto& [in, out] : cases) {
    EXPECT_EQ(printable(in), out);
    EXPECT_EQ(printable(printable(in)), out);
    EXPECT_EQ(std::string(Error(Errc::kParse, "file '" + in + "'").what()), "file '" + out + "'");
  }
}

// reserve() checks its frame, and a reserved Renderer renders what a fresh one does.
TEST(ApiErrors, ReserveChecksItsFrameAndChangesNoImage) {
  Renderer r(RendererOptions{2});
  for (const FrameReserve bad :
       {FrameReserve{0, 8, 1, 10}, FrameReserve{8, 16385, 1, 10}, FrameReserve{8, 8, 3, 10},
        FrameReserve{8, 8, 4, ~0ull}, FrameReserve{8, 8, 4, 10, std::uint64_t{1} << 32}}) {
    try {
      r.reserve(bad);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kInvalidArgument) << e.what();
    }
  }
  test::Rng rng(31);
  const std::vector<Mesh> meshes = test::random_draws(61, 47, 3, 2000, rng);
  const std::vector<Draw> draws = test::draws_of(meshes);
  Frame f;
  f.draws = draws;
  RenderTarget a(61, 47, 4), b(61, 47, 4);
  Renderer(RendererOptions{2}).render(f, a);
  r.reserve({61, 47, 4, 6000});
  r.render(f, b);
  EXPECT_EQ(a.image_hash(), b.image_hash());
}

// One Renderer per thread: two render at once, each into its own target, and each image is the
// one a lone render gives.
TEST(ApiErrors, TwoRenderersOnTwoThreadsRenderAsAlone) {
  test::Rng rng(32);
  const std::vector<Mesh> meshes = test::random_draws(96, 64, 4, 500, rng);
  const std::vector<Draw> draws = test::draws_of(meshes);
  Frame f;
  f.draws = draws;
  RenderTarget alone(96, 64, 4);
  Renderer(RendererOptions{2}).render(f, alone);
  std::vector<std::uint64_t> hashes[2];
  auto work = [&](int k) {
    Renderer r(RendererOptions{2});
    RenderTarget t(96, 64, 4);
    for (int i = 0; i < 20; ++i) {
      r.render(f, t);
      hashes[k].push_back(t.image_hash());
    }
  };
  std::thread one(work, 0), two(work, 1);
  one.join();
  two.join();
  for (const auto& h : hashes) {
    ASSERT_EQ(h.size(), 20u);
    for (std::uint64_t v : h) EXPECT_EQ(v, alone.image_hash());
  }
}

TEST(ApiErrors, ARendererEnteredWhileItRendersThrowsBusy) {
  // Thread A renders a frame whose shader holds the frame open until the main thread has tried
  // to render with the same Renderer; that attempt must throw kBusy and leave its target alone.
  // Inside the frame, the shader's own render() call is refused the same way.
  for (Isa isa : available_isas()) {
    SCOPED_TRACE(to_string(isa));
    Renderer renderer(RendererOptions{.threads = 2, .isa = isa});
    std::atomic<bool> inside{false}, attempted{false};
    std::atomic<int> nested = -1;
    Mesh m = test::screen_mesh();
    test::add_tri(m, {1, 1}, {30, 2}, {3, 29}, {200, 30, 60, 255});
    Frame nested_frame;
    RenderTarget nested_target(8, 8);
    Draw d = m.draw();
    d.shader = make_shader(
        [&](const Fragment&) {
          if (!inside.exchange(true)) {
            try {
              renderer.render(nested_frame, nested_target);
              nested = 0;
            } catch (const Error& e) {
              nested = static_cast<int>(e.code());
            }
            const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
            while (!attempted && std::chrono::steady_clock::now() < give_up)
              std::this_thread::yield();
          }
          return glm::vec4(1, 0, 0, 1);
        },
        0);
    Frame f;
    f.draws = std::span<const Draw>(&d, 1);
    RenderTarget a(32, 32, 4), b(32, 32, 4);
    std::thread first([&] { renderer.render(f, a); });
    while (!inside) std::this_thread::yield();
    const std::uint64_t cleared = b.image_hash();
    expect_error(Errc::kBusy, [&] { renderer.render(f, b); });
    EXPECT_EQ(b.image_hash(), cleared);
    attempted = true;
    first.join();
    EXPECT_EQ(nested, static_cast<int>(Errc::kBusy));
    // Once the frame is done, the Renderer takes the next one.
    inside = true;  // the shader now just colours
    EXPECT_EQ(renderer.render(f, b).triangles_drawn, 1u);
    EXPECT_EQ(a.image_hash(), b.image_hash());
  }
}

// A frame rendered first, then a bad one: the bad one must throw the expected code from every
// renderer and leave the target's image and sample buffers as the good frame left them.
class BadDraw : public ::testing::Test {
 protected:
  void SetUp() override {
    good_ = test::screen_mesh();
    test::add_tri(good_, {1, 1}, {14, 2}, {3, 13}, {200, 30, 60, 255});
    test::add_tri(good_, {15, 15}, {2, 14}, {13, 3}, {20, 230, 60, 255});
  }

  // A renderer of `isa` on `threads` threads that has drawn the good frame into `t`.
  Renderer after_good_frame(Isa isa, int threads, RenderTarget& t) const {
    RendererOptions o;
    o.isa = isa;
    o.threads = threads;
    Renderer r(o);
    const Draw g = good_.draw();
    Frame good;
    good.draws = std::span<const Draw>(&g, 1);
    r.render(good, t);
    return r;
  }

  void expect_rejected(Errc code, const std::vector<Draw>& bad_draws) {
    std::vector<Isa> isas = available_isas();
    isas.push_back(Isa::kAuto);
    for (Isa isa : isas) {
      SCOPED_TRACE(to_string(isa));
      RenderTarget t(16, 16, 4, TargetOptions{true, true});
      Renderer r = after_good_frame(isa, 2, t);
      const std::vector<Rgba8> color(t.color().begin(), t.color().end());
      const std::vector<Rgba8> sample_color(t.sample_color().begin(), t.sample_color().end());
      const std::vector<float> sample_depth(t.sample_depth().begin(), t.sample_depth().end());
      const std::uint64_t hash = t.image_hash();
      ASSERT_NE(std::count(color.begin(), color.end(), Rgba8{0, 0, 0, 255}), 256);
      Frame bad;
      bad.draws = bad_draws;
      expect_error(code, [&] { r.render(bad, t); });
      expect_error(code, [&] { validate(bad, t); });
      EXPECT_TRUE(std::equal(color.begin(), color.end(), t.color().begin(), t.color().end()));
      EXPECT_TRUE(std::equal(sample_color.begin(), sample_color.end(), t.sample_color().begin(),
                             t.sample_color().end()));
      EXPECT_TRUE(std::equal(sample_depth.begin(), sample_depth.end(), t.sample_depth().begin(),
                             t.sample_depth().end()));
      EXPECT_EQ(t.image_hash(), hash);
    }
  }

  Mesh good_;
};

TEST_F(BadDraw, IndexOutOfRange) {
  Mesh m = good_;
  m.indices = {0, 1, 2, 3, 4, 6};  // 6 vertices: index 6 does not exist
  expect_rejected(Errc::kIndexOutOfRange, {good_.draw(), m.draw()});
  m.indices = {0, 1, 0xffffffffu};
  m.colors.resize(1);
  expect_rejected(Errc::kIndexOutOfRange, {m.draw()});
  // Indices into an empty vertex buffer.
  Mesh empty = test::screen_mesh();
  empty.indices = {0, 0, 0};
  empty.colors = {{1, 2, 3, 255}};
  expect_rejected(Errc::kIndexOutOfRange, {empty.draw()});
}

// The fast path checks index ranges in its front end, chunk by chunk and in parallel: a bad
// index deep in a large mesh, in any chunk, with or without the vertex stage, 32- or 16-bit,
// still throws validate()'s error (the first bad position) and leaves the target as it was.
TEST_F(BadDraw, IndexOutOfRangeDeepInALargeMesh) {
  // A 60 × 60 grid of cells, two triangles each (7,200 triangles, several front-end chunks):
  // shared vertices, so the vertex stage projects them (more indices than vertices).
  constexpr int kCells = 60;
  Mesh grid = test::screen_mesh();
  grid.color_source = ColorSource::kConstant;
  for (int y = 0; y <= kCells; ++y)
    for (int x = 0; x <= kCells; ++x)
      grid.positions.emplace_back(static_cast<float>(x) * 64.0f / kCells,
                                  static_cast<float>(y) * 64.0f / kCells, 0.25f, 1.0f);
  const auto at = [](int x, int y) { return static_cast<std::uint32_t>(y * (kCells + 1) + x); };
  for (int y = 0; y < kCells; ++y)
    for (int x = 0; x < kCells; ++x)
      for (std::uint32_t i :
           {at(x, y), at(x + 1, y), at(x, y + 1), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)})
        grid.indices.push_back(i);
  // The same triangles with a vertex each: no vertex stage (as many indices as vertices).
  Mesh soup = test::screen_mesh();
  soup.color_source = ColorSource::kConstant;
  for (std::uint32_t i : grid.indices) {
    soup.indices.push_back(static_cast<std::uint32_t>(soup.positions.size()));
    soup.positions.push_back(grid.positions[i]);
  }
  const std::uint32_t vertices_grid = static_cast<std::uint32_t>(grid.positions.size());
  const std::uint32_t vertices_soup = static_cast<std::uint32_t>(soup.positions.size());

  std::vector<Isa> isas = available_isas();
  isas.push_back(Isa::kAuto);
  for (const bool shared : {true, false})
    for (const std::size_t position : {std::size_t{5}, std::size_t{13'001}, std::size_t{21'597}})
      for (const bool narrow : {false, true}) {
        Mesh m = shared ? grid : soup;
        const std::uint32_t bad = (shared ? vertices_grid : vertices_soup) + 7;
        m.indices[position] = narrow ? 0xffffu : bad;
        // A second bad index later on: the error names the first.
        m.indices[21'598] = narrow ? 0xfffeu : bad + 1;
        std::vector<std::uint16_t> indices16(m.indices.begin(), m.indices.end());
        Draw d = m.draw();
        if (narrow) d.indices = indices16;
        const std::string expected = "index " + std::to_string(m.indices[position]) +
                                     " at position " + std::to_string(position) + " ";
        for (Isa isa : isas)
          for (int threads : {1, 2, 7}) {
            SCOPED_TRACE(std::string(to_string(isa)) + " threads " + std::to_string(threads) +
                         (shared ? " shared" : " soup") + (narrow ? " 16-bit" : " 32-bit") +
                         " position " + std::to_string(position));
            RenderTarget t(64, 64, 4, TargetOptions{true, true});
            Renderer r = after_good_frame(isa, threads, t);
            const std::uint64_t hash = t.image_hash();
            const std::vector<float> depth(t.sample_depth().begin(), t.sample_depth().end());
            Frame bad_frame;
            bad_frame.draws = std::span<const Draw>(&d, 1);
            std::string what;
            try {
              r.render(bad_frame, t);
              ADD_FAILURE() << "no error";
            } catch (const Error& e) {
              EXPECT_EQ(e.code(), Errc::kIndexOutOfRange);
              what = e.what();
            }
            EXPECT_NE(what.find(expected), std::string::npos) << what;
            EXPECT_EQ(t.image_hash(), hash);
            EXPECT_TRUE(std::equal(depth.begin(), depth.end(), t.sample_depth().begin(),
                                   t.sample_depth().end()));
            // The renderer is whole afterwards: the mesh with its index mended draws.
            Draw mended = d;
            std::vector<std::uint32_t> fixed32 = m.indices;
            fixed32[position] = 0;
            fixed32[21'598] = 0;
            const std::vector<std::uint16_t> fixed16(fixed32.begin(), fixed32.end());
            if (narrow) {
              mended.indices = fixed16;
            } else {
              mended.indices = fixed32;
            }
            Frame fine;
            fine.draws = std::span<const Draw>(&mended, 1);
            EXPECT_NO_THROW(r.render(fine, t));
          }
      }
}

// A frame with a bad index in one draw and another error in a later draw throws the first in
// draw order, as validate() does, though the fast path checks indices after the other checks.
TEST_F(BadDraw, FirstErrorInDrawOrder) {
  Mesh bad_index = good_;
  bad_index.indices = {0, 1, 2, 3, 4, 9};
  Mesh bad_count = good_;
  bad_count.indices = {0, 1, 2, 3};
  expect_rejected(Errc::kIndexOutOfRange, {bad_index.draw(), bad_count.draw()});
  expect_rejected(Errc::kInvalidDraw, {bad_count.draw(), bad_index.draw()});
}

TEST_F(BadDraw, IndexCountNotAMultipleOfThree) {
  Mesh m = good_;
  m.indices = {0, 1, 2, 3};
  expect_rejected(Errc::kInvalidDraw, {m.draw()});
}

TEST_F(BadDraw, VertexCountNotAMultipleOfThreeWithoutIndices) {
  Mesh m = good_;
  m.positions.pop_back();
  expect_rejected(Errc::kInvalidDraw, {good_.draw(), m.draw()});
}

TEST_F(BadDraw, ColourCountMismatch) {
  Mesh per_triangle = good_;  // 2 triangles
  per_triangle.colors.pop_back();
  expect_rejected(Errc::kInvalidDraw, {per_triangle.draw()});
  per_triangle.colors = {{1, 1, 1, 255}, {1, 1, 1, 255}, {1, 1, 1, 255}};
  expect_rejected(Errc::kInvalidDraw, {per_triangle.draw()});
  Mesh per_vertex = good_;  // 6 vertices
  per_vertex.color_source = ColorSource::kPerVertex;
  per_vertex.colors.assign(5, {1, 1, 1, 255});
  expect_rejected(Errc::kInvalidDraw, {good_.draw(), per_vertex.draw()});
  per_vertex.colors.clear();
  expect_rejected(Errc::kInvalidDraw, {per_vertex.draw()});
}

TEST_F(BadDraw, BothPositionKinds) {
  const std::vector<glm::vec3> xyz(6, glm::vec3(0));
  Draw d = good_.draw();
  d.positions_xyz = xyz;
  expect_rejected(Errc::kInvalidDraw, {d});
}

TEST_F(BadDraw, StridesShorterThanWhatTheyStep) {
  // A position stride below the position's size would overlap the vertices.
  Draw d = good_.draw();
  d.positions = StridedSpan<glm::vec4>(&good_.positions[0], 3, sizeof(glm::vec4) - 4);
  expect_rejected(Errc::kInvalidDraw, {good_.draw(), d});
  const std::vector<glm::vec3> xyz(6, glm::vec3(1));
  Draw x = good_.draw();
  x.positions = {};
  x.positions_xyz = StridedSpan<glm::vec3>(xyz.data(), 6, 0);
  expect_rejected(Errc::kInvalidDraw, {x});
  // Attribute rows closer together than the attributes in a row, and a strided buffer that
  // ends before the last vertex's attributes.
  const std::vector<float> attrs(6 * 4, 0.5f);
  const std::uint32_t varyings[] = {0, 1, 2};
  Draw shaded = good_.draw();
  shaded.shader = normal_color_shader();
  shaded.attributes = attrs;
  shaded.attribute_count = 3;
  shaded.varyings = varyings;
  shaded.attribute_stride = 2;
  expect_rejected(Errc::kInvalidDraw, {shaded});
  shaded.attribute_stride = 5;  // the last vertex's row would start at 25, past 24 floats
  expect_rejected(Errc::kInvalidDraw, {shaded});
  shaded.attribute_stride = 4;  // 5 * 4 + 3 = 23 floats: fits
  Renderer r;
  RenderTarget t(16, 16, 4);
  Frame f;
  f.draws = std::span<const Draw>(&shaded, 1);
  EXPECT_NO_THROW(r.render(f, t));
}

// --- Non-finite coordinates ----------------------------------------------------------------------

TEST(ApiNonFinite, BadTrianglesAreCulledAndDoNotDisturbTheOthers) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  // Neighbouring triangles sharing edges with the bad ones' finite vertices.
  const std::vector<glm::vec4> good{{2, 2, 0.5f, 1},  {20, 3, 0.5f, 1},  {4, 20, 0.5f, 1},
                                    {20, 3, 0.5f, 1}, {22, 22, 0.4f, 1}, {4, 20, 0.5f, 1}};
  const std::vector<std::vector<glm::vec4>> bad{
      {{20, 3, 0.5f, 1}, {nan, 10, 0.5f, 1}, {22, 22, 0.5f, 1}},
      {{inf, 3, 0.5f, 1}, {30, 10, 0.5f, 1}, {22, 22, 0.5f, 1}},
      {{20, 3, 0.5f, 1}, {30, -inf, 0.5f, 1}, {22, 22, 0.5f, 1}},
      {{20, 3, nan, 1}, {30, 10, 0.5f, 1}, {22, 22, 0.5f, 1}},
      {{20, 3, 0.5f, 1}, {30, 10, 0.5f, inf}, {22, 22, 0.5f, 1}},
      {{nan, nan, nan, nan}, {nan, nan, nan, nan}, {nan, nan, nan, nan}},
  };
  for (Space space : {Space::kScreen, Space::kClip}) {
    Mesh ref;
    ref.space = space;
    ref.positions = good;
    if (space == Space::kClip)  // the same pixels: NDC = pixel / 16 - 1 on a 32x32 target
      for (glm::vec4& p : ref.positions) p = {p.x / 16 - 1, 1 - p.y / 16, p.z, 1};
    RenderTarget expect_t(32, 32, 4);
    const FrameStats expect_s = test::render_reference(ref, expect_t);
    for (std::size_t i = 0; i < bad.size(); ++i) {
      SCOPED_TRACE(i);
      Mesh m = ref;
      // The bad triangle goes first, in the middle and last.
      for (int where : {0, 1, 2}) {
        m.positions = ref.positions;
        std::vector<glm::vec4> b = bad[i];
        if (space == Space::kClip)
          for (glm::vec4& p : b)
            if (std::isfinite(p.x) && std::isfinite(p.y))
              p = {p.x / 16 - 1, 1 - p.y / 16, p.z, p.w};
        m.positions.insert(m.positions.begin() + 3 * where, b.begin(), b.end());
        RenderTarget t(32, 32, 4);
        const FrameStats s = test::render_reference(m, t);
        EXPECT_EQ(s.triangles_in, 3u);
        EXPECT_EQ(s.triangles_nonfinite, 1u);
        EXPECT_EQ(s.triangles_drawn, expect_s.triangles_drawn);
        EXPECT_EQ(s.samples_written, expect_s.samples_written);
        EXPECT_EQ(t.image_hash(), expect_t.image_hash());
      }
    }
  }
}

TEST(ApiNonFinite, TransformedPositions) {
  // positions_xyz through a transform: NaN in a position culls that triangle only; NaN or Inf in
  // the matrix culls every triangle.
  const std::vector<glm::vec3> xyz{
      {-0.8f, -0.8f, 0.5f}, {0.8f, -0.7f, 0.5f},
      {0, 0.8f, 0.5f},      {std::numeric_limits<float>::quiet_NaN(), 0, 0.5f},
      {0.5f, 0.5f, 0.5f},   {0, 0.5f, 0.5f}};
  Draw d;
  d.positions_xyz = xyz;
  Frame f;
  f.draws = std::span<const Draw>(&d, 1);
  RendererOptions o;
  o.isa = Isa::kReference;
  Renderer r(o);
  RenderTarget t(16, 16);
  FrameStats s = r.render(f, t);
  EXPECT_EQ(s.triangles_in, 2u);
  EXPECT_EQ(s.triangles_nonfinite, 1u);
  EXPECT_EQ(s.triangles_drawn, 1u);
  for (float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    d.transform = glm::mat4(1.0f);
    d.transform[3][0] = bad;  // translation x
    s = r.render(f, t);
    EXPECT_EQ(s.triangles_nonfinite, 2u);
    EXPECT_EQ(s.triangles_drawn, 0u);
    EXPECT_EQ(std::count(t.color().begin(), t.color().end(), t.clear_color()), 256);
  }
}

}  // namespace
}  // namespace mosaic

namespace mosaic {
namespace {

TEST(ApiRobustness, ExtremeFiniteCoordinatesNeverCrash) {
  // Finite but hostile vertices: w of 0, negative, tiny and huge; coordinates up to float's
  // limits. Each frame must render without throwing, and every submitted triangle must end up
  // drawn (possibly in pieces) or counted under exactly one rejection.
  test::Rng rng(71);
  const float magnitudes[] = {0.0f, 1e-38f, 1e-30f, 1e-6f, 0.5f,   1.0f,
                              3.0f, 1e4f,   1e6f,   1e30f, 3.4e38f};
  auto value = [&] {
    const float m = magnitudes[rng.range(0, std::size(magnitudes) - 1)];
    return static_cast<float>(m * rng.uniform(-1, 1));
  };
  for (Space space : {Space::kScreen, Space::kClip}) {
    for (int samples : {1, 4}) {
      Mesh m;
      m.space = space;
      m.color_source = ColorSource::kPerVertex;
      for (int i = 0; i < 3 * 400; ++i) {
        m.positions.push_back({value(), value(), value(), value()});
        m.colors.push_back({static_cast<std::uint8_t>(rng.range(0, 255)), 7, 9, 255});
      }
      m.state.depth_test = DepthTest::kAlways;
      RenderTarget t = test::sample_target(24, 16, samples);
      FrameStats s;
      ASSERT_NO_THROW(s = test::render_reference(m, t));
      EXPECT_EQ(s.triangles_in, 400u);
      EXPECT_LE(s.triangles_nonfinite + s.triangles_culled_face + s.triangles_degenerate +
                    s.triangles_outside,
                s.triangles_in);
      EXPECT_GE(s.samples_written, test::count_covered(t));
      EXPECT_GT(s.triangles_drawn, 0u);
      for (float d : t.sample_depth()) ASSERT_TRUE(d >= 0.0f && d <= 1.0f) << d;
    }
  }
}

}  // namespace
}  // namespace mosaic
