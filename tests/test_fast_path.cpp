// The fast tile path against the exact reference rasterizer: bit-identical resolved images,
// per-sample colour and depth, and samples_written, for every SIMD path this CPU runs, every
// sample count, both fill rules, every depth mode, MSAA and SSAA, 1, 2 and 7 threads, and
// image sizes that tiles do not divide.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <utility>
#include <vector>

#include "bin/binner.hpp"
#include "mosaic/mosaic.hpp"
#include "reference_test_util.hpp"
#include "scenes/rng.hpp"

namespace {

using Rng = mosaic::SplitMix64;

using mosaic::Isa;

enum class Shape { kSmall, kTiny, kLarge, kSliver, kHuge, kClipSpace, kOnSamples };

struct TestScene {
  std::vector<glm::vec4> positions;
  std::vector<mosaic::Rgba8> colors;
  mosaic::Space space = mosaic::Space::kScreen;
  mosaic::ColorSource source = mosaic::ColorSource::kPerVertex;
};

// Random triangles of one shape over a w × h screen (or clip space). Vertices are often snapped
// to 1/16 px so that many samples lie exactly on edges, which exercises the fill rule.
TestScene make_scene(Shape shape, int w, int h, int count, std::uint64_t seed, bool per_vertex) {
  Rng rng{seed};
  TestScene sc;
  sc.source = per_vertex ? mosaic::ColorSource::kPerVertex : mosaic::ColorSource::kPerTriangle;
  auto snap16 = [&](double v) { return (rng.next() & 1) ? std::floor(v * 16) / 16 : v; };
  for (int i = 0; i < count; ++i) {
    double cx = rng.uniform(-0.1 * w, 1.1 * w), cy = rng.uniform(-0.1 * h, 1.1 * h);
    double r = 0;
    switch (shape) {
      case Shape::kSmall:
        r = rng.uniform(1, 8);
        break;
      case Shape::kTiny:
        // Boxes of one pixel (the kernels' one-pixel path) and just over, as a distant mesh has.
        r = rng.uniform(0.05, 1.0);
        break;
      case Shape::kLarge:
        r = rng.uniform(0.2, 0.8) * w;
        break;
      case Shape::kSliver:
        r = rng.uniform(20, 200);
        break;
      case Shape::kHuge:
        r = rng.uniform(3e3, 1e6);
        break;
      case Shape::kClipSpace:
        r = 0;
        break;
      case Shape::kOnSamples:
        r = rng.uniform(1, 20);
        break;
    }
    const double z = rng.uniform(0, 1);
    for (int k = 0; k < 3; ++k) {
      glm::vec4 p;
      if (shape == Shape::kClipSpace) {
        // Vertices in front of and behind the camera, with varied w.
        const double wv = rng.uniform(-0.5, 3.0);
        p = glm::vec4(rng.uniform(-2, 2) * std::abs(wv), rng.uniform(-2, 2) * std::abs(wv),
                      rng.uniform(-0.2, 1.2) * wv, wv);
      } else if (shape == Shape::kOnSamples) {
        // Vertices exactly on 4x sample positions, often sharing a row or column with the
        // previous vertex: edges run through samples, which only the fill rule decides.
        static constexpr int kOff[4][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
        const int* o = kOff[rng.next() % 4];
        double x = std::floor(cx + rng.uniform(-r, r)) + 0.5 + o[0] / 16.0;
        double y = std::floor(cy + rng.uniform(-r, r)) + 0.5 + o[1] / 16.0;
        if (k > 0 && (rng.next() % 3) == 0) {
          if (rng.next() & 1)
            x = sc.positions.back().x;
          else
            y = sc.positions.back().y;
        }
        p = glm::vec4(x, y, static_cast<float>(z), 1);
      } else if (shape == Shape::kSliver) {
        const double a = rng.uniform(0, 6.2832);
        const double t = (k == 0) ? -1 : 1;
        const double off = (k == 2) ? rng.uniform(0.3, 3) : 0;
        p = glm::vec4(snap16(cx + t * r * std::cos(a) - off * std::sin(a)),
                      snap16(cy + t * r * std::sin(a) + off * std::cos(a)),
                      static_cast<float>(z + rng.uniform(-0.05, 0.05)), 1);
      } else {
        p = glm::vec4(snap16(cx + rng.uniform(-r, r)), snap16(cy + rng.uniform(-r, r)),
                      static_cast<float>(std::clamp(z + rng.uniform(-0.2, 0.2), 0.0, 1.0)), 1);
      }
      sc.positions.push_back(p);
      if (per_vertex) sc.colors.push_back({rng.byte(), rng.byte(), rng.byte(), rng.byte()});
    }
    if (!per_vertex) sc.colors.push_back({rng.byte(), rng.byte(), rng.byte(), 255});
  }
  if (shape == Shape::kClipSpace) sc.space = mosaic::Space::kClip;
  return sc;
}

using Result = mosaic::test::Captured;

Result render(const TestScene& sc, int w, int h, int samples, Isa isa, int threads,
              mosaic::DrawState state, bool ssaa = false, bool painter = false, int tile_size = 0) {
  mosaic::RenderTarget target(w, h, samples, {true, true});
  target.set_clear({10, 20, 30, 255}, state.depth_test == mosaic::DepthTest::kGreater ? 0.f : 1.f);
  mosaic::Draw d;
  d.space = sc.space;
  d.positions = sc.positions;
  d.color_source = sc.source;
  d.colors = sc.colors;
  d.state = state;
  const mosaic::Draw draws[] = {d};
  mosaic::Frame frame;
  frame.draws = draws;
  frame.ssaa = ssaa;
  frame.painter = painter;
  mosaic::Renderer r({.threads = threads, .isa = isa, .tile_size = tile_size});
  return mosaic::test::capture(r, frame, target);
}

using mosaic::test::simd_isas;

using mosaic::test::expect_same;

struct Case {
  Shape shape;
  int count;
  const char* name;
};

constexpr Case kCases[] = {{Shape::kOnSamples, 400, "on-samples"}, {Shape::kSmall, 600, "small"},
                           {Shape::kTiny, 3000, "tiny"},           {Shape::kLarge, 12, "large"},
                           {Shape::kSliver, 80, "sliver"},         {Shape::kHuge, 10, "huge"},
                           {Shape::kClipSpace, 60, "clip"}};

TEST(FastPath, IdenticalToReferenceEverySimdPathSampleCountAndFillRule) {
  const auto isas = simd_isas();
  ASSERT_FALSE(isas.empty()) << "no SIMD path runs on this CPU";
  const int w = 157, h = 131;  // not a multiple of the tile or block size
  std::uint64_t seed = 1;
  for (const Case& c : kCases) {
    for (int samples : {1, 4, 8, 16}) {
      for (auto rule : {mosaic::FillRule::kD3D, mosaic::FillRule::kOpenGL}) {
        const bool per_vertex = (seed & 1) != 0;
        const TestScene sc = make_scene(c.shape, w, h, c.count, seed++, per_vertex);
        mosaic::DrawState st;
        st.fill_rule = rule;
        const Result ref = render(sc, w, h, samples, Isa::kReference, 1, st);
        for (Isa isa : isas) {
          const Result fast = render(sc, w, h, samples, isa, 2, st);
          expect_same(ref, fast,
                      std::string(c.name) + " " + std::to_string(samples) + "x " +
                          mosaic::to_string(isa) +
                          (rule == mosaic::FillRule::kD3D ? " d3d" : " gl"));
        }
      }
    }
  }
}

TEST(FastPath, IdenticalToReferenceForEveryDepthModeSsaaAndPainter) {
  const int w = 97, h = 75;
  const mosaic::DepthTest tests[] = {mosaic::DepthTest::kLess, mosaic::DepthTest::kLessEqual,
                                     mosaic::DepthTest::kGreater, mosaic::DepthTest::kGreaterEqual,
                                     mosaic::DepthTest::kAlways};
  std::uint64_t seed = 100;
  for (auto test : tests) {
    for (bool write : {true, false}) {
      for (bool ssaa : {false, true}) {
        for (const Shape shape : {Shape::kSmall, Shape::kTiny}) {
          const TestScene sc =
              make_scene(shape, w, h, shape == Shape::kTiny ? 2000 : 300, seed++, true);
          mosaic::DrawState st;
          st.depth_test = test;
          st.depth_write = write;
          const Result ref = render(sc, w, h, 4, Isa::kReference, 1, st, ssaa);
          for (Isa isa : simd_isas())
            expect_same(ref, render(sc, w, h, 4, isa, 2, st, ssaa),
                        std::string(shape == Shape::kTiny ? "tiny" : "small") + " depth mode " +
                            std::to_string(int(test)) + " write " + std::to_string(write) +
                            " ssaa " + std::to_string(ssaa));
        }
      }
    }
  }
  const TestScene sc = make_scene(Shape::kLarge, w, h, 20, 7, false);
  const Result ref = render(sc, w, h, 4, Isa::kReference, 1, {}, false, true);
  for (Isa isa : simd_isas())
    expect_same(ref, render(sc, w, h, 4, isa, 2, {}, false, true), "painter");
}

TEST(FastPath, DeterministicAcrossThreadCounts) {
  const int w = 300, h = 200;
  const TestScene sc = make_scene(Shape::kSmall, w, h, 5000, 42, true);
  for (Isa isa : simd_isas()) {
    const Result one = render(sc, w, h, 4, isa, 1, {});
    for (int threads : {2, 7}) expect_same(one, render(sc, w, h, 4, isa, threads, {}), "threads");
  }
}

TEST(FastPath, LargeTargetWithManyChunksMatchesReference) {
  // More triangles than one front-end chunk, over many tiles, in several draws.
  const int w = 1917, h = 1083;
  const TestScene sc = make_scene(Shape::kSmall, w, h, 6000, 9, false);
  const Result ref = render(sc, w, h, 1, Isa::kReference, 1, {});
  for (Isa isa : simd_isas()) expect_same(ref, render(sc, w, h, 1, isa, 2, {}), "1917x1083");
}

// The tile size (RendererOptions::tile_size) changes the work, never the image: every size on a
// target that none of them divides, for every kind of triangle, sample count and SIMD path.
TEST(FastPath, EveryTileSizeMatchesReference) {
  const int w = 333, h = 201;
  for (const Case& c : {kCases[1], kCases[2], kCases[3], kCases[5]}) {
    const TestScene sc = make_scene(c.shape, w, h, c.count, 17, true);
    for (int samples : {1, 4, 16}) {
      const Result ref = render(sc, w, h, samples, Isa::kReference, 1, {});
      for (Isa isa : simd_isas()) {
        for (int size = mosaic::kMinTileSize; size <= mosaic::kMaxTileSize; size *= 2) {
          SCOPED_TRACE(std::string(c.name) + " " + std::to_string(samples) + "x " +
                       mosaic::to_string(isa) + " tile " + std::to_string(size));
          expect_same(ref, render(sc, w, h, samples, isa, 2, {}, false, false, size), "tile size");
        }
      }
    }
  }
}

// With no tile size given, the renderer picks one by sample count and reports it (for a frame
// whose triangles reach many tiles: see FastPath.FramesInFewTilesAreSplit).
TEST(FastPath, DefaultTileSizeFollowsTheSampleCount) {
  const TestScene sc = make_scene(Shape::kSmall, 1100, 600, 600, 3, false);
  for (int samples : {1, 4, 8, 16}) {
    mosaic::RenderTarget target(1100, 600, samples);
    mosaic::Draw d;
    d.space = sc.space;
    d.positions = sc.positions;
    d.color_source = sc.source;
    d.colors = sc.colors;
    const mosaic::Draw draws[] = {d};
    mosaic::Renderer auto_size;
    EXPECT_EQ(auto_size.render({draws}, target).tile_size, mosaic::default_tile_size(samples));
    EXPECT_EQ(mosaic::default_tile_size(samples), samples <= 4 ? 128 : 64);
    mosaic::Renderer fixed({.tile_size = 16});
    EXPECT_EQ(fixed.render({draws}, target).tile_size, 16);
  }
}

// A frame whose triangles reach fewer than kFewBusyTiles tiles of the automatic size (a mesh far
// away) is binned again on kSplitTileSize tiles, so that its tile work spreads: triangles in 15
// tiles are split, in 16 they are not. The split frame draws what the reference and a renderer
// given 32 px tiles draw, with the same counters and bins, on every ISA and thread count; a
// tile size the caller gives is never split.
TEST(FastPath, FramesInFewTilesAreSplit) {
  namespace t = mosaic::test;
  constexpr int kW = 512, kH = 512;  // 4 × 4 tiles of 128 px, 8 × 8 of 64
  for (const int busy : {mosaic::bin::kFewBusyTiles - 1, mosaic::bin::kFewBusyTiles}) {
    // In tile k of 128 px, two overlapping triangles inside one tile of 32 and of 64 px too, so
    // that every automatic size sees `busy` tiles.
    mosaic::Mesh m = t::screen_mesh();
    for (int k = 0; k < busy; ++k) {
      const double x = 128.0 * (k % 4) + 40, y = 128.0 * (k / 4) + 40;
      const auto c = static_cast<std::uint32_t>(k);
      t::add_tri(m, {x, y}, {x + 20, y + 2}, {x + 4, y + 20}, t::distinct_color(c), 0.6f);
      t::add_tri(m, {x + 1, y + 19}, {x + 3, y + 1}, {x + 19, y + 17}, t::distinct_color(c + 50),
                 0.4f);
    }
    const std::vector<mosaic::Draw> draws{m.draw()};
    const mosaic::Frame frame{.draws = draws};
    // 1x and 4x split 128 px tiles, 16x 64 px ones.
    for (const int samples : {1, 4, 16}) {
      const auto draw = [&](mosaic::RendererOptions options) {
        mosaic::RenderTarget target(kW, kH, samples, mosaic::TargetOptions{true, true});
        mosaic::Renderer r(options);
        return t::capture(r, frame, target);
      };
      const Result ref = draw({.isa = Isa::kReference});
      const int expected =
          busy < mosaic::bin::kFewBusyTiles ? 32 : mosaic::default_tile_size(samples);
      for (const Isa isa : simd_isas()) {
        const std::string what =
            std::to_string(busy) + " tiles " + std::to_string(samples) + "x " + to_string(isa);
        for (const int threads : {1, 2, 7}) {
          const Result split = draw({.threads = threads, .isa = isa});
          EXPECT_EQ(split.stats.tile_size, expected) << what << " " << threads << "T";
          expect_same(ref, split, what + " " + std::to_string(threads) + "T");
        }
        const Result split = draw({.threads = 2, .isa = isa});
        const Result fixed = draw({.threads = 2, .isa = isa, .tile_size = expected});
        EXPECT_EQ(fixed.stats.tile_size, expected) << what;
        EXPECT_EQ(split.stats.triangles_binned, fixed.stats.triangles_binned) << what;
        EXPECT_EQ(split.stats.samples_tested, fixed.stats.samples_tested) << what;
        const Result given = draw({.threads = 2, .isa = isa, .tile_size = 128});
        EXPECT_EQ(given.stats.tile_size, 128) << what;
        expect_same(ref, given, what + " given 128 px");
      }
    }
  }
}

TEST(FastPath, RecordedCostsCoverEveryTileAndChunkAndLeaveTheImageAlone) {
  using namespace mosaic;
  // 5000 triangles: three front-end chunks of 2048; 1917x1083 does not divide into tiles.
  const Scene scene = builtin_scene("random-small", 1917, 1083, 3);
  const std::vector<Draw> draws = scene.draws();
  const Frame frame{draws};
  RenderTarget plain(1917, 1083, 4), costed(1917, 1083, 4);
  Renderer r0(RendererOptions{2, Isa::kAuto, false});
  Renderer r1(RendererOptions{2, Isa::kAuto, true});
  const FrameStats s0 = r0.render(frame, plain);
  const FrameStats s1 = r1.render(frame, costed);
  EXPECT_EQ(plain.image_hash(), costed.image_hash());
  EXPECT_TRUE(s0.tile_costs.empty());
  EXPECT_TRUE(s0.chunk_costs.empty());

  const int tiles_x = (1917 + s1.tile_size - 1) / s1.tile_size;
  const int tiles_y = (1083 + s1.tile_size - 1) / s1.tile_size;
  ASSERT_EQ(s1.tile_costs.size(), static_cast<std::size_t>(tiles_x * tiles_y));
  std::uint64_t binned = 0, pixels = 0;
  for (std::size_t t = 0; t < s1.tile_costs.size(); ++t) {
    const TileCost& c = s1.tile_costs[t];
    EXPECT_EQ(c.x0, static_cast<int>(t % tiles_x) * s1.tile_size);
    EXPECT_EQ(c.y0, static_cast<int>(t / tiles_x) * s1.tile_size);
    EXPECT_GT(c.ms, 0.0);
    binned += c.triangles;
    pixels += static_cast<std::uint64_t>(c.width) * c.height;
  }
  EXPECT_EQ(binned, s1.triangles_binned);
  EXPECT_EQ(pixels, 1917u * 1083u);
  std::uint64_t submitted = 0;
  for (const ChunkCost& c : s1.chunk_costs) {
    submitted += c.triangles;
    EXPECT_GT(c.ms_setup, 0.0);
    EXPECT_GT(c.ms_binning, 0.0);
  }
  EXPECT_EQ(s1.chunk_costs.size(), (scene.triangle_count() + 2047) / 2048);
  EXPECT_EQ(submitted, s1.triangles_in);
}

TEST(FastPath, ManySmallDrawsShareChunksAndMatchReference) {
  using namespace mosaic;
  // 6000 small triangles as draws of 0 to 3000 triangles with four depth and colour states: the
  // chunks cut across draws, and every tile's runs must still take each draw's own state.
  const int w = 700, h = 500;
  const TestScene sc = make_scene(Shape::kSmall, w, h, 6000, 17, false);
  const DrawState kStates[] = {{},
                               {.depth_test = DepthTest::kLessEqual},
                               {.depth_test = DepthTest::kAlways, .depth_write = false},
                               {.color_write = false}};
  static constexpr std::uint32_t kSizes[] = {1, 0, 7, 3000, 2, 1, 2047, 2049, 1};
  std::vector<Draw> draws;
  for (std::uint32_t t = 0, k = 0; t < 6000; ++k) {
    const std::uint32_t n = std::min<std::uint32_t>(kSizes[k % std::size(kSizes)], 6000 - t);
    Draw d;
    d.space = Space::kScreen;
    d.positions = std::span<const glm::vec4>(sc.positions).subspan(3 * t, 3 * n);
    d.color_source = ColorSource::kPerTriangle;
    d.colors = std::span<const Rgba8>(sc.colors).subspan(t, n);
    d.state = kStates[k % std::size(kStates)];
    draws.push_back(d);
    t += n;
  }
  auto run = [&](Isa isa, int threads, std::span<const Draw> frame_draws) {
    RenderTarget target(w, h, 4, {true, true});
    target.set_clear({10, 20, 30, 255});
    Renderer r({.threads = threads, .isa = isa, .record_costs = true});
    return test::capture(r, Frame{frame_draws}, target);
  };
  const Result ref = run(Isa::kReference, 1, draws);
  for (Isa isa : simd_isas())
    for (int threads : {1, 2, 7}) {
      const Result fast = run(isa, threads, draws);
      expect_same(ref, fast, std::string(to_string(isa)) + " " + std::to_string(threads));
      // The chunks are as many as for one draw of the same triangles, not one per draw.
      EXPECT_EQ(fast.stats.chunk_costs.size(), (6000u + 2047) / 2048);
    }
  // One draw per triangle with one state gives what one draw of them all gives.
  std::vector<Draw> single(6000), whole(1);
  for (std::uint32_t t = 0; t < 6000; ++t) {
    single[t].space = Space::kScreen;
    single[t].positions = std::span<const glm::vec4>(sc.positions).subspan(3 * t, 3);
    single[t].color_source = ColorSource::kPerTriangle;
    single[t].colors = std::span<const Rgba8>(sc.colors).subspan(t, 1);
  }
  whole[0] = single[0];
  whole[0].positions = sc.positions;
  whole[0].colors = sc.colors;
  expect_same(run(Isa::kAuto, 2, whole), run(Isa::kAuto, 2, single), "one draw per triangle");
}

}  // namespace

// --- What a frame uses: depth-only draws and frames, frames without depth, hierarchical z ---

namespace {

/// One frame of several draws of `sc`'s triangles (draw i takes every draws-th triangle, so
/// that the draws interleave in space), each with its own state.
struct MultiResult {
  Result r;
  std::vector<float> hiz_min, hiz_max;
};

// How render_draws renders besides its ISA: threads, tile size (0: the renderer's choice) and
// Frame::occluders_nearest_first.
struct RenderWith {
  int threads = 2;
  int tile_size = 0;
  bool nearest_first = false;
};

MultiResult render_draws(const TestScene& sc, int w, int h, int samples, Isa isa,
                         std::span<const mosaic::DrawState> states, mosaic::TargetOptions keep,
                         bool ssaa, mosaic::Rgba8 clear = {10, 20, 30, 255},
                         float clear_depth = 1.0f, mosaic::RenderTarget* reuse = nullptr,
                         RenderWith with = {}) {
  const std::size_t n = states.size();
  std::vector<std::vector<std::uint32_t>> indices(n);
  const std::size_t tris = sc.positions.size() / 3;
  for (std::size_t t = 0; t < tris; ++t)
    for (std::uint32_t k = 0; k < 3; ++k)
      indices[t % n].push_back(static_cast<std::uint32_t>(3 * t) + k);
  // Per-vertex colours are shared by the indexed draws; per-triangle ones are not, so a
  // per-triangle scene is drawn with the first triangle colour of each draw, constant.
  std::vector<mosaic::Draw> draws(n);
  for (std::size_t i = 0; i < n; ++i) {
    mosaic::Draw& d = draws[i];
    d.space = sc.space;
    d.positions = sc.positions;
    d.indices = indices[i];
    if (sc.source == mosaic::ColorSource::kPerVertex) {
      d.color_source = mosaic::ColorSource::kPerVertex;
      d.colors = sc.colors;
    } else {
      d.color_source = mosaic::ColorSource::kConstant;
      d.color = sc.colors[i % sc.colors.size()];
    }
    d.state = states[i];
  }
  mosaic::RenderTarget own(w, h, samples, keep);
  mosaic::RenderTarget& target = reuse ? *reuse : own;
  target.set_clear(clear, clear_depth);
  mosaic::Frame frame;
  frame.draws = draws;
  frame.ssaa = ssaa;
  frame.keep_hierarchical_z = true;
  frame.occluders_nearest_first = with.nearest_first;
  mosaic::Renderer r({.threads = with.threads, .isa = isa, .tile_size = with.tile_size});
  MultiResult out;
  out.r = mosaic::test::capture(r, frame, target);
  const mosaic::HierarchicalZ& hz = r.hierarchical_z();
  EXPECT_EQ(hz.width(), w);
  EXPECT_EQ(hz.height(), h);
  out.hiz_min.assign(hz.zmin().begin(), hz.zmin().end());
  out.hiz_max.assign(hz.zmax().begin(), hz.zmax().end());
  return out;
}

/// The same comparison as expect_same, plus the hierarchical z (compared as values: the bounds
/// are a min and a max of the same floats, and -0 may stand for +0).
void expect_same_hiz(const MultiResult& ref, const MultiResult& fast, const std::string& what) {
  ASSERT_EQ(ref.hiz_min.size(), fast.hiz_min.size()) << what;
  std::size_t bad = 0;
  for (std::size_t i = 0; i < ref.hiz_min.size(); ++i)
    bad += !(ref.hiz_min[i] == fast.hiz_min[i]) + !(ref.hiz_max[i] == fast.hiz_max[i]);
  EXPECT_EQ(bad, 0u) << what << ": hierarchical z";
}

void expect_same_multi(const MultiResult& ref, const MultiResult& fast, const std::string& what) {
  expect_same(ref.r, fast.r, what);
  expect_same_hiz(ref, fast, what);
}

}  // namespace

TEST(FastPath, DepthOnlyDrawsAmongColourDrawsMatchReference) {
  // Depth-only draws (every depth mode) interleaved with colour draws: the depth-only ones must
  // change depth exactly as the reference does and leave colour alone.
  const int w = 157, h = 131;
  const mosaic::DepthTest tests[] = {mosaic::DepthTest::kLess, mosaic::DepthTest::kLessEqual,
                                     mosaic::DepthTest::kGreater, mosaic::DepthTest::kGreaterEqual,
                                     mosaic::DepthTest::kAlways};
  std::uint64_t seed = 300;
  for (auto test : tests) {
    for (int samples : {1, 4, 16}) {
      for (bool ssaa : {false, true}) {
        const bool per_vertex = (seed & 1) != 0;
        const TestScene sc = make_scene(Shape::kSmall, w, h, 500, seed++, per_vertex);
        std::vector<mosaic::DrawState> states(3);
        for (std::size_t i = 0; i < states.size(); ++i) {
          states[i].depth_test = test;
          states[i].depth_write = i != 2;
          states[i].color_write = i != 1;
        }
        const float cd =
            test == mosaic::DepthTest::kGreater || test == mosaic::DepthTest::kGreaterEqual ? 0.f
                                                                                            : 1.f;
        const MultiResult ref = render_draws(sc, w, h, samples, Isa::kReference, states,
                                             {true, true}, ssaa, {10, 20, 30, 255}, cd);
        for (Isa isa : simd_isas())
          expect_same_multi(ref,
                            render_draws(sc, w, h, samples, isa, states, {true, true}, ssaa,
                                         {10, 20, 30, 255}, cd),
                            "mixed depth-only test " + std::to_string(int(test)) + " " +
                                std::to_string(samples) + "x ssaa " + std::to_string(ssaa) + " " +
                                mosaic::to_string(isa));
      }
    }
  }
}

TEST(FastPath, DepthOnlyFrameKeepsNoColourAndMatchesReference) {
  // Every draw depth-only and no sample colour kept: the tiles keep no colour at all. The image
  // must still be the clear colour (as the reference's box filter of untouched samples), depth
  // and the hierarchical z exact, including after a colour frame into the same target.
  const int w = 157, h = 131;
  std::uint64_t seed = 400;
  for (int samples : {1, 4, 8}) {
    for (Shape shape : {Shape::kSmall, Shape::kLarge, Shape::kClipSpace}) {
      const TestScene sc = make_scene(shape, w, h, shape == Shape::kLarge ? 20 : 300, seed++, true);
      std::vector<mosaic::DrawState> states(2);
      states[0].color_write = states[1].color_write = false;
      states[1].depth_test = mosaic::DepthTest::kLessEqual;
      const mosaic::TargetOptions depth_only{true, false};
      const MultiResult ref =
          render_draws(sc, w, h, samples, Isa::kReference, states, depth_only, false);
      for (const mosaic::Rgba8& c : ref.r.color) ASSERT_EQ(c, (mosaic::Rgba8{10, 20, 30, 255}));
      for (Isa isa : simd_isas()) {
        const std::string what =
            "depth-only frame " + std::to_string(samples) + "x " + mosaic::to_string(isa);
        expect_same_multi(ref, render_draws(sc, w, h, samples, isa, states, depth_only, false),
                          what);
        // A colour frame, then the depth-only frame into the same target with another clear
        // colour, then once more with that colour (the image is already right: no rewrite).
        mosaic::RenderTarget target(w, h, samples, depth_only);
        const std::vector<mosaic::DrawState> colour(2);
        render_draws(sc, w, h, samples, isa, colour, depth_only, false, {10, 20, 30, 255}, 1.f,
                     &target);
        for (int pass = 0; pass < 2; ++pass) {
          const MultiResult again = render_draws(sc, w, h, samples, isa, states, depth_only, false,
                                                 {1, 2, 3, 4}, 1.f, &target);
          std::size_t bad = 0;
          for (const mosaic::Rgba8& c : again.r.color) bad += !(c == mosaic::Rgba8{1, 2, 3, 4});
          EXPECT_EQ(bad, 0u) << what << " after a colour frame, pass " << pass;
          EXPECT_EQ(again.r.sample_depth, ref.r.sample_depth) << what;
        }
      }
    }
  }
}

TEST(FastPath, FrameWithoutDepthMatchesReference) {
  // No draw tests or writes depth (kAlways without writes, and the painter's algorithm): the tile
  // keeps no depth; kept sample depth and the hierarchical z hold the clear depth.
  const int w = 157, h = 131;
  const TestScene sc = make_scene(Shape::kSmall, w, h, 400, 500, true);
  std::vector<mosaic::DrawState> states(2);
  for (mosaic::DrawState& s : states) {
    s.depth_test = mosaic::DepthTest::kAlways;
    s.depth_write = false;
  }
  for (int samples : {1, 4}) {
    const MultiResult ref =
        render_draws(sc, w, h, samples, Isa::kReference, states, {true, true}, false);
    for (float z : ref.r.sample_depth) ASSERT_EQ(z, 1.0f);
    for (Isa isa : simd_isas())
      expect_same_multi(ref, render_draws(sc, w, h, samples, isa, states, {true, true}, false),
                        "no depth " + std::to_string(samples) + "x " + mosaic::to_string(isa));
  }
}

// A right triangle with legs w and h px from (x, y), at depth z (rising to the right).
void add_right_triangle(TestScene& sc, float x, float y, float w, float h, float z) {
  for (const glm::vec4& p :
       {glm::vec4(x, y, z, 1), glm::vec4(x + w, y, z + 0.1f, 1), glm::vec4(x, y + h, z, 1)}) {
    sc.positions.push_back(p);
    sc.colors.push_back({200, 100, 50, 255});
  }
}

// A depth-only draw leaves a block that one triangle covers whole and wins as that triangle's
// depth plane, and writes its samples only when something reads them: a later triangle of any
// size that tests or partly covers the block, a colour draw, or the end of the tile. Large
// triangles over small, tiny and thin ones, in every depth test, sample count and tile size, with
// right triangles just holding an 8×8 block and just not (legs of 16 and 15 px): depth, image,
// counters and hierarchical z as the reference's.
TEST(FastPath, DepthPlanesOfWholeBlocksMatchReference) {
  const int w = 157, h = 131;
  TestScene sc;
  const auto add = [&sc](const TestScene& more) {
    sc.positions.insert(sc.positions.end(), more.positions.begin(), more.positions.end());
    sc.colors.insert(sc.colors.end(), more.colors.begin(), more.colors.end());
  };
  // Interleaved so that every draw of render_draws() gets large and small triangles in turn.
  for (std::uint64_t seed = 600; seed < 606; ++seed) {
    add(make_scene(Shape::kLarge, w, h, 3, seed, true));
    add(make_scene(Shape::kSmall, w, h, 40, seed, true));
    add(make_scene(Shape::kTiny, w, h, 60, seed, true));
    add(make_scene(Shape::kSliver, w, h, 8, seed, true));
  }
  for (float legs : {16.f, 15.f})
    for (float z : {0.9f, 0.1f}) add_right_triangle(sc, 40, 24, legs, legs, z);
  const mosaic::DepthTest tests[] = {mosaic::DepthTest::kLess, mosaic::DepthTest::kLessEqual,
                                     mosaic::DepthTest::kGreater, mosaic::DepthTest::kGreaterEqual,
                                     mosaic::DepthTest::kAlways};
  for (auto test : tests) {
    // Depth-only writes, a depth-only test without writes, a colour draw, depth-only again.
    std::vector<mosaic::DrawState> states(4);
    for (std::size_t i = 0; i < states.size(); ++i) {
      states[i].depth_test = test;
      states[i].color_write = i == 2;
      states[i].depth_write = i != 1;
    }
    const bool reversed =
        test == mosaic::DepthTest::kGreater || test == mosaic::DepthTest::kGreaterEqual;
    const float cd = reversed ? 0.f : 1.f;
    for (int samples : {1, 4, 16}) {
      const MultiResult ref = render_draws(sc, w, h, samples, Isa::kReference, states, {true, true},
                                           false, {10, 20, 30, 255}, cd);
      for (Isa isa : simd_isas())
        for (int tile : {0, 16})
          expect_same_multi(ref,
                            render_draws(sc, w, h, samples, isa, states, {true, true}, false,
                                         {10, 20, 30, 255}, cd, nullptr, {2, tile, false}),
                            "depth planes, test " + std::to_string(int(test)) + " " +
                                std::to_string(samples) + "x tile " + std::to_string(tile) + " " +
                                mosaic::to_string(isa));
    }
  }
}

// A grid of cell × cell px squares, two triangles each, over [x0, x0 + n·cell)², at depth z: a
// surface of small triangles, none of which covers an 8×8 block, every sample covered once.
void add_grid(TestScene& sc, double x0, int n, double cell, float z, mosaic::Rgba8 color) {
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const auto v = [&](int di, int dj) {
        return glm::vec4(static_cast<float>(x0 + (i + di) * cell),
                         static_cast<float>(x0 + (j + dj) * cell), z, 1);
      };
      for (const glm::vec4& p : {v(0, 0), v(1, 0), v(1, 1), v(0, 0), v(1, 1), v(0, 1)}) {
        sc.positions.push_back(p);
        sc.colors.push_back(color);
      }
    }
  }
}

