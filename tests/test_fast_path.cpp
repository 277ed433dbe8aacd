// The fast tile path against the exact reference rasterizer: bit-identical resolved images,
// per-sample colour and depth, and samples_written, for every SIMD path this CPU runs, every
// sample count, both fill rules, every depth mode, MSAA and SSAA, 1, 2 and 7 threads, and
// image sizes that tiles do not divide.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "mosaic/mosaic.hpp"

namespace {

using mosaic::Isa;

// splitmix64: a tiny deterministic generator, identical on every standard library.
struct Rng {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * double(next() >> 11) * 0x1p-53; }
  std::uint8_t byte() { return static_cast<std::uint8_t>(next()); }
};

enum class Shape { kSmall, kLarge, kSliver, kHuge, kClipSpace, kOnSamples };

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
      case Shape::kSmall: r = rng.uniform(1, 8); break;
      case Shape::kLarge: r = rng.uniform(0.2, 0.8) * w; break;
      case Shape::kSliver: r = rng.uniform(20, 200); break;
      case Shape::kHuge: r = rng.uniform(3e3, 1e6); break;
      case Shape::kClipSpace: r = 0; break;
      case Shape::kOnSamples: r = rng.uniform(1, 20); break;
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
          if (rng.next() & 1) x = sc.positions.back().x; else y = sc.positions.back().y;
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

struct Result {
  std::vector<mosaic::Rgba8> color, sample_color;
  std::vector<float> sample_depth;
  mosaic::FrameStats stats;
};

Result render(const TestScene& sc, int w, int h, int samples, Isa isa, int threads,
              mosaic::DrawState state, bool ssaa = false, bool painter = false) {
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
  mosaic::Renderer r({threads, isa});
  Result out;
  out.stats = r.render(frame, target);
  out.color.assign(target.color().begin(), target.color().end());
  out.sample_color.assign(target.sample_color().begin(), target.sample_color().end());
  out.sample_depth.assign(target.sample_depth().begin(), target.sample_depth().end());
  return out;
}

std::vector<Isa> simd_isas() {
  std::vector<Isa> v;
  for (Isa i : mosaic::available_isas())
    if (i != Isa::kReference) v.push_back(i);
  return v;
}

void expect_same(const Result& ref, const Result& fast, const std::string& what) {
  ASSERT_EQ(ref.stats.samples_written, fast.stats.samples_written) << what;
  ASSERT_EQ(ref.stats.triangles_drawn, fast.stats.triangles_drawn) << what;
  ASSERT_EQ(ref.sample_depth.size(), fast.sample_depth.size()) << what;
  std::size_t bad_depth = 0, bad_color = 0, bad_pixel = 0;
  for (std::size_t i = 0; i < ref.sample_depth.size(); ++i) {
    if (std::memcmp(&ref.sample_depth[i], &fast.sample_depth[i], sizeof(float)) != 0) ++bad_depth;
    if (!(ref.sample_color[i] == fast.sample_color[i])) ++bad_color;
  }
  for (std::size_t i = 0; i < ref.color.size(); ++i)
    if (!(ref.color[i] == fast.color[i])) ++bad_pixel;
  EXPECT_EQ(bad_depth, 0u) << what;
  EXPECT_EQ(bad_color, 0u) << what;
  EXPECT_EQ(bad_pixel, 0u) << what;
}

struct Case {
  Shape shape;
  int count;
  const char* name;
};

constexpr Case kCases[] = {{Shape::kOnSamples, 400, "on-samples"}, {Shape::kSmall, 600, "small"},   {Shape::kLarge, 12, "large"},
                           {Shape::kSliver, 80, "sliver"},  {Shape::kHuge, 10, "huge"},
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
          expect_same(ref, fast, std::string(c.name) + " " + std::to_string(samples) + "x " +
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
        const TestScene sc = make_scene(Shape::kSmall, w, h, 300, seed++, true);
        mosaic::DrawState st;
        st.depth_test = test;
        st.depth_write = write;
        const Result ref = render(sc, w, h, 4, Isa::kReference, 1, st, ssaa);
        for (Isa isa : simd_isas())
          expect_same(ref, render(sc, w, h, 4, isa, 2, st, ssaa),
                      std::string("depth mode ") + std::to_string(int(test)) + " write " +
                          std::to_string(write) + " ssaa " + std::to_string(ssaa));
      }
    }
  }
  const TestScene sc = make_scene(Shape::kLarge, w, h, 20, 7, false);
  const Result ref = render(sc, w, h, 4, Isa::kReference, 1, {}, false, true);
  for (Isa isa : simd_isas()) expect_same(ref, render(sc, w, h, 4, isa, 2, {}, false, true), "painter");
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

}  // namespace
