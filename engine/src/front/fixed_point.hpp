// front/fixed_point.hpp — the vertex coordinate format and the bit budget it implies.
//
// Snapped vertex coordinates are signed 16.8 fixed point held in int32: value = raw / 256,
// 8 fractional bits (1/256 px, the D3D11 and llvmpipe precision), and 16 integer bits including
// the sign, i.e. |x| <= kGuardBandPx. Edge functions are evaluated exactly in int64.
#pragma once

#include <cstdint>

#include "mosaic/types.hpp"

namespace mosaic::front {

/// Fractional bits of a snapped coordinate (GL_SUBPIXEL_BITS = 8 on llvmpipe, 8 in D3D11).
inline constexpr int kSubpixelBits = 8;
/// One pixel in 16.8 units.
inline constexpr std::int32_t kSubpixelOne = 1 << kSubpixelBits;

/// Triangles are clipped to [-kGuardBandPx, kGuardBandPx]² in pixels before snapping, so that a
/// snapped coordinate always fits the 16.8 format: 2^15 px * 2^8 = 2^23 < 2^31.
inline constexpr std::int32_t kGuardBandPx = 1 << 15;
static_assert(kGuardBandPx >= 2 * kMaxTargetSize, "guard band must exceed the largest target");

/// Budget of an edge function E = a*x + b*y + c over 16.8 coordinates:
/// |a|, |b| <= 2 * kGuardBandPx * 256 = 2^24, and |x|, |y| <= 2^23, so |a*x + b*y| <= 2^48 and
/// |c| = |xa*yb - xb*ya| <= 2^47. Everything fits int64 with room to spare.
inline constexpr int kEdgeCoefficientBits = 1 + 15 + kSubpixelBits + 1;  // 2^24 range, signed
inline constexpr int kEdgeValueBits = 2 * (15 + kSubpixelBits) + 3;      // 2^49 range, signed
static_assert(kEdgeValueBits < 63, "edge functions must fit in int64");

/// A snapped 2-D point in 16.8 units.
struct FixedPoint {
  std::int32_t x = 0, y = 0;
};

}  // namespace mosaic::front