// Hierarchical z tightens from many small triangles: once a surface of 2–3 px triangles has
// filled a block, a surface behind it is rejected block by block, though no single triangle ever
// covered a block. Drawn the other way round nothing is hidden and nothing is rejected. The
// image, depth and counters match the reference, and the rejections are the same on every path.
TEST(FastPath, HierarchicalZTightensFromManySmallTriangles) {
  const int w = 96, h = 80;
  // The near surface covers [4, 76)² (blocks 1..8 whole on both axes), the far one [6, 72)².
  TestScene near_first, far_first;
  near_first.source = far_first.source = mosaic::ColorSource::kPerVertex;
  add_grid(near_first, 4, 36, 2.0, 0.25f, {200, 40, 40, 255});
  add_grid(near_first, 6, 22, 3.0, 0.75f, {40, 200, 40, 255});
  add_grid(far_first, 6, 22, 3.0, 0.75f, {40, 200, 40, 255});
  add_grid(far_first, 4, 36, 2.0, 0.25f, {200, 40, 40, 255});
  const mosaic::DrawState state;  // less, depth write on
  for (int samples : {1, 4, 16}) {
    const Result ref_near = render(near_first, w, h, samples, Isa::kReference, 1, state);
    const Result ref_far = render(far_first, w, h, samples, Isa::kReference, 1, state);
    std::uint64_t rejected = 0;
    for (Isa isa : simd_isas()) {
      const std::string what = std::to_string(samples) + "x " + mosaic::to_string(isa);
      const Result fast = render(near_first, w, h, samples, isa, 1, state);
      expect_same(ref_near, fast, "near first " + what);
      if (rejected == 0) rejected = fast.stats.blocks_hiz_rejected;
      EXPECT_EQ(fast.stats.blocks_hiz_rejected, rejected) << what;
      EXPECT_EQ(render(near_first, w, h, samples, isa, 2, state).color, fast.color) << what;
      const Result behind = render(far_first, w, h, samples, isa, 1, state);
      expect_same(ref_far, behind, "far first " + what);
      // Far first, hierarchical z rejects only boxes that meet a block where their triangle
      // covers nothing. Near first, it also rejects the far surface in the blocks the near one
      // has filled: blocks 1..8 of both axes hold far triangles (64 blocks), each met by several.
      EXPECT_GE(fast.stats.blocks_hiz_rejected, behind.stats.blocks_hiz_rejected + 64) << what;
      EXPECT_LT(fast.stats.samples_tested, behind.stats.samples_tested) << what;
      // Both orders draw the same picture: the near surface wherever it is.
      EXPECT_EQ(behind.color, fast.color) << what;
    }
  }
}

