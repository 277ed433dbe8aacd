// post/filters.cpp — resolve filters wider than the box, over kept per-sample colours.
//
// Takes: a RenderTarget with keep_sample_color and a Filter. Gives: one RGBA8 pixel per pixel,
// the normalised weighted mean of every sample within the filter's reach, each sample at its
// standard position (raster/sample_patterns.hpp). Rows run in parallel (oneTBB).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mosaic/errors.hpp"
#include "mosaic/post.hpp"
#include "parallel/stage_edges.hpp"
#include "raster/sample_patterns.hpp"
#include "resolve/resolve.hpp"

namespace mosaic::post {
namespace {

/// Support half-width of the tent: it reaches the neighbours' centres, the classic choice.
constexpr double kTentRadius = 1.0;
/// Gaussian standard deviation (px) and cut-off: sigma 0.5 px blurs about as much as the tent;
/// at 3 sigma the weight is e^-4.5 ~ 1 % of the peak.
constexpr double kGaussSigma = 0.5;
constexpr double kGaussRadius = 3 * kGaussSigma;
/// Pixels per unit of a SampleOffset (offsets are stored in 1/16 px).
constexpr double kOffsetPx = 1.0 / 16.0;

}  // namespace

double filter_radius(Filter filter) noexcept {
  switch (filter) {
    case Filter::kBox:
      return 0.5;
    case Filter::kTent:
      return kTentRadius;
    case Filter::kGaussian:
      return kGaussRadius;
  }
  return 0.5;
}

double filter_weight(Filter filter, double t) noexcept {
  const double a = std::fabs(t);
  switch (filter) {
    case Filter::kBox:
      return a <= 0.5 ? 1.0 : 0.0;
    case Filter::kTent:
      return a < kTentRadius ? 1.0 - a / kTentRadius : 0.0;
    case Filter::kGaussian:
      return a < kGaussRadius ? std::exp(-a * a / (2 * kGaussSigma * kGaussSigma)) : 0.0;
  }
  return 0.0;
}

void filter_resolve(const RenderTarget& target, Filter filter, std::span<Rgba8> out) {
  const int w = target.width(), h = target.height(), s = target.samples();
  const std::span<const Rgba8> samples = target.sample_color();
  const std::size_t n = static_cast<std::size_t>(w) * h;
  if (samples.size() != n * s)
    throw Error(Errc::kInvalidArgument, "filter_resolve: the target kept no sample colours");
  if (out.size() != n)
    throw Error(Errc::kInvalidArgument, "filter_resolve: output size does not match the target");
  const std::span<const raster::SampleOffset> pattern = raster::sample_pattern(s);
  if (filter == Filter::kBox) {
    resolve::box_resolve(samples, s, out);
    return;
  }
  // Samples of a pixel q lie within 0.5 px of its centre: q matters while |q - x| - 0.5 is
  // inside the radius.
  const int reach = static_cast<int>(std::floor(filter_radius(filter) + 0.5));
  // The weight of sample k of the pixel at offset (ox, oy) depends only on those three: tabulate
  // it once instead of evaluating the filter (an exp for the Gaussian) for every sample.
  const int span = 2 * reach + 1;
  std::vector<double> weight(static_cast<std::size_t>(span) * span * s);
  for (int oy = -reach; oy <= reach; ++oy) {
    for (int ox = -reach; ox <= reach; ++ox) {
      for (int k = 0; k < s; ++k) {
        weight[(static_cast<std::size_t>(oy + reach) * span + (ox + reach)) * s + k] =
            filter_weight(filter, ox + pattern[k].dx * kOffsetPx) *
            filter_weight(filter, oy + pattern[k].dy * kOffsetPx);
      }
    }
  }
  parallel::StageEdges edges;
  tbb::parallel_for(0, h, edges.task([&](int y) {
    for (int x = 0; x < w; ++x) {
      double acc[4] = {0, 0, 0, 0}, wsum = 0;
      for (int qy = std::max(0, y - reach); qy <= std::min(h - 1, y + reach); ++qy) {
        for (int qx = std::max(0, x - reach); qx <= std::min(w - 1, x + reach); ++qx) {
          const Rgba8* c = &samples[(static_cast<std::size_t>(qy) * w + qx) * s];
          const double* wt =
              &weight[(static_cast<std::size_t>(qy - y + reach) * span + (qx - x + reach)) * s];
          for (int k = 0; k < s; ++k) {
            acc[0] += wt[k] * c[k].r;
            acc[1] += wt[k] * c[k].g;
            acc[2] += wt[k] * c[k].b;
            acc[3] += wt[k] * c[k].a;
            wsum += wt[k];
          }
        }
      }
      auto q = [&](double v) {
        return static_cast<std::uint8_t>(std::floor(std::clamp(v / wsum, 0.0, 255.0) + 0.5));
      };
      out[static_cast<std::size_t>(y) * w + x] = {q(acc[0]), q(acc[1]), q(acc[2]), q(acc[3])};
    }
  }));
  edges.join();
}

}  // namespace mosaic::post
