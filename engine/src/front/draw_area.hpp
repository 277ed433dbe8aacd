// front/draw_area.hpp — where a draw's triangles land in the target: its viewport and scissor.
//
// Takes: a draw's DrawState and the target's size. Gives: a DrawArea. The front end sets a
// draw's triangles up in its viewport's own pixels, as if the viewport were the whole target,
// keeps their boxes to the clip rectangle (viewport ∩ scissor ∩ target), and then moves each
// set-up triangle by the viewport's whole-pixel offset into the target. Moving by whole pixels
// changes no edge's sign at any sample and no plane's value at any sample (planes are anchored
// at the triangle's own snapped corner), so a draw through a viewport is, bit for bit, the draw
// into a target of the viewport's size.
#pragma once

#include <algorithm>
#include <cstdint>

#include "front/fixed_point.hpp"
#include "front/setup.hpp"
#include "mosaic/draw.hpp"

namespace mosaic::front {

struct DrawArea {
  int width = 0, height = 0;  ///< the viewport's size: what clip space maps onto
  /// Pixels [x0, x1) × [y0, y1) that may be drawn, in the viewport's pixels (empty: none).
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int dx = 0, dy = 0;  ///< the viewport's top-left pixel in the target

  /// A draw with neither viewport nor scissor on a width × height target.
  static DrawArea whole(int width, int height) {
    return {width, height, 0, 0, width, height, 0, 0};
  }

  /// The area of a draw with `state` (validated) on a width × height target.
  static DrawArea of(const DrawState& state, int width, int height) {
    const PixelRect vp = state.viewport.value_or(PixelRect{0, 0, width, height});
    DrawArea a{vp.width, vp.height, 0, 0, vp.width, vp.height, vp.x, vp.y};
    // The target, and the scissor if any, in the viewport's pixels.
    a.clip_to(-vp.x, -vp.y, width, height);
    if (state.scissor) {
      const PixelRect& s = *state.scissor;
      a.clip_to(s.x - vp.x, s.y - vp.y, s.width, s.height);
    }
    return a;
  }

  bool moved() const { return (dx | dy) != 0; }

  /// The pixels that may be drawn, in the target's pixels.
  PixelRect in_target() const { return {x0 + dx, y0 + dy, x1 - x0, y1 - y0}; }

  /// Moves a triangle set up in the viewport's pixels into the target's: E'(x + d) = E(x).
  void move(TriangleSetup& t) const {
    const std::int64_t ux = std::int64_t{dx} * kSubpixelOne, uy = std::int64_t{dy} * kSubpixelOne;
    for (EdgeFunction& e : t.edge) e.c -= e.a * ux + e.b * uy;
    // Exact: the anchor is a multiple of 1/256 below 2^16 in magnitude, as is the sum.
    t.x0 += static_cast<float>(dx);
    t.y0 += static_cast<float>(dy);
    t.bx0 += dx;
    t.bx1 += dx;
    t.by0 += dy;
    t.by1 += dy;
  }

 private:
  void clip_to(int x, int y, int w, int h) {
    // In int64: validation bounds each term by 2 × kMaxTargetSize, but not their sums' ranges.
    x0 = static_cast<int>(std::max<std::int64_t>(x0, x));
    y0 = static_cast<int>(std::max<std::int64_t>(y0, y));
    x1 = static_cast<int>(std::min<std::int64_t>(x1, std::int64_t{x} + w));
    y1 = static_cast<int>(std::min<std::int64_t>(y1, std::int64_t{y} + h));
  }
};

}  // namespace mosaic::front