// Rows of three or more blocks are classified by hierarchical z in SIMD lanes, narrower ones
// block by block. Large triangles at random depths under heavy overdraw, so that blocks are
// rejected, accepted and tested, in every depth test: a draw that writes depth, one that only
// tests it, and a colour draw over them. Tiles of 8 to 128 px make rows of 1 to 16 blocks, the
// image's last blocks are partial, and a scissor cuts blocks and rows. Image, depth, samples
// written and hierarchical z as the reference's; its counters the same on every path and thread
// count.
TEST(FastPath, HierarchicalZRowsInSimdLanesMatchReference) {
  const int w = 157, h = 131;
  const mosaic::DepthTest tests[] = {mosaic::DepthTest::kLess, mosaic::DepthTest::kLessEqual,
                                     mosaic::DepthTest::kGreater, mosaic::DepthTest::kGreaterEqual,
                                     mosaic::DepthTest::kAlways};
  std::uint64_t seed = 700;
  for (const mosaic::DepthTest test : tests) {
    const TestScene sc = make_scene(Shape::kLarge, w, h, 60, seed++, true);
    const bool greater =
        test == mosaic::DepthTest::kGreater || test == mosaic::DepthTest::kGreaterEqual;
    std::vector<mosaic::DrawState> states(3);
    for (mosaic::DrawState& s : states) s.depth_test = test;
    states[0].color_write = false;
    states[1].color_write = false;
    states[1].depth_write = false;
    std::uint64_t rejected_wide = 0, accepted_wide = 0;
    for (const bool scissored : {false, true}) {
      for (mosaic::DrawState& s : states)
        s.scissor = scissored ? std::optional<mosaic::PixelRect>({13, 9, 121, 97}) : std::nullopt;
      for (const int samples : {1, 4}) {
        const MultiResult ref =
            render_draws(sc, w, h, samples, Isa::kReference, states, {true, true}, false,
                         {10, 20, 30, 255}, greater ? 0.0f : 1.0f);
        for (const int tile : {8, 16, 32, 64, 128}) {
          bool first = true;
          std::uint64_t rejected = 0, accepted = 0;
          for (Isa isa : simd_isas()) {
            for (const int threads : {1, 2}) {
              const std::string what = "depth test " + std::to_string(static_cast<int>(test)) +
                                       ", " + std::to_string(samples) + "x, tile " +
                                       std::to_string(tile) + (scissored ? ", scissor, " : ", ") +
                                       mosaic::to_string(isa) + ", " + std::to_string(threads);
              const MultiResult fast = render_draws(
                  sc, w, h, samples, isa, states, {true, true}, false, {10, 20, 30, 255},
                  greater ? 0.0f : 1.0f, nullptr, {.threads = threads, .tile_size = tile});
              expect_same_multi(ref, fast, what);
              if (first) {
                rejected = fast.r.stats.blocks_hiz_rejected;
                accepted = fast.r.stats.blocks_hiz_accepted;
                first = false;
              }
              EXPECT_EQ(fast.r.stats.blocks_hiz_rejected, rejected) << what;
              EXPECT_EQ(fast.r.stats.blocks_hiz_accepted, accepted) << what;
            }
          }
          if (tile >= 32) {
            rejected_wide += rejected;
            accepted_wide += accepted;
          }
        }
      }
    }
    // Wide rows saw every answer (none for kAlways, which tests nothing).
    const bool always = test == mosaic::DepthTest::kAlways;
    EXPECT_EQ(rejected_wide > 0, !always) << "depth test " << static_cast<int>(test);
    EXPECT_EQ(accepted_wide > 0, !always) << "depth test " << static_cast<int>(test);
  }
}

