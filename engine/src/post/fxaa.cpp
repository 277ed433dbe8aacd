// post/fxaa.cpp — an FXAA-style post-process over a resolved RGBA8 image (mosaic/post.hpp).
//
// Takes: a width × height RGBA8 image. Gives: the image with its luma edges blended. The
// algorithm follows FXAA 3.11's quality path (Lottes 2011) on the CPU, with unit search steps:
// (1) local contrast test on the 4-neighbourhood; (2) edge orientation from the 3×3 second
// differences; (3) the neighbour across the edge with the steeper gradient; (4) a walk along the
// edge, on the line between the pixel and that neighbour, until the luma there leaves the
// edge's average by a quarter of the gradient (an end); (5) blend towards the neighbour by
// 0.5 - distance-to-nearer-end / edge-length when that end turns the right way, or by the
// sub-pixel term when it is larger. Pixels outside the image repeat the border. Rows run in
// parallel (oneTBB).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mosaic/errors.hpp"
#include "mosaic/post.hpp"
#include "parallel/stage_edges.hpp"

namespace mosaic::post {
namespace {

/// Rec. 601 luma weights (FXAA's luma), on values scaled to [0, 1].
constexpr double kLumaR = 0.299, kLumaG = 0.587, kLumaB = 0.114;
constexpr double kMaxChannel = 255.0;
/// An edge end is where the luma on the edge line differs from the edge's average by this
/// fraction of the gradient across the edge (FXAA's gradientScaled = gradient / 4).
constexpr double kEndGradientFraction = 0.25;

}  // namespace

void fxaa(std::span<const Rgba8> in, int width, int height, std::span<Rgba8> out,
          const FxaaOptions& o) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (width < 1 || height < 1 || in.size() != n || out.size() != n)
    throw Error(Errc::kInvalidArgument, "fxaa: image buffers do not match the size");
  if (o.search_steps < 0 || !(o.subpixel >= 0 && o.subpixel <= 1))
    throw Error(Errc::kInvalidArgument, "fxaa: options out of range");
  std::vector<double> luma(n);
  for (std::size_t i = 0; i < n; ++i)
    luma[i] = (kLumaR * in[i].r + kLumaG * in[i].g + kLumaB * in[i].b) / kMaxChannel;
  auto L = [&](int x, int y) {
    x = std::clamp(x, 0, width - 1);
    y = std::clamp(y, 0, height - 1);
    return luma[static_cast<std::size_t>(y) * width + x];
  };
  auto C = [&](int x, int y) {
    x = std::clamp(x, 0, width - 1);
    y = std::clamp(y, 0, height - 1);
    return in[static_cast<std::size_t>(y) * width + x];
  };
  // Rows are independent (each reads `in` only): run them in parallel.
  parallel::StageEdges edges;
  tbb::parallel_for(0, height, edges.task([&](int y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t idx = static_cast<std::size_t>(y) * width + x;
      out[idx] = in[idx];
      const double m = L(x, y), nn = L(x, y - 1), s = L(x, y + 1), e = L(x + 1, y), w = L(x - 1, y);
      const double hi = std::max({m, nn, s, e, w}), lo = std::min({m, nn, s, e, w});
      const double range = hi - lo;
      if (range < std::max(o.edge_threshold_min, hi * o.edge_threshold)) continue;
      const double nw = L(x - 1, y - 1), ne = L(x + 1, y - 1), sw = L(x - 1, y + 1),
                   se = L(x + 1, y + 1);
      // FXAA's orientation test: second differences down the columns are large across a
      // horizontal edge, second differences along the rows across a vertical one.
      const double edge_h =
          std::fabs(nw - 2 * w + sw) + 2 * std::fabs(nn - 2 * m + s) + std::fabs(ne - 2 * e + se);
      const double edge_v =
          std::fabs(nw - 2 * nn + ne) + 2 * std::fabs(w - 2 * m + e) + std::fabs(sw - 2 * s + se);
      const bool horizontal = edge_h >= edge_v;
      // Neighbours across the edge: north/south for a horizontal edge, west/east otherwise.
      const double l1 = horizontal ? nn : w, l2 = horizontal ? s : e;
      const double g1 = std::fabs(l1 - m), g2 = std::fabs(l2 - m);
      const bool towards1 = g1 >= g2;
      const double pair = towards1 ? l1 : l2;
      const double gradient_scaled = kEndGradientFraction * std::max(g1, g2);
      const double local_avg = 0.5 * (pair + m);
      // Across offset (sx, sy) to the chosen neighbour; along direction (ax, ay).
      const int sx = horizontal ? 0 : (towards1 ? -1 : 1);
      const int sy = horizontal ? (towards1 ? -1 : 1) : 0;
      const int ax = horizontal ? 1 : 0, ay = horizontal ? 0 : 1;
      // Luma on the line half-way between the edge pixel row/column and the neighbour's.
      auto edge_luma = [&](int k) {
        return 0.5 * (L(x + k * ax, y + k * ay) + L(x + k * ax + sx, y + k * ay + sy)) - local_avg;
      };
      int dn = 0, dp = 0;
      double end_n = 0, end_p = 0;
      bool found_n = false, found_p = false;
      for (int k = 1; k <= o.search_steps && !found_n; ++k) {
        end_n = edge_luma(-k);
        dn = k;
        found_n = std::fabs(end_n) >= gradient_scaled;
      }
      for (int k = 1; k <= o.search_steps && !found_p; ++k) {
        end_p = edge_luma(k);
        dp = k;
        found_p = std::fabs(end_p) >= gradient_scaled;
      }
      // Distances from the pixel centre to the ends, measured as in FXAA from the last sample
      // (which lies past the end): the end is between step k - 1 and k, so use k - 0.5.
      const double dist_n = dn - 0.5, dist_p = dp - 0.5;
      const bool nearer_n = dist_n < dist_p;
      const double dist = std::min(dist_n, dist_p);
      const double span = dist_n + dist_p;
      const bool m_below = (m - local_avg) < 0;
      const double end = nearer_n ? end_n : end_p;
      const bool found = nearer_n ? found_n : found_p;
      // The staircase blends only where the nearer end turns away from the pixel's side.
      const bool good = found && ((end < 0) != m_below);
      const double edge_blend = good ? 0.5 - dist / span : 0.0;
      // Sub-pixel term: how far the pixel is from its 3×3 low-pass, smoothstepped and squared.
      const double lowpass = (2 * (nn + s + e + w) + (nw + ne + sw + se)) / 12.0;
      const double a = std::clamp(std::fabs(lowpass - m) / range, 0.0, 1.0);
      const double smooth = (-2 * a + 3) * a * a;
      const double sub_blend = smooth * smooth * o.subpixel;
      const double t = std::max(edge_blend, sub_blend);
      if (t <= 0) continue;
      const Rgba8 a0 = in[idx], a1 = C(x + sx, y + sy);
      auto mix = [t](std::uint8_t p, std::uint8_t q) {
        return static_cast<std::uint8_t>(std::lround(p + t * (static_cast<double>(q) - p)));
      };
      out[idx] = {mix(a0.r, a1.r), mix(a0.g, a1.g), mix(a0.b, a1.b), a0.a};
    }
  }));
  edges.join();
}

}  // namespace mosaic::post
