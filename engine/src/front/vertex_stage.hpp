// front/vertex_stage.hpp — the vertex stage: each vertex of an indexed draw projected once per
// frame, before its triangles are set up.
//
// Takes: a Draw (validated) and the target size. Gives: per vertex, what the front end computes
// of it for each triangle corner that names it (VertexFetch, the clip tests, the perspective
// divide, snapping) as a ProjectedVertex. These are functions of the vertex alone, so
// a triangle set up from its corners' entries gets the same bits as one set up from the draw.
// The SIMD front end (front/setup_simd.hpp) fills the cache in lanes of vertices and gathers
// from it in lanes of triangles; the scalar front end, the oracle, never reads it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "mosaic/draw.hpp"

namespace mosaic::front {

/// What the vertex stage keeps of a vertex, 32 bytes; the SIMD front end gathers each field.
struct alignas(32) ProjectedVertex {
  /// The snapped window position in 16.8 units: integers of at most 2^23 in magnitude (the guard
  /// band), exact in float.
  float px, py;
  float z;             ///< Z / W rounded to float, as ScreenVertex::z
  std::uint32_t code;  ///< vertex_code bits
  double q;            ///< 1 / W
  std::uint32_t rgba;  ///< a kPerVertex draw's colour: bytes r, g, b, a from the low one
  std::uint32_t unused;
};
static_assert(sizeof(ProjectedVertex) == 32, "a record is 32 bytes, two to a cache line");

/// The bits of a vertex's code.
namespace vertex_code {
/// Beyond one clip plane (x < 0, x > width, y < 0, y > height, z < 0, z > w in window space). A
/// triangle whose three corners share one of these bits is outside the view.
inline constexpr std::uint8_t kLeft = 1, kRight = 2, kTop = 4, kBottom = 8, kNear = 16, kFar = 32;
inline constexpr std::uint8_t kClipPlanes = 63;
/// Beyond the guard band or the depth range, or with no finite screen position (W <= 0): a
/// triangle using it needs clipping, which the scalar front end does, unless it is outside.
inline constexpr std::uint8_t kClip = 64;
/// A NaN or infinite coordinate: the scalar front end takes (and counts) its triangles.
inline constexpr std::uint8_t kNonFinite = 128;
}  // namespace vertex_code

/// One draw's projected vertices, indexed like its positions: a view of VertexRecords. Empty
/// for a draw left to the front end's own fetch.
struct VertexCache {
  ProjectedVertex* data = nullptr;
  std::size_t size = 0;
  bool empty() const { return size == 0; }
};

/// The vertices a draw gives (positions or positions_xyz).
inline std::size_t vertex_count(const Draw& draw) {
  return draw.positions_xyz.empty() ? draw.positions.size() : draw.positions_xyz.size();
}

/// The memory of a frame's VertexCaches, kept across frames. Records are left unwritten: the
/// stage writes every one, in parallel, which is also where new pages are first touched.
class VertexRecords {
 public:
  /// Room for `n` records from data(); a larger n than before replaces the memory (and so
  /// invalidates the views into it).
  void reserve(std::size_t n) {
    if (n <= capacity_) return;
    data_ = std::make_unique_for_overwrite<ProjectedVertex[]>(n);
    capacity_ = n;
  }
  /// reserve(n), with every page of the memory written, so that no frame faults them in.
  void reserve_touched(std::size_t n) {
    reserve(n);
    if (capacity_ > 0)  // (memset of a null pointer is undefined, even of no bytes)
      std::memset(static_cast<void*>(data_.get()), 0, capacity_ * sizeof(ProjectedVertex));
  }
  ProjectedVertex* data() { return data_.get(); }

 private:
  std::unique_ptr<ProjectedVertex[]> data_;
  std::size_t capacity_ = 0;
};

/// Vertices per task of the vertex stage: a few thousand, so that a mesh of 64k vertices still
/// spreads over 16 workers, while a task's overhead stays below a percent of its work.
inline constexpr std::uint32_t kVertexStageBlock = 4096;

/// Whether a draw goes through the vertex stage: an indexed draw whose triangles name more
/// corners than it has vertices, so that projecting each vertex once does less work than
/// projecting every corner (a closed mesh names each vertex about six times).
inline bool wants_vertex_stage(const Draw& draw) {
  return !draw.indices.empty() && draw.indices.size() > vertex_count(draw);
}

/// Projects vertices [begin, end) of `draw` for a width × height target into `cache`, which is
/// sized for the draw. One per instruction set (isa_dispatch.hpp).
using VertexStageFn = void(const Draw& draw, int width, int height, std::uint32_t begin,
                           std::uint32_t end, const VertexCache& cache);
using VertexStage = VertexStageFn*;

}  // namespace mosaic::front
