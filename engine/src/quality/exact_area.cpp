// quality/exact_area.cpp — exact triangle ∩ pixel areas (see exact_area.hpp).
#include "quality/exact_area.hpp"

#include <vector>

#include "front/fixed_point.hpp"
#include "front/setup.hpp"

namespace mosaic::quality {
namespace {

/// One pixel in 16.8 units, as an int64 for the corner arithmetic.
constexpr std::int64_t kOne = front::kSubpixelOne;
/// A pixel's area in (1/256 px)², to turn a shoelace sum into px².
constexpr long kUnitsPerPx2 = long{kOne} * kOne;

struct Point {
  mpq_class x, y;
};

/// Keeps the part of `poly` with coord(axis) >= bound (keep_above) or <= bound.
std::vector<Point> clip(const std::vector<Point>& poly, bool x_axis, long bound, bool keep_above) {
  std::vector<Point> out;
  if (poly.empty()) return out;
  const mpq_class b(bound);
  auto coord = [&](const Point& p) -> const mpq_class& { return x_axis ? p.x : p.y; };
  auto inside = [&](const Point& p) { return keep_above ? coord(p) >= b : coord(p) <= b; };
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Point& p = poly[i];
    const Point& q = poly[(i + 1) % poly.size()];
    const bool pin = inside(p), qin = inside(q);
    if (pin) out.push_back(p);
    if (pin != qin) {
      // The crossing of segment p→q with the line coord = bound: exact in rationals.
      const mpq_class t = (b - coord(p)) / (coord(q) - coord(p));
      Point c;
      if (x_axis) {
        c.x = b;
        c.y = p.y + t * (q.y - p.y);
      } else {
        c.x = p.x + t * (q.x - p.x);
        c.y = b;
      }
      out.push_back(c);
    }
  }
  return out;
}

}  // namespace

SnappedTriangle snap_triangle(const glm::vec4& a, const glm::vec4& b, const glm::vec4& c) {
  SnappedTriangle t;
  const std::array<const glm::vec4*, 3> v{&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    t.x[k] = front::snap(static_cast<double>(v[k]->x));
    t.y[k] = front::snap(static_cast<double>(v[k]->y));
  }
  return t;
}

mpq_class exact_area(const SnappedTriangle& t, int px, int py) {
  const std::int64_t ox = std::int64_t{px} * kOne, oy = std::int64_t{py} * kOne;
  std::vector<Point> poly;
  for (int k = 0; k < 3; ++k)
    poly.push_back({mpq_class(long{t.x[k] - ox}), mpq_class(long{t.y[k] - oy})});
  poly = clip(poly, true, 0, true);
  poly = clip(poly, true, kOne, false);
  poly = clip(poly, false, 0, true);
  poly = clip(poly, false, kOne, false);
  mpq_class twice;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Point& p = poly[i];
    const Point& q = poly[(i + 1) % poly.size()];
    twice += p.x * q.y - q.x * p.y;
  }
  mpq_class area = abs(twice) / (2 * kUnitsPerPx2);
  area.canonicalize();
  return area;
}

PixelClass classify(const SnappedTriangle& t, int px, int py) {
  // Orientation: twice the signed area. |coordinates| <= 2^23 (the guard band in 16.8), so the
  // products stay below 2^48.
  const std::int64_t area2 =
      (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.x[2] - t.x[0]) * (t.y[1] - t.y[0]);
  if (area2 == 0) return PixelClass::kOutside;
  const std::int64_t sign = area2 > 0 ? 1 : -1;
  const std::array<std::int64_t, 4> cx{px * kOne, (px + 1) * kOne, px * kOne, (px + 1) * kOne};
  const std::array<std::int64_t, 4> cy{py * kOne, py * kOne, (py + 1) * kOne, (py + 1) * kOne};
  bool all_inside = true;
  for (int e = 0; e < 3; ++e) {
    const int f = (e + 1) % 3;
    const std::int64_t dx = t.x[f] - t.x[e], dy = t.y[f] - t.y[e];
    bool any_pos = false, any_neg = false;
    for (int k = 0; k < 4; ++k) {
      // Positive on the triangle's side of edge e. |dx|, |dy| <= 2^24 and the corner offsets
      // are below 2^24 on any target, so each product is below 2^48.
      const std::int64_t v = sign * (dx * (cy[k] - t.y[e]) - dy * (cx[k] - t.x[e]));
      any_pos = any_pos || v > 0;
      any_neg = any_neg || v < 0;
    }
    // Every corner on the far side (or on the line): the square lies in the closed outer
    // half-plane, so the intersection has zero area.
    if (!any_pos) return PixelClass::kOutside;
    if (any_neg) all_inside = false;
  }
  return all_inside ? PixelClass::kInside : PixelClass::kPartial;
}

double coverage(const SnappedTriangle& t, int px, int py) {
  switch (classify(t, px, py)) {
    case PixelClass::kOutside:
      return 0.0;
    case PixelClass::kInside:
      return 1.0;
    case PixelClass::kPartial:
      break;
  }
  return exact_area(t, px, py).get_d();
}

}  // namespace mosaic::quality
