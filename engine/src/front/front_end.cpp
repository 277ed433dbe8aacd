#include "front/front_end.hpp"

#include <algorithm>
#include <cmath>

namespace mosaic::front {

FrontStats& FrontStats::operator+=(const FrontStats& o) {
  in += o.in;
  nonfinite += o.nonfinite;
  culled_face += o.culled_face;
  degenerate += o.degenerate;
  outside += o.outside;
  clipped += o.clipped;
  drawn += o.drawn;
  no_sample += o.no_sample;
  index_out_of_range = index_out_of_range || o.index_out_of_range;
  return *this;
}

void FrontStats::add_to(FrameStats& s) const {
  s.triangles_in += in;
  s.triangles_nonfinite += nonfinite;
  s.triangles_culled_face += culled_face;
  s.triangles_degenerate += degenerate;
  s.triangles_outside += outside;
  s.triangles_clipped += clipped;
  s.triangles_drawn += drawn;
  s.triangles_no_sample += no_sample;
}

std::uint32_t triangle_count(const Draw& draw) {
  if (!draw.indices.empty()) return static_cast<std::uint32_t>(draw.indices.size() / 3);
  return static_cast<std::uint32_t>(vertex_count(draw) / 3);
}

namespace {

// The perspective divide. False for a vertex on the eye point (W <= 0 survives clipping only
// there), which has no screen position. Clipping keeps 0 <= Z <= W only in exact arithmetic: a
// clipped vertex's rounding, divided by a tiny W, can leave [0, 1], so depth is clamped to the
// range (a no-op for a vertex that was not clipped, which the SIMD front end also divides).
bool divide(const ClipVertex& c, ScreenVertex& s) {
  if (!(c.W > 0)) return false;
  const double q = 1.0 / c.W;
  s.x = c.X * q;
  s.y = c.Y * q;
  s.z = std::clamp(static_cast<float>(c.Z * q), 0.0f, 1.0f);
  s.q = q;
  s.color = c.color;
  return std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(q);
}

}  // namespace

TriangleFrontEnd::TriangleFrontEnd(const Draw& draw, std::uint32_t draw_index, int width,
                                   int height, std::vector<TriangleSetup>& out, FrontStats& stats,
                                   PlaneArray* planes, int samples)
    : area(DrawArea::of(draw.state, width, height)),
      fetch(draw, area.width, area.height),
      shader(static_cast<bool>(draw.shader)),
      // A shader colours the draw: vertex colours are not set up.
      per_vertex(!shader && draw.color_source == ColorSource::kPerVertex),
      nvary(shader && planes ? static_cast<int>(draw.varyings.size()) : 0),
      spots(SampleSpots::of(samples)),
      draw_(draw),
      draw_index_(draw_index),
      out_(out),
      stats_(stats),
      planes_(planes) {}

void TriangleFrontEnd::run(std::uint32_t t) {
  const Draw& draw = draw_;
  FrontStats& stats = stats_;
  ClipPolygon& poly = poly_;
  auto& sv = sv_;
  auto& corner_attr = corner_attr_;
  auto& poly_attr = poly_attr_;
  ++stats.in;
  std::array<ClipVertex, 3> cv;
  bool finite = true;
  for (int k = 0; k < 3; ++k) {
    finite = finite && fetch(fetch.vertex(t, k), cv[k]);
    if (shader) cv[k].color = {k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0, 0.0};
  }
  if (!finite) {
    ++stats.nonfinite;
    return;
  }
  Rgba8 flat = draw.color;
  if (draw.color_source == ColorSource::kPerTriangle) flat = draw.colors[t];

  const ClipResult r = clip_triangle(cv, area.width, area.height, poly);
  if (r == ClipResult::kCulled) {
    ++stats.outside;
    return;
  }
  if (r == ClipResult::kInside) {
    poly.count = 3;
    for (int k = 0; k < 3; ++k) poly.v[k] = cv[k];
  } else {
    ++stats.clipped;
  }
  bool ok = true;
  for (int k = 0; k < poly.count; ++k) ok = ok && divide(poly.v[k], sv[k]);
  if (!ok) {
    ++stats.degenerate;
    return;
  }
  if (nvary > 0) {
    for (int c = 0; c < 3; ++c) {
      const std::size_t row = static_cast<std::size_t>(fetch.vertex(t, c)) * attribute_row(draw);
      for (int k = 0; k < nvary; ++k) corner_attr[c][k] = draw.attributes[row + draw.varyings[k]];
    }
    if (r == ClipResult::kInside) {
      for (int c = 0; c < 3; ++c) poly_attr[c] = corner_attr[c];
    } else {
      // (Not for unclipped corners: 0 * an infinite attribute would make NaN of a finite one.)
      for (int j = 0; j < poly.count; ++j) {
        const auto& b = poly.v[j].color;  // barycentric weights (front/clip.hpp)
        for (int k = 0; k < nvary; ++k)
          poly_attr[j][k] =
              b[0] * corner_attr[0][k] + b[1] * corner_attr[1][k] + b[2] * corner_attr[2][k];
      }
    }
  }
  // A clipped polygon is drawn as a fan around its first vertex. The rejection counters count
  // submitted triangles: a polygon none of whose pieces is drawn counts once, face culling
  // first (every piece has the polygon's winding); a piece rejected beside drawn ones is a
  // sliver or an off-screen part of a drawn triangle and is not counted.
  bool any_drawn = false, any_face = false, any_outside = false, any_no_sample = false;
  for (int k = 1; k + 1 < poly.count; ++k) {
    TriangleSetup ts;
    PlaneBasis basis;
    const std::array<ScreenVertex, 3> tri{sv[0], sv[k], sv[k + 1]};
    const SetupReject why =
        setup_triangle(tri, draw.state, area, per_vertex, flat, ts, planes_,
                       nvary > 0 || sort_keys ? &basis : nullptr, spots.count ? &spots : nullptr);
    any_face = any_face || why == SetupReject::kFace;
    any_outside = any_outside || why == SetupReject::kOutside;
    any_no_sample = any_no_sample || why == SetupReject::kNoSample;
    if (why == SetupReject::kNoCoveredSample) {
      // A piece that set up but covers none of its box's samples is counted by piece, as
      // drawn pieces are, and leaves the polygon's counters to the other pieces.
      ++stats.no_sample;
      any_drawn = true;
      continue;
    }
    if (why != SetupReject::kNone) continue;
    if (shader && planes_)
      setup_varyings(tri, basis,
                     {poly_attr[0].data(), poly_attr[k].data(), poly_attr[k + 1].data()}, nvary, ts,
                     *planes_);
    ts.set_draw(draw_index_, ts.back_face());
    if (sort_keys) sort_keys->push_back(sort_depth(tri, basis));
    ++stats.drawn;
    any_drawn = true;
    out_.push_back(ts);
  }
  if (any_drawn) return;
  if (any_face) {
    ++stats.culled_face;
  } else if (any_outside) {
    ++stats.outside;
  } else if (any_no_sample) {
    ++stats.no_sample;
  } else {
    ++stats.degenerate;
  }
}

void run_front_end(const Draw& draw, std::uint32_t draw_index, std::uint32_t begin,
                   std::uint32_t end, int width, int height, std::vector<TriangleSetup>& out,
                   FrontStats& stats, PlaneArray* planes, int samples,
                   const VertexCache* /*vertices*/) {
  if (!draw.indices.empty()) {
    const std::size_t vertices = vertex_count(draw);
    for (std::size_t i = 3 * std::size_t{begin}; i < 3 * std::size_t{end}; ++i) {
      if (draw.indices[i] >= vertices) {
        stats.index_out_of_range = true;
        return;
      }
    }
  }
  TriangleFrontEnd front(draw, draw_index, width, height, out, stats, planes, samples);
  for (std::uint32_t t = begin; t < end; ++t) front.run(t);
}

}  // namespace mosaic::front
