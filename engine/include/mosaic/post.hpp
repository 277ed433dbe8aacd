// mosaic/post.hpp — post passes over a finished frame: FXAA and wide resolve filters.
//
// Takes: a resolved RGBA8 image (fxaa) or a RenderTarget that kept its per-sample colours
// (filter_resolve). Gives: a new RGBA8 image of the same size. Both are library functions run
// after Renderer::render(); neither touches the target.
#pragma once

#include <span>

#include "mosaic/render_target.hpp"
#include "mosaic/types.hpp"

namespace mosaic::post {

/// Tuning of fxaa(); the defaults are FXAA 3.11's "quality" preset values.
struct FxaaOptions {
  /// A pixel is processed only when the luma range of its 4 neighbours and itself exceeds
  /// max(edge_threshold_min, edge_threshold * the largest luma): low contrast is left alone.
  double edge_threshold = 0.125;
  double edge_threshold_min = 0.0625;
  /// Strength of the sub-pixel term (0: off, 1: full), which softens single-pixel features.
  double subpixel = 0.75;
  /// Pixels searched along an edge in each direction for its end.
  int search_steps = 12;
};

/// FXAA-style post-process (after Lottes, "FXAA", NVIDIA 2009–2011): finds luma edges, walks
/// along each to its ends, and blends every edge pixel with its neighbour across the edge by
/// how far the pixel sits from the nearer end (which undoes the staircase), or by the sub-pixel
/// term if that is larger. Luma is Rec. 601 on the stored values; alpha is copied. `in` and
/// `out` are width × height, row-major, and must not overlap. Throws Error{kInvalidArgument}
/// for a size mismatch.
void fxaa(std::span<const Rgba8> in, int width, int height, std::span<Rgba8> out,
          const FxaaOptions& options = {});

/// A resolve filter: the weight of a sample at offset (dx, dy) px from a pixel's centre is
/// f(dx) * f(dy), normalised per pixel over the samples within reach.
enum class Filter {
  kBox,       ///< f = 1 inside the pixel's own square: the engine's resolve
  kTent,      ///< f(t) = 1 - |t| for |t| < 1 (radius 1 px)
  kGaussian,  ///< f(t) = exp(-t² / (2 · 0.5²)) for |t| < 1.5 (sigma 0.5 px, cut at 3 sigma)
};

/// Half-width of a filter's support, pixels.
double filter_radius(Filter filter) noexcept;
/// The one-dimensional weight f(t) of a filter (0 outside its support).
double filter_weight(Filter filter, double t) noexcept;

/// Resolves the target's kept per-sample colours (TargetOptions::keep_sample_color) with
/// `filter`, each sample at its standard position, into `out` (width × height). Channels are
/// rounded to nearest, ties up; kBox reproduces the engine's resolve exactly. Throws
/// Error{kInvalidArgument} if the target kept no sample colours or `out` has the wrong size.
void filter_resolve(const RenderTarget& target, Filter filter, std::span<Rgba8> out);

}  // namespace mosaic::post
