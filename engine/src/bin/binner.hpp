// bin/binner.hpp — sorting triangles into screen tiles.
//
// Takes: one chunk of set-up triangles (in submission order) and the tile grid. Gives: for every
// tile the chunk reaches, the indices of its triangles that may cover a sample there, in
// submission order (a CSR table over the tiles reached). Each chunk is binned by one thread into
// its own table; TileChunks lists each tile's chunks, and tile workers read those chunks' bins in
// chunk order, which merges them in submission order without copying — so the image never
// depends on the thread count.
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

/// A frame whose triangles land in fewer tiles than this (a mesh far away or small on screen) is
/// binned again on tiles of kSplitTileSize, so that its tile work can spread over 16 cores.
inline constexpr int kFewBusyTiles = 16;
/// The finer tiles: 4×4 blocks. Smaller ones cost more than they spread: each triangle reaches
/// more tiles, and each tile pays its run set-up and resolve.
inline constexpr int kSplitTileSize = 32;

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
/// the first frames, a frame allocates nothing per triangle. The bins are kept for the tiles
/// that have triangles only, so that binning costs as much on a grid of many small tiles as on
/// one of few.
struct Chunk {
  std::vector<front::TriangleSetup> tris;
  /// Per piece, in order; empty when the chunk's triangles come from draws in any order (the
  /// painter's), whose runs then name each triangle's draw (raster::BinRun::kMixedDraws).
  std::vector<DrawStart> draw_starts;
  front::PlaneArray planes;            ///< out-of-line planes: interpolated colours, varyings
  std::vector<std::uint32_t> tiles;    ///< the tiles with triangles, in the order first reached
  std::vector<std::uint32_t> starts;   ///< bin j, of tiles[j], is [starts[j], starts[j + 1])
  std::vector<std::uint32_t> indices;  ///< triangle indices into `tris`, grouped by bin
  std::vector<std::uint64_t> pairs;    ///< scratch: (bin << 32 | triangle) before grouping
  /// Scratch: per tile of the grid, 1 + its bin's index while binning, and 0 otherwise (between
  /// binnings every entry is 0, so a binning clears only the entries it set).
  std::vector<std::uint32_t> slot;

  /// Bin j's triangle indices, in submission order.
  std::span<const std::uint32_t> bin(std::size_t j) const {
    return {indices.data() + starts[j], indices.data() + starts[j + 1]};
  }
};

/// Sets up `pieces` into `chunk` (replacing what it held) with `front_end`, piece by piece, and
/// records where each draw starts. Returns the triangles submitted. `vertices`: one cache per
/// draw from the vertex stage (front/vertex_stage.hpp), or empty for none.
std::uint32_t set_up_chunk(Chunk& chunk, std::span<const ChunkPiece> pieces,
                           std::span<const Draw> draws, front::FrontEnd front_end, int width,
                           int height, int samples, front::FrontStats& stats,
                           std::span<const front::VertexCache> vertices = {});

/// For every tile, the chunks with triangles in it and the index of its bin in each, in chunk
/// order: a tile's reader visits only those, so that a frame's bookkeeping grows with the
/// (chunk, tile) pairs that hold triangles, not with chunks × tiles (512 chunks of a 1 M-triangle
/// mesh and 2,040 tiles of 32 px are a million pairs, nearly all empty).
class TileChunks {
 public:
  /// A chunk and the index of a tile's bin in it.
  struct Entry {
    std::uint32_t chunk = 0, bin = 0;
  };
  /// Indexes `chunks` (binned on a grid of `tiles` tiles).
  void build(std::span<const Chunk> chunks, int tiles);
  std::span<const Entry> of(int tile) const {
    return {entries_.data() + first_[tile], entries_.data() + first_[tile + 1]};
  }
  /// The triangles binned into `tile`, over every chunk.
  std::uint64_t triangles(std::span<const Chunk> chunks, int tile) const;
  /// Tiles with at least one triangle.
  int busy_tiles() const { return busy_; }
  /// Tiles of `coarse` that hold a busy tile of `grid`, a finer grid of the same image whose
  /// tiles nest in them. (At most the busy tiles binning on `coarse` would find: a triangle's
  /// conservative edge test may pass a tile and none of the tiles nested in it.)
  int busy_tiles_on(const TileGrid& grid, const TileGrid& coarse) const;

 private:
  std::vector<std::uint32_t> first_;  ///< tile t's entries are [first_[t], first_[t + 1])
  std::vector<Entry> entries_;        ///< grouped by tile
  int busy_ = 0;
  mutable std::vector<std::uint8_t> marks_;  ///< scratch of busy_tiles_on()
};

/// Appends the runs of `chunk`'s bin j to `runs`, one per draw, in order.
void append_runs(const Chunk& chunk, std::size_t j, std::vector<raster::BinRun>& runs);

/// Bins `chunk.tris` into `chunk.tiles` / `starts` / `indices`, and returns the number of
/// (triangle, tile) pairs. A triangle whose bounding box spans several tiles goes only to the tiles
/// that its three edges do not trivially reject. (Setup has culled those that cover no sample.)
std::uint64_t bin_chunk(Chunk& chunk, const TileGrid& grid);

}  // namespace mosaic::bin