// A triangle hidden behind a whole tile is dropped before its blocks are visited, and its
// rejected blocks are counted from the tile's block rectangles: every block its box meets that
// holds pixels of the image and of the draw's scissor. The image's last blocks are partial, and
// the tiles (8 to 128 px) cut the scissor on and between block edges.
TEST(FastPath, HiddenTileCountsTheBlocksInsideImageAndScissor) {
  const int w = 157, h = 131;
  const int blocks_x = (w + 7) / 8, blocks_y = (h + 7) / 8;  // 20 × 17, partial at the edges
  mosaic::Draw far;
  far.space = mosaic::Space::kScreen;
  far.color_source = mosaic::ColorSource::kPerTriangle;
  // One triangle over the whole image, so that every tile bins it.
  const float z = 0.75f;
  const std::vector<glm::vec4> positions = {
      {-4, -4, z, 1}, {2 * w + 8.0f, -4, z, 1}, {-4, 2 * h + 8.0f, z, 1}};
  const std::vector<mosaic::Rgba8> colors = {{200, 40, 40, 255}};
  far.positions = positions;
  far.colors = colors;
  // The scissor [13, 61) × [5, 70) meets block columns 1..7 and rows 0..8.
  const mosaic::PixelRect scissor{13, 5, 48, 65};
  for (bool scissored : {false, true}) {
    far.state.scissor = scissored ? std::optional<mosaic::PixelRect>(scissor) : std::nullopt;
    const std::uint64_t blocks = scissored ? 7 * 9 : std::uint64_t{blocks_x} * blocks_y;
    for (Isa isa : simd_isas()) {
      for (int tile : {8, 16, 32, 128}) {
        const std::string what = std::string(mosaic::to_string(isa)) + ", tile " +
                                 std::to_string(tile) + (scissored ? ", scissor" : "");
        // The clear depth is nearer than the triangle: every tile hides it.
        mosaic::RenderTarget target(w, h, 4, {true, true});
        target.set_clear({10, 20, 30, 255}, 0.25f);
        const mosaic::Draw draws[] = {far};
        mosaic::Frame frame;
        frame.draws = draws;
        mosaic::Renderer r({.threads = 2, .isa = isa, .tile_size = tile});
        const Result fast = mosaic::test::capture(r, frame, target);
        EXPECT_EQ(fast.stats.blocks_hiz_rejected, blocks) << what;
        EXPECT_EQ(fast.stats.samples_tested, 0u) << what;
        mosaic::Renderer ref({.threads = 1, .isa = Isa::kReference});
        expect_same(mosaic::test::capture(ref, frame, target), fast, what);
      }
    }
  }
}

