#include "bin/binner.hpp"

#include <algorithm>
#include <iterator>

namespace mosaic::bin {

raster::TileRect TileGrid::rect(int tile) const {
  const int tx = tile % tiles_x, ty = tile / tiles_x;
  raster::TileRect r;
  r.x0 = tx * size;
  r.y0 = ty * size;
  r.width = std::min(size, width - r.x0);
  r.height = std::min(size, height - r.y0);
  return r;
}

namespace {

// True when no edge of `t` rejects the whole tile (tx, ty), a square of `span` 16.8 units that
// holds every sample of the tile: the largest value of each edge function over the square,
// found at one of its corners, must be >= 0.
bool edges_touch(const front::TriangleSetup& t, int tx, int ty, std::int64_t span) {
  const std::int64_t x0 = tx * span, y0 = ty * span;
  for (const front::EdgeFunction& e : t.edge) {
    const std::int64_t hi =
        e(x0, y0) + std::max<std::int64_t>(0, e.a * span) + std::max<std::int64_t>(0, e.b * span);
    if (hi < 0) return false;
  }
  return true;
}

}  // namespace

std::uint64_t bin_chunk(Chunk& c, const TileGrid& grid) {
  const int tiles = grid.count();
  c.offsets.assign(static_cast<std::size_t>(tiles) + 1, 0);
  c.pairs.clear();
  const int shift = grid.shift;  // (boxes are inside the image: never negative)
  const std::int64_t span = std::int64_t{grid.size} * front::kSubpixelOne;
  for (std::uint32_t i = 0; i < c.tris.size(); ++i) {
    const front::TriangleSetup& t = c.tris[i];
    const int tx0 = t.bx0 >> shift, tx1 = (t.bx1 - 1) >> shift;
    const int ty0 = t.by0 >> shift, ty1 = (t.by1 - 1) >> shift;
    const bool single = tx0 == tx1 && ty0 == ty1;
    for (int ty = ty0; ty <= ty1; ++ty) {
      for (int tx = tx0; tx <= tx1; ++tx) {
        if (!single && !edges_touch(t, tx, ty, span)) continue;
        const std::uint32_t tile = static_cast<std::uint32_t>(ty * grid.tiles_x + tx);
        c.pairs.push_back(std::uint64_t{tile} << 32 | i);
        ++c.offsets[tile + 1];
      }
    }
  }
  for (int t = 0; t < tiles; ++t) c.offsets[t + 1] += c.offsets[t];
  // Counting sort by tile; pairs are produced in triangle order, so each bin stays in order.
  c.indices.resize(c.pairs.size());
  std::vector<std::uint32_t>& cursor = c.offsets;  // reused below, then restored
  for (const std::uint64_t p : c.pairs) {
    const std::uint32_t tile = static_cast<std::uint32_t>(p >> 32);
    c.indices[cursor[tile]++] = static_cast<std::uint32_t>(p);
  }
  // After the scatter, cursor[t] is the end of bin t: shift back to get the starts.
  for (int t = tiles; t > 0; --t) c.offsets[t] = c.offsets[t - 1];
  c.offsets[0] = 0;
  return c.pairs.size();
}

void ChunkPlan::build(std::span<const std::uint32_t> draw_triangles,
                      std::uint32_t chunk_triangles) {
  pieces_.clear();
  first_.assign(1, 0);
  std::uint32_t room = chunk_triangles;  // left in the last chunk
  for (std::uint32_t d = 0; d < draw_triangles.size(); ++d) {
    for (std::uint32_t b = 0; b < draw_triangles[d];) {
      if (room == 0) {
        first_.push_back(static_cast<std::uint32_t>(pieces_.size()));
        room = chunk_triangles;
      }
      const std::uint32_t e = b + std::min(room, draw_triangles[d] - b);
      pieces_.push_back({d, b, e});
      room -= e - b;
      b = e;
    }
  }
  if (!pieces_.empty()) first_.push_back(static_cast<std::uint32_t>(pieces_.size()));
}

void ChunkPlan::single() {
  pieces_.assign(1, {});
  first_ = {0, 1};
}

std::uint32_t set_up_chunk(Chunk& chunk, std::span<const ChunkPiece> pieces,
                           std::span<const Draw> draws, front::FrontEnd front_end, int width,
                           int height, int samples, front::FrontStats& stats,
                           std::span<const front::VertexCache> vertices) {
  chunk.tris.clear();
  chunk.planes.clear();
  chunk.draw_starts.clear();
  std::uint32_t triangles = 0;
  for (const ChunkPiece& p : pieces) {
    chunk.draw_starts.push_back({p.draw, static_cast<std::uint32_t>(chunk.tris.size())});
    front_end(draws[p.draw], p.draw, p.begin, p.end, width, height, chunk.tris, stats,
              &chunk.planes, samples, vertices.empty() ? nullptr : &vertices[p.draw]);
    triangles += p.end - p.begin;
  }
  return triangles;
}

void append_runs(const Chunk& chunk, int tile, std::vector<raster::BinRun>& runs) {
  const std::span<const std::uint32_t> bin = chunk.bin(tile);
  if (bin.empty()) return;
  const std::vector<DrawStart>& starts = chunk.draw_starts;
  if (starts.empty()) {
    runs.push_back({chunk.tris.data(), bin, chunk.planes.data(), raster::BinRun::kMixedDraws});
    return;
  }
  // Both lists ascend: find the draw of each run's first triangle, then where that draw ends.
  auto draw_of = starts.begin();
  for (auto it = bin.begin(); it != bin.end();) {
    draw_of = std::prev(
        std::upper_bound(draw_of, starts.end(), *it,
                         [](std::uint32_t i, const DrawStart& s) { return i < s.first; }));
    const auto next = std::next(draw_of);
    const auto end =
        next == starts.end() ? bin.end() : std::lower_bound(it, bin.end(), next->first);
    runs.push_back({chunk.tris.data(), std::span<const std::uint32_t>(it, end), chunk.planes.data(),
                    draw_of->draw});
    it = end;
  }
}

}  // namespace mosaic::bin
