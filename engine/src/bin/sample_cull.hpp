// bin/sample_cull.hpp — culling set-up triangles that cover no sample, before they are binned.
//
// Takes: a TriangleSetup and the frame's sample pattern. Gives: whether the triangle provably
// covers no sample, so that no tile ever sees it. A tiny triangle (a distant mesh's are far below
// a pixel) costs a tile kernel its whole per-triangle setup for nothing; here its few candidate
// samples, those of its box, are tested with the exact int64 edge functions every rasterizer
// uses, so a culled triangle is one that would have written nothing: the image never changes.
#pragma once

#include <cstdint>
#include <span>

#include "front/setup.hpp"
#include "raster/sample_patterns.hpp"

namespace mosaic::bin {

/// The most candidate samples (box pixels × samples per pixel) the cull tests. A test costs a few
/// instructions per candidate and stops at the first covered one, against the hundreds a tile
/// kernel spends on any triangle it visits; larger boxes are left to the kernels, which reject
/// empty blocks anyway.
inline constexpr int kMaxCullCandidates = 32;

/// The cull tests only triangles expected to cover at most this many samples (area in px² times
/// samples per pixel): a larger one nearly always covers one, and testing it costs more than the
/// kernels spend on the few that do not (a 1 M-triangle mesh of ~1 px² triangles at 4x: binning
/// 6.8 -> 31.9 ms with every small box tested, for 7 % of its triangles culled).
inline constexpr std::int64_t kCullMaxExpectedSamples = 1;

/// Twice the area of one pixel in 16.8 units², the unit of an edge cross product.
inline constexpr std::int64_t kPixelArea2 = 2 * 256 * 256;

/// True when no sample of `pattern` inside the triangle's box is covered (all three E >= 0).
/// Triangles with more than kMaxCullCandidates samples in their box, or an area of more than
/// kCullMaxExpectedSamples samples, answer false without testing: "not proven".
inline bool covers_no_sample(const front::TriangleSetup& t,
                             std::span<const raster::SampleOffset> pattern) {
  const std::int64_t w = t.bx1 - t.bx0, h = t.by1 - t.by0;
  const auto samples = static_cast<std::int64_t>(pattern.size());
  if (w * h * samples > kMaxCullCandidates) return false;
  // Twice the area: the cross product of two edge directions, (b, -a) each (|a|, |b| < 2^24).
  const std::int64_t area2 = t.edge[0].a * t.edge[1].b - t.edge[0].b * t.edge[1].a;
  if ((area2 < 0 ? -area2 : area2) * samples > kCullMaxExpectedSamples * kPixelArea2) return false;
  // Every candidate is tested, with no branch on its result: which sample a tiny triangle covers
  // is data, which short-circuit tests mispredict. A sample is inside where no edge value has its
  // sign bit set. Each sample's edge values start at the box's first pixel and step by a pixel
  // (a or b times one pixel in 16.8): the same integers as evaluating each candidate afresh.
  std::int64_t all_outside = -1;  // its sign bit stays set while every candidate is outside
  const std::int64_t one = front::kSubpixelOne;
  for (const raster::SampleOffset o : pattern) {
    const std::int64_t sx = raster::sample_x_fixed(t.bx0, o), sy = raster::sample_y_fixed(t.by0, o);
    std::int64_t row0 = t.edge[0](sx, sy), row1 = t.edge[1](sx, sy), row2 = t.edge[2](sx, sy);
    for (int py = t.by0; py < t.by1; ++py) {
      std::int64_t e0 = row0, e1 = row1, e2 = row2;
      for (int px = t.bx0; px < t.bx1; ++px) {
        all_outside &= e0 | e1 | e2;
        e0 += t.edge[0].a * one;
        e1 += t.edge[1].a * one;
        e2 += t.edge[2].a * one;
      }
      row0 += t.edge[0].b * one;
      row1 += t.edge[1].b * one;
      row2 += t.edge[2].b * one;
    }
  }
  return all_outside < 0;
}

}  // namespace mosaic::bin