TEST(FastPath, HierarchicalZIsExactOnEveryPathAndEmptyWhenNotAsked) {
  const int w = 157, h = 131;  // partial blocks on the right and at the bottom
  for (Shape shape : {Shape::kSmall, Shape::kLarge, Shape::kHuge}) {
    const TestScene sc = make_scene(shape, w, h, shape == Shape::kSmall ? 800 : 15, 600, false);
    const std::vector<mosaic::DrawState> states(1);
    for (int samples : {1, 4, 16}) {
      const MultiResult ref =
          render_draws(sc, w, h, samples, Isa::kReference, states, {true, false}, false);
      // The reference's bounds, checked against its own samples: every sample inside them,
      // and each bound reached by some sample of its block.
      const int bw = (w + 7) / 8;
      ASSERT_EQ(ref.hiz_min.size(), static_cast<std::size_t>(bw * ((h + 7) / 8)));
      std::vector<int> reached(ref.hiz_min.size(), 0);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int s = 0; s < samples; ++s) {
            const float z = ref.r.sample_depth[(static_cast<std::size_t>(y) * w + x) * samples + s];
            const std::size_t b = static_cast<std::size_t>(y / 8) * bw + x / 8;
            ASSERT_GE(z, ref.hiz_min[b]);
            ASSERT_LE(z, ref.hiz_max[b]);
            reached[b] |= (z == ref.hiz_min[b] ? 1 : 0) | (z == ref.hiz_max[b] ? 2 : 0);
          }
      for (int r : reached) ASSERT_EQ(r, 3);
      for (Isa isa : simd_isas())
        expect_same_multi(ref, render_draws(sc, w, h, samples, isa, states, {true, false}, false),
                          "hi-z " + std::to_string(samples) + "x " + mosaic::to_string(isa));
    }
  }
  mosaic::RenderTarget target(16, 16);
  mosaic::Renderer r({1});
  r.render({}, target);
  EXPECT_TRUE(r.hierarchical_z().empty());
}

