// occlusion/occlusion.cpp — occlusion queries against a frame's hierarchical z.
//
// Takes: the block bounds the tile kernels (or the reference) wrote at the end of a frame, and
// a screen rectangle or a draw. Gives: visible / hidden, never "hidden" for a query any sample of
// which would pass the depth test. Triangles go through the renderer's own front end, so that a
// query sees the same snapped edges and depth planes as a draw would; the per-block depth bound
// is the kernels' (raster/hiz.hpp).
#include "mosaic/occlusion.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "frame_checks.hpp"
#include "front/front_end.hpp"
#include "raster/hiz.hpp"

namespace mosaic {

namespace {

constexpr int kB = HierarchicalZ::kBlockSize;
/// One pixel, and one block, in the 16.8 units of the edge functions.
constexpr std::int64_t kSubpixel = 256;
constexpr std::int64_t kBlockSpan = kB * kSubpixel;

}  // namespace

void HierarchicalZ::reset(int width, int height) {
  width_ = width;
  height_ = height;
  const std::size_t n = static_cast<std::size_t>(blocks_x()) * static_cast<std::size_t>(blocks_y());
  zmin_.resize(n);
  zmax_.resize(n);
}

void HierarchicalZ::clear() noexcept {
  width_ = height_ = 0;
  zmin_.clear();
  zmax_.clear();
}

bool HierarchicalZ::rect_visible(const ScreenRect& r, float nearest, DepthTest test) const {
  if (empty()) return true;
  if (std::isnan(r.x0) || std::isnan(r.y0) || std::isnan(r.x1) || std::isnan(r.y1) ||
      std::isnan(nearest))
    return true;
  // Every sample of pixel p lies in [p, p + 1), so the blocks holding a sample of the rectangle
  // are those meeting [x0, x1) × [y0, y1), clipped to the image (a block meeting only the closed
  // right edge is included too: conservative). Clamping first keeps any float in int range.
  const float x0 = std::clamp(r.x0, 0.0f, static_cast<float>(width_));
  const float x1 = std::clamp(r.x1, 0.0f, static_cast<float>(width_));
  const float y0 = std::clamp(r.y0, 0.0f, static_cast<float>(height_));
  const float y1 = std::clamp(r.y1, 0.0f, static_cast<float>(height_));
  if (!(x0 < x1) || !(y0 < y1)) return false;  // empty, or entirely off the screen
  const int bx0 = static_cast<int>(x0) / kB, by0 = static_cast<int>(y0) / kB;
  const int bx1 = std::min(blocks_x() - 1, static_cast<int>(x1) / kB);
  const int by1 = std::min(blocks_y() - 1, static_cast<int>(y1) / kB);
  const int stride = blocks_x();
  for (int by = by0; by <= by1; ++by)
    for (int bx = bx0; bx <= bx1; ++bx) {
      const std::size_t b = static_cast<std::size_t>(by) * stride + bx;
      if (!raster::hiz_hidden(test, nearest, nearest, zmin_[b], zmax_[b])) return true;
    }
  return false;
}

bool HierarchicalZ::draw_visible(const Draw& draw) const {
  detail::validate_draw(draw, 0);
  if (empty()) return true;
  // The front end's output, reused between calls on this thread (queries come by the thousand).
  thread_local std::vector<front::TriangleSetup> tris;
  tris.clear();
  front::FrontStats fs;
  front::run_front_end(draw, 0, 0, front::triangle_count(draw), width_, height_, tris, fs);
  const DepthTest test = draw.state.depth_test;
  const int stride = blocks_x();
  for (const front::TriangleSetup& t : tris) {
    const int x_lo = std::max(t.bx0, 0), x_hi = std::min(t.bx1, width_);
    const int y_lo = std::max(t.by0, 0), y_hi = std::min(t.by1, height_);
    if (x_lo >= x_hi || y_lo >= y_hi) continue;
    const raster::BlockDepthRange zrange(t);
    for (int by = y_lo / kB; by <= (y_hi - 1) / kB; ++by) {
      const int py0 = by * kB;
      for (int bx = x_lo / kB; bx <= (x_hi - 1) / kB; ++bx) {
        const int px0 = bx * kB;
        // Edge rejection: an edge whose largest value over the block's square is negative
        // leaves every sample of the block outside (the kernels' test, in exact int64).
        bool outside = false;
        for (const front::EdgeFunction& e : t.edge) {
          const std::int64_t corner =
              e.a * (std::int64_t{px0} * kSubpixel) + e.b * (std::int64_t{py0} * kSubpixel) + e.c;
          outside |= corner + std::max<std::int64_t>(0, e.a * kBlockSpan) +
                         std::max<std::int64_t>(0, e.b * kBlockSpan) <
                     0;
        }
        if (outside) continue;
        const auto [lo, hi] = zrange.over(px0, py0, kB, kB, t.z_min, t.z_max);
        const std::size_t b = static_cast<std::size_t>(by) * stride + bx;
        if (!raster::hiz_hidden(test, lo, hi, zmin_[b], zmax_[b])) return true;
      }
    }
  }
  return false;
}

}  // namespace mosaic
