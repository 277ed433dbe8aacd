#include "front/clip.hpp"

#include <cstdint>

#include "front/fixed_point.hpp"

namespace mosaic::front {
namespace {

constexpr double kGuard = kGuardBandPx;

// Signed distances to the clipping planes; a vertex is inside a plane when its distance >= 0.
enum Plane { kNear, kFar, kLeft, kRight, kTop, kBottom, kPlaneCount };

double distance(const ClipVertex& v, int plane) {
  switch (plane) {
    case kNear:
      return v.Z;
    case kFar:
      return v.W - v.Z;
    case kLeft:
      return v.X + kGuard * v.W;
    case kRight:
      return kGuard * v.W - v.X;
    case kTop:
      return v.Y + kGuard * v.W;
    default:
      return kGuard * v.W - v.Y;
  }
}

// Outcode against the viewport rectangle itself (not the guard band): a triangle whose three
// vertices are all beyond the same side is invisible.
std::uint32_t viewport_outcode(const ClipVertex& v, double width, double height) {
  std::uint32_t code = 0;
  if (v.X < 0) code |= 1;
  if (v.X > width * v.W) code |= 2;
  if (v.Y < 0) code |= 4;
  if (v.Y > height * v.W) code |= 8;
  if (v.Z < 0) code |= 16;
  if (v.Z > v.W) code |= 32;
  return code;
}

// The point where segment (p, q) crosses `plane`, where exactly one of p, q is inside it. The
// interpolation starts from the inside end: the result then depends only on the unordered pair
// {p, q}, which keeps shared edges identical in the two triangles that clip them, and it stays
// accurate when the outside end is huge. (Starting from a vertex at 1e30 px rounds t to 1 and
// a + (b - a) * t to garbage: 1e30 + (20 - 1e30) is 0, not 20.)
ClipVertex intersect(const ClipVertex& p, const ClipVertex& q, int plane) {
  const bool p_inside = distance(p, plane) >= 0;
  const ClipVertex& a = p_inside ? p : q;
  const ClipVertex& b = p_inside ? q : p;
  const double da = distance(a, plane);
  const double db = distance(b, plane);
  const double t = da / (da - db);  // in [0, 1): da >= 0 > db
  ClipVertex r;
  r.X = a.X + (b.X - a.X) * t;
  r.Y = a.Y + (b.Y - a.Y) * t;
  r.Z = a.Z + (b.Z - a.Z) * t;
  r.W = a.W + (b.W - a.W) * t;
  for (int c = 0; c < kColorChannels; ++c) r.color[c] = a.color[c] + (b.color[c] - a.color[c]) * t;
  // The point lies on the plane by construction; pin it there so rounding cannot leave it a
  // hair outside and fail the next plane's test or the 16.8 range.
  switch (plane) {
    case kNear:
      r.Z = 0;
      break;
    case kFar:
      r.Z = r.W;
      break;
    case kLeft:
      r.X = -kGuard * r.W;
      break;
    case kRight:
      r.X = kGuard * r.W;
      break;
    case kTop:
      r.Y = -kGuard * r.W;
      break;
    default:
      r.Y = kGuard * r.W;
      break;
  }
  return r;
}

}  // namespace

ClipResult clip_triangle(const std::array<ClipVertex, 3>& in, double width, double height,
                         ClipPolygon& out) {
  const std::uint32_t c0 = viewport_outcode(in[0], width, height);
  const std::uint32_t c1 = viewport_outcode(in[1], width, height);
  const std::uint32_t c2 = viewport_outcode(in[2], width, height);
  if (c0 & c1 & c2) return ClipResult::kCulled;

  std::uint32_t outside_any = 0;
  for (const ClipVertex& v : in)
    for (int p = 0; p < kPlaneCount; ++p)
      if (distance(v, p) < 0) outside_any |= 1u << p;
  if (outside_any == 0) return ClipResult::kInside;

  // Sutherland–Hodgman, one plane at a time, only against the planes some vertex of the current
  // polygon violates. Not the triangle's: a crossing point lies between its edge's ends only up
  // to rounding, and next to coordinates of 1e38 that rounding can leave it far outside a plane
  // that no original vertex violated.
  ClipPolygon a, b;
  a.count = 3;
  for (int i = 0; i < 3; ++i) a.v[i] = in[i];
  ClipPolygon* src = &a;
  ClipPolygon* dst = &b;
  for (int p = 0; p < kPlaneCount; ++p) {
    bool violated = false;
    for (int i = 0; i < src->count; ++i) violated = violated || distance(src->v[i], p) < 0;
    if (!violated) continue;
    dst->count = 0;
    for (int i = 0; i < src->count; ++i) {
      const ClipVertex& cur = src->v[i];
      const ClipVertex& next = src->v[(i + 1) % src->count];
      const double dc = distance(cur, p);
      const double dn = distance(next, p);
      // A convex polygon gains at most one vertex per plane; rounding on a near-degenerate one
      // could try for more, and such a sliver has no area to lose.
      if (dst->count + 2 > kMaxClipVertices) return ClipResult::kCulled;
      if (dc >= 0) dst->v[dst->count++] = cur;
      if ((dc >= 0) != (dn >= 0)) dst->v[dst->count++] = intersect(cur, next, p);
    }
    if (dst->count < 3) return ClipResult::kCulled;
    std::swap(src, dst);
  }
  out = *src;
  return ClipResult::kClipped;
}

}  // namespace mosaic::front
