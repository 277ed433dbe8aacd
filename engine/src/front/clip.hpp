// front/clip.hpp — homogeneous clipping in window space.
//
// Takes: a triangle whose vertices are in window-homogeneous space (pixel x = X / W,
// y = Y / W, depth = Z / W). Gives: the convex polygon of its part that lies in front of the
// camera (Z >= 0), before the far plane (Z <= W) and inside the guard band
// |X / W|, |Y / W| <= kGuardBandPx, or nothing.
//
// Clipping is watertight: the point where a shared edge meets a plane is interpolated from the
// edge's endpoint inside the plane towards the other, an order that does not depend on the
// triangle, so both triangles sharing the edge get the same bits.
#pragma once

#include <array>

namespace mosaic::front {

/// Number of colour channels carried through clipping (r, g, b, a as floats 0..255).
inline constexpr int kColorChannels = 4;

/// A vertex in window-homogeneous space, with its colour.
///
/// A shader draw has no vertex colour; its `color` carries instead the vertex's barycentric
/// weights in the submitted triangle (a corner is a unit vector, the fourth channel 0). Clipping
/// interpolates them like X, Y, Z and W, so a clipped vertex's attributes are the weighted sum of
/// the corners' (attributes are linear in homogeneous space): the clipper carries three numbers
/// instead of every attribute, in a field every vertex has anyway (a separate field measured
/// +0.3 % instructions on random-small for draws without shaders).
struct ClipVertex {
  double X = 0, Y = 0, Z = 0, W = 1;
  std::array<double, kColorChannels> color{};
};

/// The channels of ClipVertex::color that hold barycentric weights in a shader draw.
inline constexpr int kBaryChannels = 3;
static_assert(kColorChannels >= kBaryChannels);

/// Six planes each add at most one vertex to a triangle; two spare slots let the clipper test
/// the bound before it writes.
inline constexpr int kMaxClipVertices = 3 + 6 + 2;

struct ClipPolygon {
  std::array<ClipVertex, kMaxClipVertices> v;
  int count = 0;
};

enum class ClipResult {
  kInside,   ///< entirely inside every plane: use the triangle as it is
  kClipped,  ///< `out` holds the visible polygon (3 or more vertices)
  kCulled,   ///< nothing visible: outside one plane, or outside the viewport rectangle
};

/// Clips against the near, far and guard-band planes, and rejects triangles wholly outside the
/// viewport [0, width] × [0, height]. Vertices must be finite.
ClipResult clip_triangle(const std::array<ClipVertex, 3>& in, double width, double height,
                         ClipPolygon& out);

}  // namespace mosaic::front