// A tile that no triangle reaches writes the clear values to the outputs without clearing and
// resolving its samples. After a frame that left other values everywhere, a frame reaching a few
// tiles: empty tiles (partial ones at the right and bottom edges too), a tile holding one small
// triangle, tiles a long sliver's box reaches, and a depth-only frame (whose image the tiles
// leave alone). Its image (in RGBA and in a BGRA view), sample colour and depth and hierarchical
// z equal the reference's.
TEST(FastPath, TilesNoTriangleReachesHoldTheClearValues) {
  const int w = 150, h = 70;  // 32 px tiles: a column 22 px wide and a row 6 px high
  const mosaic::Rgba8 clear{10, 20, 200, 77};
  const float clear_depth = 0.625f;
  mosaic::test::Rng rng(4242);
  const std::vector<mosaic::Mesh> full = mosaic::test::random_draws(w, h, 2, 200, rng);
  mosaic::Mesh sparse = mosaic::test::screen_mesh();
  mosaic::test::add_tri(sparse, {40.2, 40.2}, {41.9, 40.3}, {40.3, 41.8}, {90, 80, 70, 255}, 0.25f);
  mosaic::test::add_tri(sparse, {3.0, 60.0}, {140.0, 66.0}, {140.0, 66.1}, {1, 200, 3, 255}, 0.5f);
  mosaic::Mesh sparse_depth = sparse;
  sparse_depth.state.color_write = false;
  struct Out {
    std::vector<mosaic::Rgba8> image, sample_color, bgra;
    std::vector<float> sample_depth, hiz_min, hiz_max;
  };
  auto run = [&](Isa isa, int samples, bool ssaa, int threads, int tile_size,
                 const mosaic::Mesh& second) {
    mosaic::Renderer r({.threads = threads, .isa = isa, .tile_size = tile_size});
    mosaic::RenderTarget owned(w, h, samples, mosaic::TargetOptions{true, true});
    std::vector<std::uint8_t> bgra(4u * w * h);
    mosaic::RenderTarget view(w, h, samples,
                              mosaic::ColorView{bgra.data(), 4u * w, mosaic::PixelFormat::kBgra8});
    Out out;
    for (mosaic::RenderTarget* target : {&owned, &view}) {
      target->set_clear(clear, clear_depth);
      for (const std::vector<mosaic::Mesh>& meshes : {full, std::vector<mosaic::Mesh>{second}}) {
        const std::vector<mosaic::Draw> draws = mosaic::test::draws_of(meshes);
        mosaic::Frame frame;
        frame.draws = draws;
        frame.ssaa = ssaa;
        frame.keep_hierarchical_z = true;
        r.render(frame, *target);
      }
      if (target == &owned) {
        out.image.assign(owned.color().begin(), owned.color().end());
        out.sample_color.assign(owned.sample_color().begin(), owned.sample_color().end());
        out.sample_depth.assign(owned.sample_depth().begin(), owned.sample_depth().end());
        out.hiz_min.assign(r.hierarchical_z().zmin().begin(), r.hierarchical_z().zmin().end());
        out.hiz_max.assign(r.hierarchical_z().zmax().begin(), r.hierarchical_z().zmax().end());
      }
    }
    for (std::size_t i = 0; i < bgra.size(); i += 4)
      out.bgra.push_back({bgra[i + 2], bgra[i + 1], bgra[i], bgra[i + 3]});
    return out;
  };
  for (const mosaic::Mesh* second : {&sparse, &sparse_depth})
    for (auto [samples, ssaa] : {std::pair{1, false}, {4, false}, {4, true}, {16, false}}) {
      const Out ref = run(Isa::kReference, samples, ssaa, 1, 0, *second);
      // The frame reaches few tiles, and the empty ones hold the clear values.
      EXPECT_EQ(ref.image.front(), clear);
      EXPECT_EQ(ref.hiz_max.front(), clear_depth);
      for (Isa isa : simd_isas())
        for (int threads : {1, 2, 7})
          for (int tile_size : {8, 32}) {
            const std::string what =
                std::string(mosaic::to_string(isa)) + " " + std::to_string(samples) +
                (ssaa ? "x ssaa " : "x ") + std::to_string(threads) + " threads, tile " +
                std::to_string(tile_size) + (second == &sparse ? "" : ", depth-only");
            const Out fast = run(isa, samples, ssaa, threads, tile_size, *second);
            ASSERT_EQ(fast.sample_depth.size(), ref.sample_depth.size()) << what;
            EXPECT_TRUE(fast.image == ref.image) << what;
            EXPECT_TRUE(fast.bgra == ref.image) << what << ": BGRA view";
            EXPECT_TRUE(fast.sample_color == ref.sample_color) << what;
            EXPECT_EQ(std::memcmp(fast.sample_depth.data(), ref.sample_depth.data(),
                                  sizeof(float) * ref.sample_depth.size()),
                      0)
                << what;
            EXPECT_TRUE(fast.hiz_min == ref.hiz_min && fast.hiz_max == ref.hiz_max) << what;
          }
    }
}

namespace {

// The frame of scene `s` (the knot at 100 px), flat or lit, with `threads` workers.
mosaic::FrameStats knot_frame(const mosaic::Scene& s, mosaic::Isa isa, int threads,
                              mosaic::Shading shading) {
  mosaic::Renderer renderer({threads, isa});
  mosaic::RenderTarget target(s.width, s.height, 4);
  target.set_clear(s.clear_color, s.clear_depth);
  const std::vector<mosaic::Draw> draws = s.draws(shading);
  return renderer.render(mosaic::Frame{draws}, target);
}

}  // namespace

