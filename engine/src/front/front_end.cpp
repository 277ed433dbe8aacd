#include "front/front_end.hpp"

#include <cmath>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

namespace mosaic::front {

FrontStats& FrontStats::operator+=(const FrontStats& o) {
  in += o.in;
  nonfinite += o.nonfinite;
  culled_face += o.culled_face;
  degenerate += o.degenerate;
  outside += o.outside;
  clipped += o.clipped;
  drawn += o.drawn;
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
}

std::uint32_t triangle_count(const Draw& draw) {
  if (!draw.indices.empty()) return static_cast<std::uint32_t>(draw.indices.size() / 3);
  const std::size_t n = draw.positions_xyz.empty() ? draw.positions.size() : draw.positions_xyz.size();
  return static_cast<std::uint32_t>(n / 3);
}

namespace {

struct VertexFetch {
  const Draw& draw;
  glm::dmat4 transform;
  double half_w, half_h;

  // Fetches vertex `i` into window-homogeneous space (pixel x = X / W). Returns false when a
  // coordinate is NaN or infinite. Double precision keeps 1e30-sized coordinates finite.
  bool operator()(std::uint32_t i, ClipVertex& out) const {
    glm::dvec4 p;
    if (!draw.positions_xyz.empty()) {
      p = transform * glm::dvec4(glm::dvec3(draw.positions_xyz[i]), 1.0);
    } else {
      p = glm::dvec4(draw.positions[i]);
    }
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w))
      return false;
    if (draw.space == Space::kClip) {
      out.X = (p.x + p.w) * half_w;
      out.Y = (p.w - p.y) * half_h;
    } else {
      out.X = p.x;
      out.Y = p.y;
    }
    out.Z = p.z;
    out.W = p.w;
    if (draw.color_source == ColorSource::kPerVertex) {
      const Rgba8 c = draw.colors[i];
      out.color = {double(c.r), double(c.g), double(c.b), double(c.a)};
    }
    return true;
  }
};

// The perspective divide. False for a vertex on the eye point (W <= 0 survives clipping only
// there), which has no screen position.
bool divide(const ClipVertex& c, ScreenVertex& s) {
  if (!(c.W > 0)) return false;
  const double q = 1.0 / c.W;
  s.x = c.X * q;
  s.y = c.Y * q;
  s.z = static_cast<float>(c.Z * q);
  s.q = q;
  s.color = c.color;
  return std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(q);
}

}  // namespace

void run_front_end(const Draw& draw, std::uint32_t draw_index, std::uint32_t begin,
                   std::uint32_t end, int width, int height, std::vector<TriangleSetup>& out,
                   FrontStats& stats, std::vector<Plane>* planes) {
  const VertexFetch fetch{draw, glm::dmat4(draw.transform), width * 0.5, height * 0.5};
  const bool shader = static_cast<bool>(draw.shader);
  // A shader colours the draw: vertex colours are not set up.
  const bool per_vertex = !shader && draw.color_source == ColorSource::kPerVertex;
  const int nvary = shader && planes ? static_cast<int>(draw.varyings.size()) : 0;
  // Varyings of the submitted corners, and of the clipped polygon's vertices (weighted sums of
  // the corners' by their barycentric weights).
  std::array<std::array<double, kMaxVaryings>, 3> corner_attr;
  std::array<std::array<double, kMaxVaryings>, kMaxClipVertices> poly_attr;
  // Reused across triangles: each holds 11 vertices of 64 bytes, and constructing (zeroing) them
  // per triangle was a seventh of the front end. Only entries written for this triangle are read.
  ClipPolygon poly;
  std::array<ScreenVertex, kMaxClipVertices> sv;
  for (std::uint32_t t = begin; t < end; ++t) {
    ++stats.in;
    std::array<ClipVertex, 3> cv;
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t vi = draw.indices.empty() ? 3 * t + k : draw.indices[3 * t + k];
      finite = finite && fetch(vi, cv[k]);
      if (shader) cv[k].color = {k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0, 0.0};
    }
    if (!finite) {
      ++stats.nonfinite;
      continue;
    }
    Rgba8 flat = draw.color;
    if (draw.color_source == ColorSource::kPerTriangle) flat = draw.colors[t];

    const ClipResult r = clip_triangle(cv, width, height, poly);
    if (r == ClipResult::kCulled) {
      ++stats.outside;
      continue;
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
      continue;
    }
    if (nvary > 0) {
      for (std::uint32_t c = 0; c < 3; ++c) {
        const std::uint32_t vi = draw.indices.empty() ? 3 * t + c : draw.indices[3 * t + c];
        const std::size_t row = static_cast<std::size_t>(vi) * draw.attribute_count;
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
    bool any_drawn = false, any_face = false, any_outside = false;
    for (int k = 1; k + 1 < poly.count; ++k) {
      TriangleSetup ts;
      PlaneBasis basis;
      const std::array<ScreenVertex, 3> tri{sv[0], sv[k], sv[k + 1]};
      const SetupReject why = setup_triangle(tri, draw.state, width, height, per_vertex, flat, ts,
                                             nvary > 0 ? &basis : nullptr);
      any_face = any_face || why == SetupReject::kFace;
      any_outside = any_outside || why == SetupReject::kOutside;
      if (why != SetupReject::kNone) continue;
      if (shader && planes)
        setup_varyings(tri, basis,
                       {poly_attr[0].data(), poly_attr[k].data(), poly_attr[k + 1].data()}, nvary,
                       ts, *planes);
      ts.draw = draw_index;
      ++stats.drawn;
      any_drawn = true;
      out.push_back(ts);
    }
    if (any_drawn) continue;
    if (any_face) {
      ++stats.culled_face;
    } else if (any_outside) {
      ++stats.outside;
    } else {
      ++stats.degenerate;
    }
  }
}

}  // namespace mosaic::front
