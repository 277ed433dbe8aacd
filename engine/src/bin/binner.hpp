// bin/binner.hpp — sorting triangles into screen tiles.
//
// Takes: one chunk of set-up triangles (in submission order) and the tile grid. Gives: for every
// tile, the indices of the chunk's triangles that may cover a sample in it, in submission order
// (a CSR table: offsets per tile into one index array). Each chunk is binned by one thread into
// its own table; tile workers read the chunks' tables in chunk order, which merges the bins in
// submission order without copying — so the image never depends on the thread count.
#pragma once

#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "front/front_end.hpp"
#include "front/setup.hpp"
#include "raster/tile.hpp"

namespace mosaic::bin {

/// The screen divided into square tiles of `size` pixels; the last column and row may be partial.
struct TileGrid {
  int width = 0, height = 0;
  int size = 0;   ///< tile edge in pixels: a power of two, at least raster::kBlockSize
  int shift = 0;  ///< log2(size): binning divides pixel coordinates by shifting
  int tiles_x = 0, tiles_y = 0;
  TileGrid() = default;
  TileGrid(int w, int h, int tile_size)
      : width(w),
        height(h),
        size(tile_size),
        shift(std::countr_zero(unsigned(tile_size))),
        tiles_x((w + size - 1) / size),
        tiles_y((h + size - 1) / size) {}
  int count() const { return tiles_x * tiles_y; }
  raster::TileRect rect(int tile) const;
};

/// Triangles per front-end chunk: large enough that a chunk's bookkeeping (a tile-offset table
/// of tiles + 1 entries) is small next to its work, small enough that 100k triangles give
/// dozens of chunks to balance over the workers.
inline constexpr std::uint32_t kChunkTriangles = 2048;

/// Triangles [begin, end) of draw `draw`: a chunk's share of one draw.
struct ChunkPiece {
  std::uint32_t draw = 0, begin = 0, end = 0;
};

/// The frame's triangles cut, in submission order, into chunks of at most `chunk_triangles`.
/// A chunk may hold pieces of several draws: binning a chunk and reading its bins cost time in
/// proportion to the tile count, so a frame of many small draws must not make a chunk per draw.
class ChunkPlan {
 public:
  /// Plans `draws` (triangle_count() of each), every draw's triangles in order.
  void build(std::span<const std::uint32_t> draw_triangles, std::uint32_t chunk_triangles);
  /// One chunk holding every triangle of the frame (the painter's sorted frame).
  void single();
  std::size_t chunks() const { return first_.size() - 1; }
  std::span<const ChunkPiece> pieces(std::size_t chunk) const {
    return {pieces_.data() + first_[chunk], pieces_.data() + first_[chunk + 1]};
  }

 private:
  std::vector<ChunkPiece> pieces_;
  std::vector<std::uint32_t> first_{0};  ///< chunk c's pieces are [first_[c], first_[c + 1])
};

/// Where a draw's setups begin in a chunk's `tris`.
struct DrawStart {
  std::uint32_t draw = 0, first = 0;
};

/// One chunk's triangles and bins. The vectors keep their capacity from frame to frame: after
/// the first frames, a frame allocates nothing per triangle.
struct Chunk {
  std::vector<front::TriangleSetup> tris;
  /// Per piece, in order; empty when the chunk's triangles come from draws in any order (the
  /// painter's), whose runs then name each triangle's draw (raster::BinRun::kMixedDraws).
  std::vector<DrawStart> draw_starts;
  std::vector<front::Plane> planes;    ///< out-of-line planes: interpolated colours, varyings
  std::vector<std::uint32_t> offsets;  ///< per tile: bin [offsets[t], offsets[t+1]) of indices
  std::vector<std::uint32_t> indices;  ///< triangle indices into `tris`, grouped by tile
  std::vector<std::uint64_t> pairs;    ///< scratch: (tile << 32 | triangle) before grouping

  std::span<const std::uint32_t> bin(int tile) const {
    return {indices.data() + offsets[tile], indices.data() + offsets[tile + 1]};
  }
};

/// Sets up `pieces` into `chunk` (replacing what it held) with `front_end`, piece by piece, and
/// records where each draw starts. Returns the triangles submitted. `vertices`: one cache per
/// draw from the vertex stage (front/vertex_stage.hpp), or empty for none.
std::uint32_t set_up_chunk(Chunk& chunk, std::span<const ChunkPiece> pieces,
                           std::span<const Draw> draws, front::FrontEnd front_end, int width,
                           int height, int samples, front::FrontStats& stats,
                           std::span<const front::VertexCache> vertices = {});

/// Appends the runs of `chunk`'s bin for `tile` to `runs`, one per draw, in order.
void append_runs(const Chunk& chunk, int tile, std::vector<raster::BinRun>& runs);

/// Bins `chunk.tris` into `chunk.offsets` / `chunk.indices`, and returns the number of (triangle,
/// tile) pairs. A triangle whose bounding box spans several tiles goes only to the tiles that its
/// three edges do not trivially reject. (Setup has culled those that cover no sample.)
std::uint64_t bin_chunk(Chunk& chunk, const TileGrid& grid);

}  // namespace mosaic::bin