// The frame's memory counters say what its vertex records, setups, planes and bins hold: the
// same for every thread count, exactly what the frame's counts imply, and nothing for the
// reference, which keeps no memory.
TEST(FrameMemory, CountsWhatTheFrameFilled) {
  const mosaic::Scene s = mosaic::builtin_scene("knot-100px", 160, 128);
  const std::size_t vertices = s.meshes[0].positions.size();
  const mosaic::FrameStats ref = knot_frame(s, Isa::kReference, 1, mosaic::Shading::kFlat);
  EXPECT_EQ(ref.memory.total(), 0u);
  for (const Isa isa : simd_isas())
    for (const mosaic::Shading shading : {mosaic::Shading::kFlat, mosaic::Shading::kLambert}) {
      const mosaic::FrameStats a = knot_frame(s, isa, 1, shading);
      const std::string what =
          std::string(to_string(isa)) + (shading == mosaic::Shading::kFlat ? " flat" : " lit");
      // The knot's indices outnumber its vertices: each is projected once, into 32 bytes.
      EXPECT_EQ(a.memory.vertices, 32u * vertices) << what;
      // 128 bytes a setup, for the triangles drawn and those the binner found no sample in.
      EXPECT_EQ(a.memory.setups % 128, 0u) << what;
      EXPECT_GE(a.memory.setups, 128u * a.triangles_drawn) << what;
      EXPECT_LE(a.memory.setups, 128u * (a.triangles_drawn + a.triangles_no_sample)) << what;
      // Per (triangle, tile) pair, a 4-byte index and the 8-byte pair it was sorted from; per
      // chunk of 2048 triangles, a 4-byte slot per tile of the grid and, per tile it reached,
      // the tile and its bin's start, and one more start.
      const std::uint64_t chunks = (a.triangles_in + 2047) / 2048;
      const std::uint64_t tiles = std::uint64_t{(160u + a.tile_size - 1) / a.tile_size} *
                                  ((128u + a.tile_size - 1) / a.tile_size);
      EXPECT_GE(a.memory.bins, 12u * a.triangles_binned + 4u * chunks * (tiles + 1)) << what;
      EXPECT_LE(a.memory.bins, 12u * a.triangles_binned + 4u * chunks * (3 * tiles + 1)) << what;
      // Interpolated colours (the knot's vertex colours) or varyings (the normals) have planes.
      EXPECT_GT(a.memory.planes, 0u) << what;
      for (const int threads : {2, 7}) {
        const mosaic::FrameStats b = knot_frame(s, isa, threads, shading);
        EXPECT_EQ(b.memory.vertices, a.memory.vertices) << what << ", " << threads;
        EXPECT_EQ(b.memory.setups, a.memory.setups) << what << ", " << threads;
        EXPECT_EQ(b.memory.planes, a.memory.planes) << what << ", " << threads;
        EXPECT_EQ(b.memory.bins, a.memory.bins) << what << ", " << threads;
      }
    }
}

namespace {

// Depth-only occluders (two draws), then a colour draw, into one target; the sort of
// Frame::occluders_nearest_first applies to the first two.
MultiResult render_occluders(const TestScene& sc, int w, int h, int samples, mosaic::DepthTest test,
                             Isa isa, int threads, bool nearest_first) {
  const float clear_depth =
      test == mosaic::DepthTest::kGreater || test == mosaic::DepthTest::kGreaterEqual ? 0.f : 1.f;
  std::vector<mosaic::DrawState> states(3);
  for (std::size_t i = 0; i < states.size(); ++i) {
    states[i].depth_test = test;
    states[i].color_write = i == 2;
  }
  return render_draws(sc, w, h, samples, isa, states, {true, true}, false, {10, 20, 30, 255},
                      clear_depth, nullptr, {threads, 32, nearest_first});
}

}  // namespace

// Occluders drawn nearest first leave every sample the depth, colour and hierarchical z of
// submission order (and of the reference), for each test direction, on every SIMD path and
// thread count; on overlapping large triangles they test fewer samples, and the counts do not
// depend on the thread count. Small triangles overlap too little to be sorted: same counters.
TEST(FastPath, OccludersNearestFirstKeepTheDepthOfSubmissionOrder) {
  const int w = 157, h = 131;
  std::uint64_t seed = 900;
  for (Shape shape : {Shape::kLarge, Shape::kSmall}) {
    for (mosaic::DepthTest test : {mosaic::DepthTest::kLess, mosaic::DepthTest::kLessEqual,
                                   mosaic::DepthTest::kGreater, mosaic::DepthTest::kGreaterEqual}) {
      const TestScene sc = make_scene(shape, w, h, shape == Shape::kLarge ? 60 : 600, seed++, true);
      for (int samples : {1, 4}) {
        const MultiResult ref =
            render_occluders(sc, w, h, samples, test, Isa::kReference, 1, false);
        for (Isa isa : simd_isas()) {
          const MultiResult in_order = render_occluders(sc, w, h, samples, test, isa, 2, false);
          std::uint64_t tested = 0;
          for (int threads : {1, 2, 7}) {
            const std::string what = std::string(shape == Shape::kLarge ? "large" : "small") +
                                     " test " + std::to_string(int(test)) + " " +
                                     std::to_string(samples) + "x " + mosaic::to_string(isa) + " " +
                                     std::to_string(threads) + "T";
            const MultiResult sorted =
                render_occluders(sc, w, h, samples, test, isa, threads, true);
            mosaic::test::expect_same_buffers(ref.r, sorted.r, what);
            expect_same_hiz(ref, sorted, what);
            if (threads == 1) tested = sorted.r.stats.samples_tested;
            EXPECT_EQ(sorted.r.stats.samples_tested, tested) << what;
            if (shape == Shape::kLarge)
              EXPECT_LT(sorted.r.stats.samples_tested, in_order.r.stats.samples_tested) << what;
            else
              EXPECT_EQ(sorted.r.stats.samples_tested, in_order.r.stats.samples_tested) << what;
          }
        }
      }
    }
  }
}

// A 32 px tile's occluders are sorted once their areas in the tile add up to two tiles: a far
// triangle over the tile, then a near one over all of it (sorted: the far one is hidden) or all
// but its first row (in order). A triangle whose depth reaches -0 keeps submission order.
TEST(FastPath, OccludersAreSortedFromTwoTilesOfArea) {
  const int n = 32;
  const auto run = [&](bool near_full_tile, bool negative_zero, Isa isa) {
    const float top = near_full_tile ? -100.f : 1.f;
    std::vector<glm::vec4> positions = {
        {-100, -100, 0.75f, 1}, {300, -100, 0.75f, 1}, {-100, 300, 0.75f, 1},  // far, whole tile
        {-100, top, 0.25f, 1},  {300, top, 0.25f, 1},  {50, 500, 0.25f, 1}};   // near
    if (negative_zero) {  // a triangle over one pixel centre, at depth -0
      positions.push_back({0, 0, -0.f, 1});
      positions.push_back({2, 0, -0.f, 1});
      positions.push_back({0, 2, -0.f, 1});
    }
    mosaic::Draw d;
    d.space = mosaic::Space::kScreen;
    d.positions = positions;
    d.color = {200, 40, 40, 255};
    d.state.color_write = false;
    mosaic::RenderTarget target(n, n, 1);
    const mosaic::Draw draws[] = {d};
    mosaic::Frame frame;
    frame.draws = draws;
    frame.occluders_nearest_first = true;
    mosaic::Renderer r({.threads = 1, .isa = isa, .tile_size = n});
    return mosaic::test::capture(r, frame, target).stats.samples_tested;
  };
  for (Isa isa : simd_isas()) {
    const std::string what = mosaic::to_string(isa);
    EXPECT_EQ(run(true, false, isa), std::uint64_t{n * n}) << what;  // sorted: near only
    EXPECT_EQ(run(false, false, isa), std::uint64_t{n * n + n * (n - 1)}) << what;  // in order
    EXPECT_EQ(run(true, true, isa), std::uint64_t{2 * n * n + 1}) << what;          // in order
  }
}

