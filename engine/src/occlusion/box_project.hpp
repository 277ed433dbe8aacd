// occlusion/box_project.hpp — world boxes to screen rectangles and nearest depths, for the batched
// box queries (HierarchicalZ::boxes_visible()).
//
// Takes: boxes, a view-projection matrix and the frame's size. Gives: per box, either its answer
// (a corner not finite or not in front of the near plane) or the screen rectangle and nearest
// depth to test against the block bounds. project_boxes() is the scalar reference;
// BoxProjectSimd<Arch> does the same operations in the same order on one box per double lane,
// built per ISA from simd/box_query.cpp, and gives bit-identical results.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <glm/mat4x4.hpp>
#include <limits>
#include <xsimd/xsimd.hpp>

#include "mosaic/occlusion.hpp"

namespace mosaic::occlusion {

/// One box through the matrix: `answered` with `visible` when a corner is not finite or not in
/// front of the near plane; otherwise `bounds` go to rect_visible().
struct Projected {
  bool answered = false, visible = true;
  BoxBounds bounds;
};

/// The matrix and viewport of a batch of box queries.
struct BoxView {
  double m[4][4];  ///< column-major, as glm: m[column][row]
  double half_w, half_h;
  int width, height;
  bool greater;  ///< the test is kGreater or kGreaterEqual: the nearest depth is the largest

  BoxView(const glm::mat4& view_proj, int w, int h, bool greater_test)
      : half_w(w * 0.5), half_h(h * 0.5), width(w), height(h), greater(greater_test) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = view_proj[c][r];
  }
};

/// How far a box's projected corner depth may be from the depth the renderer computes for the
/// same corner (both from double transforms, in a different order), relative to its magnitude
/// plus one: far below a float step, which the nearest depth is moved by as well.
inline constexpr double kCornerDepthSlack = 0x1p-40;
/// A box's screen rectangle is widened by this many pixels on each side: a float rounding of a
/// corner, and snapping to 1/256 px, move it by far less.
inline constexpr float kRectMarginPx = 1.0f;

/// The rectangle and nearest depth of a box whose corners all lie in front of the near plane,
/// from the corners' bounds in pixels and depth.
inline BoxBounds finish_bounds(const BoxView& v, double x0, double y0, double x1, double y1,
                               double z0, double z1) {
  // Clamped to a little past the screen first, so that the floats stay finite and ordered.
  const double pad = kRectMarginPx + 1.0;
  auto cx = [&](double x) { return static_cast<float>(std::clamp(x, -pad, v.width + pad)); };
  auto cy = [&](double y) { return static_cast<float>(std::clamp(y, -pad, v.height + pad)); };
  BoxBounds b;
  b.rect = {cx(x0) - kRectMarginPx, cy(y0) - kRectMarginPx, cx(x1) + kRectMarginPx,
            cy(y1) + kRectMarginPx};
  const float inf = std::numeric_limits<float>::infinity();
  if (v.greater) {
    b.nearest =
        std::nextafter(static_cast<float>(z1 + kCornerDepthSlack * (1 + std::abs(z1))), inf);
  } else {
    b.nearest =
        std::nextafter(static_cast<float>(z0 - kCornerDepthSlack * (1 + std::abs(z0))), -inf);
  }
  return b;
}

/// The answer of a box that has a corner not in front of the near plane (`crossing`): hidden
/// when all eight are behind it (clipped away), otherwise visible over the whole screen.
inline Projected crossing_answer(const BoxView& v, int behind) {
  if (behind == 8) return {true, false, {}};
  return {true, true, {{0, 0, float(v.width), float(v.height)}, v.greater ? 1.0f : 0.0f}};
}

/// The scalar reference: boxes [0, n) into out. Compiled once, with the baseline flags
/// (box_project.cpp), so that no copy built for one instruction set is shared with another.
void project_boxes(const Box* boxes, std::size_t n, const BoxView& v, Projected* out);

