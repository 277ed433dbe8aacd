#include "front/setup.hpp"

#include <algorithm>
#include <cmath>

#include "front/draw_area.hpp"
#include "front/sample_cull.hpp"

namespace mosaic::front {
namespace {

// Pixel size in 16.8 units squared: converts an integer doubled area to px².
constexpr double kUnitsPerPx = kSubpixelOne;

// A plane through three values at the three (oriented) vertices, in double, rounded to float.
Plane make_plane(const std::array<double, 3>& X, const std::array<double, 3>& Y, double area_px2,
                 double f0, double f1, double f2) {
  const double ddx = ((f1 - f0) * (Y[2] - Y[0]) - (f2 - f0) * (Y[1] - Y[0])) / area_px2;
  const double ddy = ((f2 - f0) * (X[1] - X[0]) - (f1 - f0) * (X[2] - X[0])) / area_px2;
  return {static_cast<float>(f0), static_cast<float>(ddx), static_cast<float>(ddy)};
}

// 1/w at the three oriented corners, scaled so that the largest is 1. Interpolated colours and
// varyings are (value·q) / q, where only ratios of q matter: the scaling keeps value·q within
// the value's own range even when w is tiny.
std::array<double, 3> normalised_q(const std::array<double, 3>& Q) {
  const double qmax = std::max({Q[0], Q[1], Q[2]});
  return {Q[0] / qmax, Q[1] / qmax, Q[2] / qmax};
}

}  // namespace

std::int32_t snap(double px) {
  // Clipping keeps |px| <= kGuardBandPx up to rounding, and on hostile input (w near 0 beside
  // coordinates near 1e38) rounding can be large: clamp, so that the conversion below is defined.
  constexpr double kLimit = kGuardBandPx;
  px = std::clamp(px, -kLimit, kLimit);
  // Round to nearest, a tie to the even step (IEEE's default rounding, and llvmpipe's). Not
  // floor(s + 0.5): that addition rounds, and sends the largest double below a tie up.
  // s - floor(s) is exact for |s| < 2^52, so the tie test is exact. floor() by conversion:
  // |s| <= 2^23 after the clamp, so the int64 is exact, and this is a few instructions where a
  // libm call is not (std::floor and std::nearbyint are calls on the baseline ISA).
  const double s = px * kUnitsPerPx;
  auto below = static_cast<std::int64_t>(s);  // truncates towards zero
  if (static_cast<double>(below) > s) --below;
  const double frac = s - static_cast<double>(below);
  const bool up = frac > 0.5 || (frac == 0.5 && (below & 1) != 0);
  return static_cast<std::int32_t>(up ? below + 1 : below);
}

Rgba8 shade(const TriangleSetup& t, const Plane* planes, float x, float y) {
  if (is_flat(t)) return t.color;
  const Plane* p = planes + t.planes_base;
  const float q = eval_plane(p[0], t.x0, t.y0, x, y);
  std::array<std::uint8_t, kColorChannels> c{};
  for (int ch = 0; ch < kColorChannels; ++ch)
    c[ch] = to_unorm8(eval_plane(p[1 + ch], t.x0, t.y0, x, y) / q);
  return {c[0], c[1], c[2], c[3]};
}

SetupReject setup_triangle(const std::array<ScreenVertex, 3>& v, const DrawState& state,
                           const DrawArea& area, bool per_vertex_color, Rgba8 flat_color,
                           TriangleSetup& out, PlaneArray* planes, PlaneBasis* basis,
                           const SampleSpots* spots) {
  std::array<FixedPoint, 3> p;
  for (int i = 0; i < 3; ++i) p[i] = {snap(v[i].x), snap(v[i].y)};

  // Twice the signed area in 16.8 units². y points down, so a triangle that looks
  // counter-clockwise on screen has a negative area here.
  const std::int64_t area2 = std::int64_t{p[1].x - p[0].x} * (p[2].y - p[0].y) -
                             std::int64_t{p[2].x - p[0].x} * (p[1].y - p[0].y);
  if (area2 == 0) return SetupReject::kDegenerate;
  const bool ccw_on_screen = area2 < 0;
  const bool front = (state.front_face == FrontFace::kCounterClockwise) == ccw_on_screen;
  if ((state.cull == CullMode::kBack && !front) || (state.cull == CullMode::kFront && front))
    return SetupReject::kFace;
  out.set_draw(0, !front);  // the caller sets the draw index

  // Orient clockwise on screen (positive area) so that "inside" is E >= 0 for all three edges.
  std::array<int, 3> idx{0, 1, 2};
  if (area2 < 0) std::swap(idx[1], idx[2]);

  for (int e = 0; e < 3; ++e) {
    const FixedPoint a = p[idx[e]];
    const FixedPoint b = p[idx[(e + 1) % 3]];
    const std::int64_t dx = b.x - a.x;
    const std::int64_t dy = b.y - a.y;
    EdgeFunction f;
    f.a = -dy;
    f.b = dx;
    f.c = std::int64_t{a.x} * b.y - std::int64_t{b.x} * a.y;
    // Fill rule (y down, clockwise on screen): edges running up are left edges; a horizontal
    // edge running right is a top edge, one running left a bottom edge. D3D keeps top-left,
    // OpenGL (as llvmpipe draws in window space) keeps bottom-left. An excluded edge needs
    // E > 0, i.e. E - 1 >= 0.
    const bool horizontal_kept = state.fill_rule == FillRule::kD3D ? dx > 0 : dx < 0;
    const bool included = dy < 0 || (dy == 0 && horizontal_kept);
    if (!included) f.c -= 1;
    out.edge[e] = f;
  }

  // Samples of pixel px lie in [px * 256, px * 256 + 240] (offsets -8..7 sixteenths), so the
  // pixels that can hold a covered sample are floor(min / 256) .. floor(max / 256).
  const auto [minx, maxx] = std::minmax({p[0].x, p[1].x, p[2].x});
  const auto [miny, maxy] = std::minmax({p[0].y, p[1].y, p[2].y});
  out.bx0 = std::max(area.x0, minx >> kSubpixelBits);
  out.by0 = std::max(area.y0, miny >> kSubpixelBits);
  out.bx1 = std::min(area.x1, (maxx >> kSubpixelBits) + 1);
  out.by1 = std::min(area.y1, (maxy >> kSubpixelBits) + 1);
  if (out.bx0 >= out.bx1 || out.by0 >= out.by1) return SetupReject::kOutside;
  if (spots &&
      !box_holds_sample(*spots, minx, maxx, miny, maxy, out.bx0, out.bx1, out.by0, out.by1))
    return SetupReject::kNoSample;
  if (spots && !shrink_to_covered(out, *spots)) return SetupReject::kNoCoveredSample;

  std::array<double, 3> X, Y, Z, Q;
  for (int i = 0; i < 3; ++i) {
    X[i] = p[idx[i]].x / kUnitsPerPx;
    Y[i] = p[idx[i]].y / kUnitsPerPx;
    Z[i] = v[idx[i]].z;
    Q[i] = v[idx[i]].q;
  }
  const double area_px2 =
      static_cast<double>(area2 < 0 ? -area2 : area2) / (kUnitsPerPx * kUnitsPerPx);
  if (basis) *basis = {X, Y, idx, area_px2};
  out.x0 = static_cast<float>(X[0]);
  out.y0 = static_cast<float>(Y[0]);
  out.z = make_plane(X, Y, area_px2, Z[0], Z[1], Z[2]);
  out.z_min = static_cast<float>(std::min({Z[0], Z[1], Z[2]}));
  out.z_max = static_cast<float>(std::max({Z[0], Z[1], Z[2]}));

  out.planes_base = kNoPlanes;
  out.color = flat_color;
  if (per_vertex_color) {
    const auto& c0 = v[idx[0]].color;
    const auto& c1 = v[idx[1]].color;
    const auto& c2 = v[idx[2]].color;
    // Equal vertex colours need no interpolation: flat is both faster and exact.
    if (planes && (c0 != c1 || c0 != c2)) {
      const std::array<double, 3> qn = normalised_q(Q);
      std::array<Plane, kColorPlanes> cp;
      cp[0] = make_plane(X, Y, area_px2, qn[0], qn[1], qn[2]);
      for (int ch = 0; ch < kColorChannels; ++ch)
        cp[1 + ch] = make_plane(X, Y, area_px2, c0[ch] * qn[0], c1[ch] * qn[1], c2[ch] * qn[2]);
      keep_color_planes(cp, *planes, out);
    }
    if (is_flat(out)) {
      out.color = {to_unorm8(static_cast<float>(c0[0])), to_unorm8(static_cast<float>(c0[1])),
                   to_unorm8(static_cast<float>(c0[2])), to_unorm8(static_cast<float>(c0[3]))};
    }
  }
  if (area.moved()) area.move(out);
  return SetupReject::kNone;
}

void setup_varyings(const std::array<ScreenVertex, 3>& v, const PlaneBasis& basis,
                    const std::array<const double*, 3>& values, int count, TriangleSetup& out,
                    PlaneArray& planes) {
  if (count == 0) {
    out.planes_base = kNoPlanes;
    return;
  }
  out.planes_base = static_cast<std::uint32_t>(planes.size());
  const auto& [X, Y, idx, area_px2] = basis;
  const double* a[3] = {values[idx[0]], values[idx[1]], values[idx[2]]};
  const std::array<double, 3> qn = normalised_q({v[idx[0]].q, v[idx[1]].q, v[idx[2]].q});
  planes.push_back(make_plane(X, Y, area_px2, qn[0], qn[1], qn[2]));
  bool ok = is_finite(planes.back());
  for (int k = 0; k < count; ++k) {
    planes.push_back(make_plane(X, Y, area_px2, a[0][k] * qn[0], a[1][k] * qn[1], a[2][k] * qn[2]));
    ok = ok && is_finite(planes.back());
  }
  if (ok) return;
  planes[out.planes_base] = {1.0f, 0.0f, 0.0f};
  for (int k = 0; k < count; ++k) {
    const std::uint32_t i = out.planes_base + 1 + static_cast<std::uint32_t>(k);  // after q
    planes[i] = {static_cast<float>(a[0][k]), 0, 0};
  }
}

}  // namespace mosaic::front