// Triangles whose boxes start at every row and column offset in a block, 1 to 17 px tall and
// wide: boxes within 2×2 blocks take the small-box walker (coverage of the rows a box meets
// only), taller or wider ones the block walker, and boxes of at most 4 pixels in one block the
// few-pixel path (2×2 and 4×1 at that bound, 5×1 and 2×3 just over), shaded draws too.
// Flat, per-vertex and shaded colour, depth-only draws, at the sample counts whose kernels have
// the small-box walker (1 and 4) and one that has not (8): as the reference, on every SIMD path.
TEST(FastPath, SmallBoxWalkerMatchesReferenceAtEveryOffsetInABlock) {
  const int w = 157, h = 131;
  Rng rng{77};
  TestScene sc;
  std::vector<float> attributes;  // one varying per vertex: its x, for the shaded draw
  for (int oy = 0; oy < 8; ++oy)
    for (int side_y : {1, 2, 3, 7, 8, 9, 10, 16, 17})
      for (int ox : {0, 3, 7})
        for (int side_x : {1, 2, 4, 5, 8, 9, 16, 17}) {
          // The box's corner at (ox, oy) in a random block; a fat triangle over the box, its
          // apex at either side, so that its top and bottom rows hold covered samples.
          const float x = static_cast<float>(8 * (rng.next() % 18) + ox);
          const float y = static_cast<float>(8 * (rng.next() % 15) + oy);
          const float bw = static_cast<float>(side_x), bh = static_cast<float>(side_y);
          const float z = static_cast<float>(rng.uniform(0.1, 0.9));
          const bool left = (rng.next() & 1) != 0;
          const glm::vec4 p[3] = {{left ? x + bw : x, y, z, 1},
                                  {left ? x : x + bw, y + 0.5f * bh, z + 0.05f, 1},
                                  {left ? x + bw : x, y + bh, z - 0.05f, 1}};
          for (const glm::vec4& v : p) {
            sc.positions.push_back(v);
            sc.colors.push_back({rng.byte(), rng.byte(), rng.byte(), 255});
            attributes.push_back(v.x / 16.0f);
          }
        }
  const std::uint32_t varyings[] = {0};
  const mosaic::Shader shader = mosaic::make_shader(
      [](const mosaic::Fragment& f) { return glm::vec4(f.varying(0) - std::floor(f.varying(0))); },
      1);
  for (int samples : {1, 4, 8}) {
    // Per-vertex colour, one colour, shaded, shaded and blended; at 4x also under SSAA.
    for (int mode = 0; mode < 4; ++mode)
      for (const bool ssaa : {false, true}) {
        if (ssaa && samples != 4) continue;
        const auto draw_with = [&](Isa isa) {
          mosaic::RenderTarget target(w, h, samples, {true, true});
          target.set_clear({10, 20, 30, 255}, 1.f);
          mosaic::Draw d;
          d.space = mosaic::Space::kScreen;
          d.positions = sc.positions;
          d.color_source =
              mode == 1 ? mosaic::ColorSource::kConstant : mosaic::ColorSource::kPerVertex;
          d.colors = sc.colors;
          d.color = {200, 100, 50, 255};
          if (mode >= 2) {
            d.attributes = attributes;
            d.attribute_count = 1;
            d.varyings = varyings;
            d.shader = shader;
          }
          // The shader's alpha is its varying's fraction: blending reads what the queue wrote.
          if (mode == 3) d.state.blend = mosaic::BlendMode::kSourceOver;
          const mosaic::Draw draws[] = {d};
          mosaic::Frame frame;
          frame.draws = draws;
          frame.ssaa = ssaa;
          mosaic::Renderer r({.threads = 2, .isa = isa});
          return mosaic::test::capture(r, frame, target);
        };
        const Result ref = draw_with(Isa::kReference);
        for (Isa isa : simd_isas())
          expect_same(ref, draw_with(isa),
                      "small boxes, mode " + std::to_string(mode) + " " + std::to_string(samples) +
                          "x" + (ssaa ? " ssaa " : " ") + mosaic::to_string(isa));
      }
    // Depth-only draws that write depth (the walker with depth planes beside the small-box one)
    // and a colour draw over them.
    std::vector<mosaic::DrawState> states(3);
    states[0].color_write = false;
    states[1].color_write = false;
    states[2].depth_test = mosaic::DepthTest::kLessEqual;
    const MultiResult ref =
        render_draws(sc, w, h, samples, Isa::kReference, states, {true, true}, false);
    for (Isa isa : simd_isas())
      expect_same_multi(
          ref, render_draws(sc, w, h, samples, isa, states, {true, true}, false),
          "small boxes, depth-only, " + std::to_string(samples) + "x " + mosaic::to_string(isa));
  }
}

// The depth-only walker at one sample for boxes within 2×2 blocks: a draw that writes depth, one
// that only tests it and a colour draw over them, on small triangles at every offset in a block
// and on huge triangles that a scissor cuts to such a box, whose edge values leave int32 there
// (coverage in double lanes). Depth, image, samples written and hierarchical z as the
// reference's, on every SIMD path.
TEST(FastPath, DepthOnlySmallBoxWalkerAtOneSampleMatchesReference) {
  const int w = 96, h = 64;
  Rng rng{91};
  TestScene small, huge;
  for (int i = 0; i < 300; ++i) {
    const float x = static_cast<float>(rng.uniform(0, w - 4)),
                y = static_cast<float>(rng.uniform(0, h - 4));
    const float s = static_cast<float>(rng.uniform(3, 14));
    const float z = static_cast<float>(rng.uniform(0.1, 0.9));
    for (const glm::vec4& v : {glm::vec4(x, y, z, 1), glm::vec4(x + s, y + 0.3f * s, z + 0.05f, 1),
                               glm::vec4(x + 0.4f * s, y + s, z - 0.05f, 1)}) {
      small.positions.push_back(v);
      small.colors.push_back({rng.byte(), rng.byte(), rng.byte(), 255});
    }
  }
  // Corners 20,000 px away, an edge across the scissor: |a|, |b| near 2^23 in 16.8.
  for (int i = 0; i < 24; ++i) {
    const float y0 = static_cast<float>(rng.uniform(12, 24)),
                y1 = static_cast<float>(rng.uniform(12, 24));
    const float z = static_cast<float>(rng.uniform(0.1, 0.9));
    const bool up = (i & 1) != 0;
    for (const glm::vec4& v : {glm::vec4(-20000.f, y0, z, 1), glm::vec4(20000.f, y1, z, 1),
                               glm::vec4(0.f, up ? -20000.f : 20000.f, z, 1)}) {
      huge.positions.push_back(v);
      huge.colors.push_back({rng.byte(), rng.byte(), rng.byte(), 255});
    }
  }
  std::vector<mosaic::DrawState> states(3);
  states[0].color_write = false;
  states[1].color_write = false;
  states[1].depth_write = false;
  states[1].depth_test = mosaic::DepthTest::kLessEqual;
  states[2].depth_test = mosaic::DepthTest::kLessEqual;
  for (const bool scissored : {false, true}) {
    // [20, 30) × [13, 22): two block columns and two block rows.
    for (mosaic::DrawState& s : states)
      s.scissor = scissored ? std::optional<mosaic::PixelRect>({20, 13, 10, 9}) : std::nullopt;
    const TestScene& sc = scissored ? huge : small;
    const MultiResult ref = render_draws(sc, w, h, 1, Isa::kReference, states, {true, true}, false);
    for (Isa isa : simd_isas())
      expect_same_multi(ref, render_draws(sc, w, h, 1, isa, states, {true, true}, false),
                        std::string(scissored ? "huge triangles, scissor " : "small boxes ") +
                            mosaic::to_string(isa));
  }
}

// Needles whose boxes span three or more blocks take the block walker, which from 8 samples on
// evaluates coverage only over the block rows that no single edge excludes: needles
// along each axis and diagonal and at shallow and steep slopes, 0.3 to 3 px wide, their corners
// on the 1/16 px grid (edges through sample rows and columns: the fill rule decides those
// samples) or anywhere on the 1/256 px one. Every sample count above one, the default depth
// state (kernels that fix the count) and others (the frame's count), a depth-only draw, MSAA
// and SSAA: as the reference, on every SIMD path.
TEST(FastPath, BlockWalkerRowTestMatchesReferenceOnNeedles) {
  const int w = 160, h = 120;
  Rng rng{113};
  TestScene sc;
  const double directions[][2] = {{1, 0},  {0, 1},  {1, 1},  {1, -1},
                                  {64, 1}, {1, 64}, {16, 3}, {3, -16}};
  const double widths[] = {0.3, 0.75, 1.5, 3.0};
  for (const auto& dir : directions)
    for (int i = 0; i < 16; ++i) {
      const double grid = i % 2 == 0 ? 16.0 : 256.0;
      const auto snap = [&](double v) { return static_cast<float>(std::round(v * grid) / grid); };
      const double len = std::hypot(dir[0], dir[1]);
      const double ux = dir[0] / len, uy = dir[1] / len;
      const double length = rng.uniform(20, 100), width = widths[i % 4];
      const double cx = rng.uniform(50, w - 50), cy = rng.uniform(50, h - 50);
      const double apex = rng.uniform(-0.8, 0.8) * length / 2;
      const float z = static_cast<float>(rng.uniform(0.1, 0.9));
      const glm::vec4 p[3] = {
          {snap(cx - ux * length / 2), snap(cy - uy * length / 2), z, 1},
          {snap(cx + ux * length / 2), snap(cy + uy * length / 2), z + 0.05f, 1},
          {snap(cx + ux * apex - uy * width), snap(cy + uy * apex + ux * width), z - 0.05f, 1}};
      for (const glm::vec4& v : p) {
        sc.positions.push_back(v);
        sc.colors.push_back({rng.byte(), rng.byte(), rng.byte(), 255});
      }
    }
  std::vector<mosaic::DrawState> states(3);
  states[1].depth_test = mosaic::DepthTest::kLessEqual;
  states[2].color_write = false;
  for (int samples : {1, 4, 8, 16})
    for (const bool ssaa : {false, true}) {
      if (ssaa && samples != 4) continue;
      const MultiResult ref =
          render_draws(sc, w, h, samples, Isa::kReference, states, {true, true}, ssaa);
      for (Isa isa : simd_isas())
        expect_same_multi(ref, render_draws(sc, w, h, samples, isa, states, {true, true}, ssaa),
                          "needles, " + std::to_string(samples) + "x" + (ssaa ? " ssaa " : " ") +
                              mosaic::to_string(isa));
    }
}
