#include "reference/reference.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <numeric>

#include "front/front_end.hpp"
#include "raster/depth_test.hpp"
#include "raster/sample_patterns.hpp"
#include "raster/tile.hpp"
#include "resolve/resolve.hpp"
#include "shade/shading.hpp"

namespace mosaic::reference {

std::vector<front::TriangleSetup> setup_frame(const Frame& frame, int width, int height,
                                              int samples, FrameStats& stats,
                                              front::PlaneArray* planes) {
  std::vector<front::TriangleSetup> tris;
  front::FrontStats fs;
  std::vector<float> keys;  // the painter's sort keys, in tris' order
  for (std::size_t d = 0; d < frame.draws.size(); ++d) {
    const Draw& draw = frame.draws[d];
    front::TriangleFrontEnd front(draw, static_cast<std::uint32_t>(d), width, height, tris, fs,
                                  planes, samples);
    if (frame.painter) front.sort_keys = &keys;
    const std::uint32_t n = front::triangle_count(draw);
    for (std::uint32_t t = 0; t < n; ++t) front.run(t);
  }
  fs.add_to(stats);
  if (frame.painter) {
    // Far to near, ties in submission order: sort the indices by key, then gather.
    std::vector<std::uint32_t> order(tris.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return keys[a] > keys[b]; });
    std::vector<front::TriangleSetup> sorted;
    sorted.reserve(tris.size());
    for (std::uint32_t i : order) sorted.push_back(tris[i]);
    tris = std::move(sorted);
  }
  return tris;
}

FrameStats render(const Frame& frame, RenderTarget& target, SampleBuffers* samples_out) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  FrameStats stats;
  stats.isa = Isa::kReference;
  stats.threads = 1;
  const int W = target.width(), H = target.height(), S = target.samples();
  const auto pattern = raster::sample_pattern(S);

  front::PlaneArray planes;
  std::vector<front::TriangleSetup> tris = setup_frame(frame, W, H, S, stats, &planes);
  std::vector<shade::DrawShading> shading;
  shade::frame_shading(frame.draws, shading);
  const auto t1 = Clock::now();

  SampleBuffers buf;
  const std::size_t n = static_cast<std::size_t>(W) * H * S;
  if (frame.color_load == LoadOp::kLoad) {
    buf.color.assign(target.sample_color().begin(), target.sample_color().end());
  } else {
    buf.color.assign(n, target.clear_color());
  }
  if (frame.depth_load == LoadOp::kLoad) {
    buf.depth = target.read_sample_depth();
  } else {
    buf.depth.assign(n, target.clear_depth());
  }

  for (const front::TriangleSetup& t : tris) {
    DrawState state = frame.draws[t.draw()].state;
    if (frame.painter) {
      state.depth_test = DepthTest::kAlways;
      state.depth_write = false;
    }
    // A draw with a shader or blending: shade::shade_one(), with the pixel in the lane the
    // tile kernels give it (pixel p of an 8×8 block is lane p % kShaderBatch).
    const shade::DrawShading* sh =
        shading.empty() || !shading[t.draw()].generic ? nullptr : &shading[t.draw()];
    const auto colour_at = [&](float x, float y, int lane) {
      return sh ? shade::shade_one(t, *sh, planes.data(), x, y, lane)
                : shade::Shaded{front::shade(t, planes.data(), x, y)};
    };
    for (int py = t.by0; py < t.by1; ++py) {
      for (int px = t.bx0; px < t.bx1; ++px) {
        // The depth test of every covered sample, then the shading, then the writes: a shader
        // that discards a pixel (or sample) leaves its depth and colour as they were.
        std::uint32_t pass = 0;
        std::array<float, raster::kMaxSamples> zs{};
        for (int s = 0; s < S; ++s) {
          const raster::SampleOffset o = pattern[s];
          const std::int64_t sx = raster::sample_x_fixed(px, o);
          const std::int64_t sy = raster::sample_y_fixed(py, o);
          if (t.edge[0](sx, sy) < 0 || t.edge[1](sx, sy) < 0 || t.edge[2](sx, sy) < 0) continue;
          zs[s] = front::sample_depth(t, raster::sample_x_px(px, o), raster::sample_y_px(py, o));
          ++stats.samples_tested;
          const std::size_t i = (static_cast<std::size_t>(py) * W + px) * S + s;
          if (raster::depth_passes(state.depth_test, zs[s], buf.depth[i])) pass |= 1u << s;
        }
        if (!pass) continue;
        const int lane = ((py % 8) * 8 + px % 8) % kShaderBatch;
        shade::Shaded pixel;  // MSAA: shaded once per pixel, at its centre, covered or not
        if (state.color_write && !frame.ssaa) {
          pixel = colour_at(float(px) + 0.5f, float(py) + 0.5f, lane);
          if (pixel.discarded) continue;
        }
        for (int s = 0; s < S; ++s) {
          if (!((pass >> s) & 1u)) continue;
          const std::size_t i = (static_cast<std::size_t>(py) * W + px) * S + s;
          shade::Shaded c = pixel;
          if (state.color_write && frame.ssaa) {
            c = colour_at(raster::sample_x_px(px, pattern[s]), raster::sample_y_px(py, pattern[s]),
                          lane);
            if (c.discarded) continue;
          }
          if (state.depth_write) buf.depth[i] = zs[s];
          ++stats.samples_written;
          if (!state.color_write) continue;  // a depth-only draw: no shading, no colour
          buf.color[i] = state.blend == BlendMode::kSourceOver
                             ? shade::blend_over(c.color, buf.color[i])
                             : c.color;
        }
      }
    }
  }
  const auto t2 = Clock::now();

  std::vector<Rgba8> image(static_cast<std::size_t>(W) * H);
  resolve::box_resolve(buf.color, S, image);
  target.store_image(image);
  if (target.options().keep_sample_color) target.sample_color_storage() = buf.color;
  if (target.keeps_sample_depth()) target.store_sample_depth(buf.depth);
  if (samples_out) *samples_out = std::move(buf);
  const auto t3 = Clock::now();

  auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  stats.ms_setup = ms(t0, t1);
  stats.ms_raster = ms(t1, t2);
  stats.ms_resolve = ms(t2, t3);
  stats.ms_total = ms(t0, t3);
  return stats;
}

}  // namespace mosaic::reference
