// A short soak: a few hundred frames of mixed targets, sample counts, SSAA and draw states through
// ONE Renderer. Every 20th frame must equal a fresh Renderer's, bit for bit, and the resident set
// must stop growing once every kind of frame has been seen (memory kept between frames is
// bounded by the largest frame, never by the frame count). The long run:
// MOSAIC_SOAK_FRAMES=5000 build/release/tests/test_soak.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "scenes/rng.hpp"

namespace mosaic {
namespace {

/// Frames of the soak (MOSAIC_SOAK_FRAMES sets a longer run, e.g. 5000); and how often a frame
/// is checked against a fresh renderer.
constexpr int kDefaultFrames = 300;
constexpr int kCheckEvery = 20;
/// The target shapes, cycled frame by frame so that every one is seen in the first frames: the
/// renderer's memory reaches its high-water mark early.
struct Shape {
  int width, height, samples;
};
constexpr Shape kShapes[] = {{1, 1, 1},      {640, 360, 4}, {4096, 8, 16}, {97, 211, 8},
                             {300, 300, 16}, {1024, 64, 1}, {8, 2048, 4},  {33, 17, 16}};
constexpr int kShapeCount = static_cast<int>(std::size(kShapes));
/// RSS may grow this much between the end of the warm-up and the last frame: allocator noise.
constexpr long kRssSlackBytes = 32L << 20;
constexpr int kWarmupFrames = 4 * kShapeCount;

long resident_bytes() {
  long pages = 0, resident = 0;
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return -1;
  const int got = std::fscanf(f, "%ld %ld", &pages, &resident);
  std::fclose(f);
  return got == 2 ? resident * sysconf(_SC_PAGESIZE) : -1;
}

/// One frame's input: screen-space draws of random triangles with random states.
struct FrameInput {
  Shape shape;
  bool ssaa = false;
  std::vector<std::vector<glm::vec4>> positions;
  std::vector<std::vector<Rgba8>> colors;
  std::vector<Draw> draws;
};

FrameInput make_frame(int index) {
  SplitMix64 rng(0x50a4 + static_cast<std::uint64_t>(index));
  FrameInput in;
  in.shape = kShapes[index % kShapeCount];
  in.ssaa = rng.chance(0.2);
  const int ndraws = rng.range(1, 4);
  in.positions.resize(static_cast<std::size_t>(ndraws));
  in.colors.resize(static_cast<std::size_t>(ndraws));
  const double w = in.shape.width, h = in.shape.height;
  for (int d = 0; d < ndraws; ++d) {
    const int tris = rng.range(0, 600);
    auto& p = in.positions[static_cast<std::size_t>(d)];
    auto& c = in.colors[static_cast<std::size_t>(d)];
    for (int t = 0; t < tris; ++t) {
      // Mostly small triangles, some large ones and slivers, some far outside the target.
      const double size = rng.chance(0.05) ? rng.uniform(0.5, 3) * (w + h) : rng.uniform(0.5, 30);
      const double cx = rng.uniform(-0.2 * w, 1.2 * w), cy = rng.uniform(-0.2 * h, 1.2 * h);
      for (int k = 0; k < 3; ++k)
        p.emplace_back(static_cast<float>(cx + rng.uniform(-size, size)),
                       static_cast<float>(cy + rng.uniform(-size, size)),
                       static_cast<float>(rng.unit()), 1.0f);
      c.push_back({static_cast<std::uint8_t>(rng.next()), static_cast<std::uint8_t>(rng.next()),
                   static_cast<std::uint8_t>(rng.next()), static_cast<std::uint8_t>(rng.next())});
    }
    Draw draw;
    draw.space = Space::kScreen;
    draw.positions = p;
    draw.color_source = ColorSource::kPerTriangle;
    draw.colors = c;
    draw.state.depth_test = static_cast<DepthTest>(rng.range(0, 4));
    draw.state.depth_write = rng.chance(0.8);
    draw.state.color_write = rng.chance(0.9);
    draw.state.cull = static_cast<CullMode>(rng.range(0, 2));
    draw.state.fill_rule = rng.chance(0.5) ? FillRule::kD3D : FillRule::kOpenGL;
    draw.state.blend = rng.chance(0.2) ? BlendMode::kSourceOver : BlendMode::kNone;
    in.draws.push_back(draw);
  }
  return in;
}

struct Output {
  std::uint64_t hash = 0, samples_written = 0;
};

Output render_frame(Renderer& renderer, const FrameInput& in) {
  RenderTarget target(in.shape.width, in.shape.height, in.shape.samples);
  target.set_clear({9, 8, 7, 255});
  Frame frame;
  frame.draws = in.draws;
  frame.ssaa = in.ssaa;
  const FrameStats st = renderer.render(frame, target);
  return {target.image_hash(), st.samples_written};
}

int soak_frames() {
  const char* env = std::getenv("MOSAIC_SOAK_FRAMES");
  const int n = env ? std::atoi(env) : 0;
  return n > 0 ? n : kDefaultFrames;
}

TEST(Soak, OneRendererOverMixedFramesMatchesFreshOnesInBoundedMemory) {
  const int frames = soak_frames();
  Renderer renderer(RendererOptions{.threads = 2});
  long rss_after_warmup = 0, rss_peak = 0;
  int checked = 0;
  for (int i = 0; i < frames; ++i) {
    const FrameInput in = make_frame(i);
    const Output out = render_frame(renderer, in);
    if (i % kCheckEvery == kCheckEvery - 1) {
      Renderer fresh(RendererOptions{.threads = 1 + i % 3});
      const Output want = render_frame(fresh, in);
      EXPECT_EQ(out.hash, want.hash) << "frame " << i;
      EXPECT_EQ(out.samples_written, want.samples_written) << "frame " << i;
      ++checked;
    }
    const long rss = resident_bytes();
    if (i == kWarmupFrames - 1) rss_after_warmup = rss;
    if (i >= kWarmupFrames) rss_peak = std::max(rss_peak, rss);
  }
  EXPECT_EQ(checked, frames / kCheckEvery);
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  // The sanitizers' quarantines keep freed memory resident: the bound is the release build's.
  (void)rss_after_warmup;
  (void)rss_peak;
#else
  ASSERT_GT(rss_after_warmup, 0) << "no /proc/self/statm";
  EXPECT_LE(rss_peak, rss_after_warmup + kRssSlackBytes)
      << "resident set grew from " << rss_after_warmup << " to " << rss_peak << " bytes";
#endif
}

}  // namespace
}  // namespace mosaic
