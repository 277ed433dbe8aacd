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
#include <string>
#include <vector>

#include "frame_checks.hpp"
#include "front/front_end.hpp"
#include "isa_dispatch.hpp"
#include "mosaic/errors.hpp"
#include "occlusion/box_project.hpp"
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
  coarse_min_.clear();
  coarse_max_.clear();
}

void HierarchicalZ::build_coarse() {
  const int bw = blocks_x(), bh = blocks_y();
  const int cw = (bw + kCoarseBlocks - 1) / kCoarseBlocks,
            ch = (bh + kCoarseBlocks - 1) / kCoarseBlocks;
  coarse_min_.assign(static_cast<std::size_t>(cw) * ch, std::numeric_limits<float>::infinity());
  coarse_max_.assign(static_cast<std::size_t>(cw) * ch, -std::numeric_limits<float>::infinity());
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      const std::size_t b = static_cast<std::size_t>(by) * bw + bx;
      const std::size_t c = static_cast<std::size_t>(by / kCoarseBlocks) * cw + bx / kCoarseBlocks;
      // std::min/max keep a NaN bound out; a NaN block never hides anything (hiz_hidden), so
      // the cell must not either: NaN poisons it on purpose.
      coarse_min_[c] = std::isnan(zmin_[b]) ? zmin_[b] : std::min(coarse_min_[c], zmin_[b]);
      coarse_max_[c] = std::isnan(zmax_[b]) ? zmax_[b] : std::max(coarse_max_[c], zmax_[b]);
    }
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
  auto blocks_hide = [&](int ya, int yb, int xa, int xb) {
    for (int by = ya; by <= yb; ++by)
      for (int bx = xa; bx <= xb; ++bx) {
        const std::size_t b = static_cast<std::size_t>(by) * stride + bx;
        if (!raster::hiz_hidden(test, nearest, nearest, zmin_[b], zmax_[b])) return false;
      }
    return true;
  };
  // Most visible queries show in their first block; hidden ones must visit every block, and a
  // cell's bounds hold all of its blocks': where they hide the query, so does each block.
  const std::size_t first = static_cast<std::size_t>(by0) * stride + bx0;
  if (!raster::hiz_hidden(test, nearest, nearest, zmin_[first], zmax_[first])) return true;
  if (coarse_min_.empty()) return !blocks_hide(by0, by1, bx0, bx1);
  constexpr int kC = kCoarseBlocks;
  const int cstride = (stride + kC - 1) / kC;
  for (int cy = by0 / kC; cy <= by1 / kC; ++cy)
    for (int cx = bx0 / kC; cx <= bx1 / kC; ++cx) {
      const std::size_t c = static_cast<std::size_t>(cy) * cstride + cx;
      if (raster::hiz_hidden(test, nearest, nearest, coarse_min_[c], coarse_max_[c])) continue;
      if (!blocks_hide(std::max(by0, cy * kC), std::min(by1, cy * kC + kC - 1),
                       std::max(bx0, cx * kC), std::min(bx1, cx * kC + kC - 1)))
        return true;
    }
  return false;
}

void HierarchicalZ::rects_visible(std::span<const ScreenRect> rects, std::span<const float> nearest,
                                  std::span<std::uint8_t> visible, DepthTest test) const {
  if (nearest.size() != rects.size() || visible.size() != rects.size())
    throw Error(Errc::kInvalidArgument, "rects_visible: " + std::to_string(rects.size()) +
                                            " rectangles, " + std::to_string(nearest.size()) +
                                            " depths and " + std::to_string(visible.size()) +
                                            " answers");
  for (std::size_t i = 0; i < rects.size(); ++i)
    visible[i] = rect_visible(rects[i], nearest[i], test) ? 1 : 0;
}

namespace {

/// The box projection of the best instruction set this CPU runs, or the scalar one.
occlusion::BoxProjector best_box_projector() {
  const std::vector<Isa> isas = dispatch::runnable_isas();
  const occlusion::BoxProjector simd =
      isas.empty() ? nullptr : dispatch::box_projector(isas.back());
  return simd ? simd : &occlusion::project_boxes;
}

/// Boxes projected per pass: the projections of one pass stay in L1.
constexpr std::size_t kBoxesPerPass = 256;

}  // namespace

void HierarchicalZ::boxes_visible(std::span<const Box> boxes, const glm::mat4& view_proj,
                                  std::span<std::uint8_t> visible, DepthTest test,
                                  std::span<BoxBounds> bounds) const {
  if (visible.size() != boxes.size() || (!bounds.empty() && bounds.size() != boxes.size()))
    throw Error(Errc::kInvalidArgument, "boxes_visible: " + std::to_string(boxes.size()) +
                                            " boxes, " + std::to_string(visible.size()) +
                                            " answers and " + std::to_string(bounds.size()) +
                                            " bounds");
  static const occlusion::BoxProjector project = best_box_projector();
  const bool greater = test == DepthTest::kGreater || test == DepthTest::kGreaterEqual;
  const occlusion::BoxView view(view_proj, width_, height_, greater);
  occlusion::Projected projected[kBoxesPerPass];
  for (std::size_t first = 0; first < boxes.size(); first += kBoxesPerPass) {
    const std::size_t n = std::min(kBoxesPerPass, boxes.size() - first);
    project(boxes.data() + first, n, view, projected);
    for (std::size_t k = 0; k < n; ++k) {
      const occlusion::Projected& p = projected[k];
      const bool v =
          empty() || (p.answered ? p.visible : rect_visible(p.bounds.rect, p.bounds.nearest, test));
      visible[first + k] = v ? 1 : 0;
      if (!bounds.empty()) bounds[first + k] = p.bounds;
    }
  }
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
