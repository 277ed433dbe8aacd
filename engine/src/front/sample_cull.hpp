// front/sample_cull.hpp — culling set-up triangles that cover no sample, before they are stored.
//
// Takes: a triangle's edges and box as setup made them, and the frame's sample positions. Gives:
// whether the triangle provably covers no sample, so that it is never stored, binned or drawn,
// and otherwise the box of the pixels holding its covered samples.
// A tiny triangle (a distant mesh's are far below a pixel) would otherwise cost its setup's
// store, its binning and a tile kernel's whole per-triangle work for nothing. Its few candidate
// samples, those of its box, are tested with the exact edge functions every rasterizer uses, so
// a culled triangle is one that would have written nothing: the image never changes.
// setup_triangle() runs this test; the SIMD front end runs the same test in lanes.
#pragma once

#include <bit>
#include <cstdint>

#include "front/fixed_point.hpp"
#include "front/setup.hpp"

namespace mosaic::front {

/// The most candidate samples (box pixels × samples per pixel) the cull tests. A test costs a few
/// instructions per candidate, against the hundreds a tile kernel spends on any triangle it
/// visits; larger boxes are left to the kernels, which reject empty blocks anyway.
inline constexpr int kMaxCullCandidates = 32;

/// The cull tests only triangles expected to cover at most this many samples (area in px² times
/// samples per pixel): a larger one nearly always covers one, and testing it costs more than the
/// kernels spend on the few that do not (the README's measurements).
inline constexpr std::int64_t kCullMaxExpectedSamples = 2;

/// Twice the area of one pixel in 16.8 units², the unit of an edge cross product.
inline constexpr std::int64_t kPixelArea2 = 2 * kSubpixelOne * kSubpixelOne;

/// Whether the cull tests a triangle whose box is w × h pixels and whose doubled area (an edge
/// cross product, either sign) is area2, with `samples` samples per pixel.
inline bool cull_tests(std::int64_t w, std::int64_t h, std::int64_t area2, std::int64_t samples) {
  return w * h * samples <= kMaxCullCandidates &&
         (area2 < 0 ? -area2 : area2) * samples <= kCullMaxExpectedSamples * kPixelArea2;
}

/// Tests `t`'s candidate samples when the cull tests it. False: it covers none of them (culled).
/// True otherwise; a tested triangle's box then shrinks to the pixels holding a covered sample,
/// so that a tiny triangle reaches one tile, and often one pixel, of the kernels (exact: no
/// sample outside that box is covered). Untested triangles, or no spots, keep their box.
inline bool shrink_to_covered(TriangleSetup& t, const SampleSpots& spots) {
  if (spots.count == 0) return true;
  const std::int64_t w = t.bx1 - t.bx0, h = t.by1 - t.by0;
  // Twice the area: the cross product of two edge directions, (b, -a) each (|a|, |b| < 2^24).
  const std::int64_t area2 = t.edge[0].a * t.edge[1].b - t.edge[0].b * t.edge[1].a;
  if (!cull_tests(w, h, area2, spots.count)) return true;
  // Every candidate is tested, with no branch on its result: which sample a tiny triangle covers
  // is data, which short-circuit tests mispredict. A sample is inside where no edge value has its
  // sign bit set. Each sample's edge values start at the box's first pixel and step by a pixel
  // (a or b times one pixel in 16.8): the same integers as evaluating each candidate afresh.
  // The covered candidates' columns and rows, as bits from the box's first.
  std::uint32_t columns = 0, rows = 0;
  const std::int64_t one = kSubpixelOne;
  for (int s = 0; s < spots.count; ++s) {
    const std::int64_t sx = std::int64_t{t.bx0} * one + spots.x[s];
    const std::int64_t sy = std::int64_t{t.by0} * one + spots.y[s];
    std::int64_t row0 = t.edge[0](sx, sy), row1 = t.edge[1](sx, sy), row2 = t.edge[2](sx, sy);
    for (int y = 0; y < h; ++y) {
      std::int64_t e0 = row0, e1 = row1, e2 = row2;
      for (int x = 0; x < w; ++x) {
        const auto in = static_cast<std::uint32_t>((e0 | e1 | e2) >= 0);
        columns |= in << x;
        rows |= in << y;
        e0 += t.edge[0].a * one;
        e1 += t.edge[1].a * one;
        e2 += t.edge[2].a * one;
      }
      row0 += t.edge[0].b * one;
      row1 += t.edge[1].b * one;
      row2 += t.edge[2].b * one;
    }
  }
  if (!columns) return false;
  t.bx1 = t.bx0 + 32 - std::countl_zero(columns);
  t.bx0 += std::countr_zero(columns);
  t.by1 = t.by0 + 32 - std::countl_zero(rows);
  t.by0 += std::countr_zero(rows);
  return true;
}

}  // namespace mosaic::front
