// front/front_end.hpp — the whole front end for a range of triangles of one draw.
//
// Takes: a Draw (validated), a triangle range, and the target size. Gives: TriangleSetups in
// submission order (a clipped triangle becomes a fan of several), and counters.
// Vertex fetch and transform, the non-finite check, clipping, the perspective divide, snapping,
// culling and setup happen here, in that order. It is pure and reentrant: the fast path runs
// it on many chunks in parallel, the reference on everything at once.
#pragma once

#include <cstdint>
#include <vector>

#include "front/setup.hpp"
#include "mosaic/draw.hpp"
#include "mosaic/renderer.hpp"

namespace mosaic::front {

/// Counters of the front end; they add up over chunks.
struct FrontStats {
  std::uint64_t in = 0, nonfinite = 0, culled_face = 0, degenerate = 0, outside = 0, clipped = 0,
                drawn = 0;
  FrontStats& operator+=(const FrontStats& o);
  void add_to(FrameStats& s) const;
};

/// Number of triangles a (validated) draw submits.
std::uint32_t triangle_count(const Draw& draw);

/// Runs the front end on triangles [begin, end) of `draw`, appending to `out`.
/// `draw_index` is the draw's index in the frame. The varying planes of a shader draw go to
/// `planes` (TriangleSetup::varying_base indexes it); without `planes` none are set up (the
/// occlusion queries need depth only).
void run_front_end(const Draw& draw, std::uint32_t draw_index, std::uint32_t begin,
                   std::uint32_t end, int width, int height, std::vector<TriangleSetup>& out,
                   FrontStats& stats, std::vector<Plane>* planes = nullptr);

}  // namespace mosaic::front
