// front/front_end.hpp — the whole front end for a range of triangles of one draw.
//
// Takes: a Draw (validated), a triangle range, and the target size. Gives: TriangleSetups in
// submission order (a clipped triangle becomes a fan of several), and counters.
// Vertex fetch and transform, the non-finite check, clipping, the perspective divide, snapping,
// culling and setup happen here, in that order. It is pure and reentrant: the fast path runs
// it on many chunks in parallel, the reference on everything at once.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "front/draw_area.hpp"
#include "front/setup.hpp"
#include "front/vertex_stage.hpp"
#include "mosaic/draw.hpp"
#include "mosaic/renderer.hpp"

namespace mosaic::front {

/// Counters of the front end; they add up over chunks.
struct FrontStats {
  std::uint64_t in = 0, nonfinite = 0, culled_face = 0, degenerate = 0, outside = 0, clipped = 0,
                drawn = 0;
  /// Culled: the box holds no sample position, or the triangle covers none of the few it holds
  /// (SetupReject::kNoSample, kNoCoveredSample).
  std::uint64_t no_sample = 0;
  /// The range held an index past the draw's last vertex, and was not set up: the frame throws.
  /// (Renderer::render() leaves the index check to the front end, which reads them anyway.)
  bool index_out_of_range = false;
  FrontStats& operator+=(const FrontStats& o);
  void add_to(FrameStats& s) const;
};

/// Number of triangles a (validated) draw submits.
std::uint32_t triangle_count(const Draw& draw);

/// Runs the front end on triangles [begin, end) of `draw`, appending to `out`.
/// `draw_index` is the draw's index in the frame. The planes of interpolated colours and of a
/// shader draw's varyings go to `planes` (TriangleSetup::planes_base indexes it); without
/// `planes` none are set up (the occlusion queries need depth only; front/setup.hpp says what
/// the triangles get instead). This is the scalar front end: the oracle, and the
/// fallback of the SIMD one (front/setup_simd.hpp), which gives the same output.
/// `samples`: the frame's sample count, whose pattern culls triangles whose box holds no sample
/// position (0: no such cull, as the occlusion queries ask).
/// `vertices`: the draw's projected vertices (front/vertex_stage.hpp), or null or empty. The
/// SIMD front ends read them instead of the draw's positions; this one, the oracle, ignores them.
/// A range that holds an index out of range sets nothing up and sets stats.index_out_of_range.
void run_front_end(const Draw& draw, std::uint32_t draw_index, std::uint32_t begin,
                   std::uint32_t end, int width, int height, std::vector<TriangleSetup>& out,
                   FrontStats& stats, PlaneArray* planes = nullptr, int samples = 0,
                   const VertexCache* vertices = nullptr);

/// A front end with run_front_end()'s signature: the scalar one or a SIMD one (isa_dispatch.hpp).
using FrontEndFn = void(const Draw& draw, std::uint32_t draw_index, std::uint32_t begin,
                        std::uint32_t end, int width, int height, std::vector<TriangleSetup>& out,
                        FrontStats& stats, PlaneArray* planes, int samples,
                        const VertexCache* vertices);
using FrontEnd = FrontEndFn*;

/// Vertex fetch: a draw's vertex in window-homogeneous space (pixel x = X / W).
struct VertexFetch {
  const Draw& draw;
  glm::dmat4 transform;
  double half_w, half_h;

  VertexFetch(const Draw& d, int width, int height)
      : draw(d), transform(glm::dmat4(d.transform)), half_w(width * 0.5), half_h(height * 0.5) {}

  /// Index of corner `k` of triangle `t`.
  std::uint32_t vertex(std::uint32_t t, int k) const {
    return draw.indices.empty() ? 3 * t + k : draw.indices[3 * t + k];
  }

  // Fetches vertex `i`. Returns false when a coordinate is NaN or infinite. Double precision
  // keeps 1e30-sized coordinates finite. Always inlined: an out-of-line copy compiled into one
  // instruction set's objects could be the one the linker keeps for every caller.
  [[gnu::always_inline]] bool operator()(std::uint32_t i, ClipVertex& out) const {
    glm::dvec4 p;
    if (!draw.positions_xyz.empty()) {
      p = transform * glm::dvec4(glm::dvec3(draw.positions_xyz[i]), 1.0);
    } else {
      p = glm::dvec4(draw.positions[i]);
    }
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w))
      return false;
    to_window(p.x, p.y, p.w, out.X, out.Y);
    out.Z = p.z;
    out.W = p.w;
    if (draw.color_source == ColorSource::kPerVertex) out.color = color(i);
    return true;
  }

  /// Vertex `i`'s colour as ClipVertex::color holds it.
  std::array<double, kColorChannels> color(std::uint32_t i) const {
    const Rgba8 c = draw.colors[i];
    return {double(c.r), double(c.g), double(c.b), double(c.a)};
  }

  /// A clip-space position's window-homogeneous x and y (y down); screen space is already so.
  /// A template for the SIMD front end, which maps double lanes with it.
  template <class T>
  void to_window(T x, T y, T w, T& X, T& Y) const {
    if (draw.space == Space::kClip) {
      X = (x + w) * T(half_w);
      Y = (w - y) * T(half_h);
    } else {
      X = x;
      Y = y;
    }
  }
};

/// The scalar front end of one triangle at a time, with its scratch kept between triangles:
/// run_front_end() runs it on every triangle, the SIMD front end on those its lanes leave (a
/// triangle that needs clipping, a non-finite one, ...).
class TriangleFrontEnd {
 public:
  /// For a width × height target; the draw's viewport and scissor give its DrawArea.
  TriangleFrontEnd(const Draw& draw, std::uint32_t draw_index, int width, int height,
                   std::vector<TriangleSetup>& out, FrontStats& stats, PlaneArray* planes,
                   int samples = 0);

  /// Runs triangle `t` of the draw: appends its setups to `out`, counts it in `stats`.
  void run(std::uint32_t t);

  const DrawArea area;  ///< where the draw lands: set up in its viewport, moved into the target
  const VertexFetch fetch;
  const bool shader;        ///< the draw has a shader
  const bool per_vertex;    ///< vertex colours are set up (a shader colours the draw itself)
  const int nvary;          ///< varyings set up per triangle
  const SampleSpots spots;  ///< the frame's sample positions, for setup's cull (count 0: none)
  /// When set, gets each appended setup's sort_depth() (front/setup.hpp), in `out`'s order: the
  /// painter's path sorts by it (reference::setup_frame()).
  std::vector<float>* sort_keys = nullptr;

 private:
  const Draw& draw_;
  std::uint32_t draw_index_;
  std::vector<TriangleSetup>& out_;
  FrontStats& stats_;
  PlaneArray* planes_;
  // Varyings of the submitted corners, and of the clipped polygon's vertices (weighted sums of
  // the corners' by their barycentric weights).
  std::array<std::array<double, kMaxVaryings>, 3> corner_attr_;
  std::array<std::array<double, kMaxVaryings>, kMaxClipVertices> poly_attr_;
  // Reused across triangles: each holds 11 vertices of 64 bytes, and constructing (zeroing) them
  // per triangle was a seventh of the front end. Only entries written for this triangle are read.
  ClipPolygon poly_;
  std::array<ScreenVertex, kMaxClipVertices> sv_;
};

}  // namespace mosaic::front