/// A box projection with project_boxes()'s signature: one per instruction set (isa_dispatch.hpp).
using BoxProjectorFn = void(const Box* boxes, std::size_t n, const BoxView& v, Projected* out);
using BoxProjector = BoxProjectorFn*;

/// project_boxes() with one box per double lane of Arch; the tail goes to the scalar code.
template <class Arch>
struct BoxProjectSimd {
  using D = xsimd::batch<double, Arch>;
  static constexpr std::size_t L = D::size;

  static void run(const Box* boxes, std::size_t n, const BoxView& v, Projected* out) {
    std::size_t i = 0;
    for (; i + L <= n; i += L) batch(boxes + i, v, out + i);
    project_boxes(boxes + i, n - i, v, out + i);
  }

 private:
  static void batch(const Box* boxes, const BoxView& v, Projected* out) {
    alignas(64) double lanes[6][L];
    for (std::size_t l = 0; l < L; ++l) {
      const Box& b = boxes[l];
      const double c[6] = {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z};
      for (int k = 0; k < 6; ++k) lanes[k][l] = c[k];
    }
    D lo[3], ext[3];
    for (int c = 0; c < 3; ++c) {
      lo[c] = D::load_aligned(lanes[c]);
      ext[c] = D::load_aligned(lanes[3 + c]) - lo[c];
    }
    D base[4], edge[3][4];
    for (int r = 0; r < 4; ++r) {
      base[r] =
          ((D(v.m[0][r]) * lo[0] + D(v.m[1][r]) * lo[1]) + D(v.m[2][r]) * lo[2]) + D(v.m[3][r]);
      for (int c = 0; c < 3; ++c) edge[c][r] = D(v.m[c][r]) * ext[c];
    }
    const D inf(std::numeric_limits<double>::infinity());
    D x0 = inf, y0 = inf, z0 = inf, x1 = -inf, y1 = -inf, z1 = -inf;
    D behind(0.0), crossing(0.0);
    const D zero(0.0), one(1.0), hw(v.half_w), hh(v.half_h);
    for (int k = 0; k < 8; ++k) {
      D p[4];
      for (int r = 0; r < 4; ++r) {
        p[r] = base[r];
        for (int c = 0; c < 3; ++c)
          if (k >> c & 1) p[r] += edge[c][r];
      }
      // Finite: x - x is 0 for a finite x and NaN for an infinite or NaN one.
      const auto finite = ((p[0] - p[0]) + (p[1] - p[1]) + (p[2] - p[2]) + (p[3] - p[3])) == zero;
      behind += xsimd::select(finite && (p[2] < zero), one, zero);
      const D q = one / p[3];
      const D x = (p[0] + p[3]) * hw * q, y = (p[3] - p[1]) * hh * q, z = p[2] * q;
      const auto in_front =
          finite && (p[3] > zero) && (p[2] >= zero) && (x == x) && (y == y) && (z == z);
      crossing += xsimd::select(in_front, zero, one);
      // Corners behind the plane leave the bounds alone (their lanes are answered anyway).
      x0 = xsimd::select(in_front, xsimd::min(x0, x), x0);
      x1 = xsimd::select(in_front, xsimd::max(x1, x), x1);
      y0 = xsimd::select(in_front, xsimd::min(y0, y), y0);
      y1 = xsimd::select(in_front, xsimd::max(y1, y), y1);
      z0 = xsimd::select(in_front, xsimd::min(z0, z), z0);
      z1 = xsimd::select(in_front, xsimd::max(z1, z), z1);
    }
    const D results[8] = {x0, y0, x1, y1, z0, z1, behind, crossing};
    alignas(64) double b[8][L];
    for (int k = 0; k < 8; ++k) results[k].store_aligned(b[k]);
    for (std::size_t l = 0; l < L; ++l)
      out[l] =
          b[7][l] != 0
              ? crossing_answer(v, static_cast<int>(b[6][l]))
              : Projected{false, true,
                          finish_bounds(v, b[0][l], b[1][l], b[2][l], b[3][l], b[4][l], b[5][l])};
  }
};

}  // namespace mosaic::occlusion
