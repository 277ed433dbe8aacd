// quality/exact_area.hpp — the exact area of a snapped triangle inside a pixel square.
//
// Takes: a triangle whose vertices are the renderer's snapped 16.8 coordinates (integers in
// 1/256 px, front::snap) and a pixel (px, py). Gives: the area of triangle ∩ [px, px+1) ×
// [py, py+1) in px², as an exact rational (GMP mpq_class) or as the double nearest to it
// (one rounding, at the end). This is the ideal box filter the antialiasing modes approximate.
//
// Why rationals and not int128: clipping a triangle against the four pixel edges creates
// vertices where a triangle edge crosses x = k or y = k. Such a vertex has a denominator equal
// to the edge's dx or dy (up to 2^24 in 1/256 units), and a corner cut off by an edge has area
// c² / (2 a b): each of the three edges brings a denominator of up to 2^49, so the sum needs
// about 2^147 in the worst case, beyond int128. GMP's rationals never overflow, so no bound
// needs proving for the general path. The fast paths below use only int64 sign tests, whose
// budget is front/fixed_point.hpp's (|E| < 2^49 for every on-screen corner).
#pragma once

#include <gmpxx.h>

#include <array>
#include <cstdint>
#include <glm/vec4.hpp>

namespace mosaic::quality {

/// A triangle in snapped 16.8 units (1/256 px), exactly as the rasterizer sees it.
struct SnappedTriangle {
  std::array<std::int64_t, 3> x{}, y{};
};

/// Snaps three screen-space positions (pixels) with the engine's own front::snap.
SnappedTriangle snap_triangle(const glm::vec4& a, const glm::vec4& b, const glm::vec4& c);

/// Exact area of triangle ∩ pixel (px, py), in px² (Sutherland–Hodgman in rationals, then the
/// shoelace formula). Slow: a few microseconds. Zero for a degenerate triangle.
mpq_class exact_area(const SnappedTriangle& t, int px, int py);

/// Where a triangle stands against a pixel, from exact int64 edge functions at its corners.
enum class PixelClass { kOutside, kInside, kPartial };
PixelClass classify(const SnappedTriangle& t, int px, int py);

/// The exact area rounded once to double: 0 or 1 straight from classify(), exact_area()
/// otherwise.
double coverage(const SnappedTriangle& t, int px, int py);

}  // namespace mosaic::quality
