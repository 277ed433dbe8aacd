// raster/kernel_traits.hpp — what a tile kernel is specialised on, chosen once per draw.
//
// Takes: a draw's state and the frame's sample mode. Gives: the traits of the kernel its
// triangles take, so that the inner loops carry no branch on state a draw does not use.
#pragma once

#include "mosaic/draw.hpp"

namespace mosaic::raster {

/// What a draw's triangles colour.
enum class ColorMode {
  kNone,          ///< nothing: a depth-only draw touches no colour memory
  kFlat,          ///< one colour per triangle (TriangleSetup::color)
  kInterpolated,  ///< vertex colour, perspective-correct, per pixel (MSAA) or per sample (SSAA)
  kGeneric,       ///< a fragment shader or blending: shaded in batches after the depth test
  kDiscarding,    ///< a shader that may discard: as kGeneric, but depth is written after shading
};

/// One specialisation of the tile kernel's triangle loop.
template <DepthTest Test, bool Write, ColorMode Color, bool Ssaa, int Samples>
struct KernelTraits {
  static constexpr DepthTest kTest = Test;
  static constexpr bool kWrite = Write;  ///< the depth write
  static constexpr ColorMode kColor = Color;
  /// Interpolated colour per sample, not per pixel (only kInterpolated depends on it: a flat
  /// colour is the same either way, and the generic path decides when it colours).
  static constexpr bool kSsaa = Ssaa;
  /// Samples per pixel, or 0 for the frame's (TileFrame::samples): a known count unrolls the
  /// per-sample loops. One sample is at the pixel centre.
  static constexpr int kSamples = Samples;
  static constexpr bool kOneSample = Samples == 1;
  /// Coloured by a shader or blending, in batches after the depth test.
  static constexpr bool kGeneric = Color == ColorMode::kGeneric || Color == ColorMode::kDiscarding;
  /// Depth written after shading, for the samples the shader keeps.
  static constexpr bool kLateZ = Color == ColorMode::kDiscarding;
};

}  // namespace mosaic::raster
