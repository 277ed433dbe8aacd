#include "bin/binner.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

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
  // Grows with zeros; every entry is 0 again when this returns.
  if (c.slot.size() < static_cast<std::size_t>(grid.count()))
    c.slot.resize(static_cast<std::size_t>(grid.count()));
  c.pairs.clear();
  c.tiles.clear();
  c.starts.clear();              // the bins' counts until the prefix sum below
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
        std::uint32_t& slot = c.slot[tile];
        if (slot == 0) {
          c.tiles.push_back(tile);
          c.starts.push_back(0);
          slot = static_cast<std::uint32_t>(c.tiles.size());
        }
        ++c.starts[slot - 1];
        c.pairs.push_back(std::uint64_t{slot - 1} << 32 | i);
      }
    }
  }
  for (const std::uint32_t tile : c.tiles) c.slot[tile] = 0;
  // Counts to starts (exclusive prefix sum), one more for the end.
  std::uint32_t sum = 0;
  for (std::uint32_t& n : c.starts) sum += std::exchange(n, sum);
  c.starts.push_back(sum);
  // Counting sort by bin; pairs are produced in triangle order, so each bin stays in order.
  c.indices.resize(c.pairs.size());
  std::vector<std::uint32_t>& cursor = c.starts;  // reused below, then restored
  for (const std::uint64_t p : c.pairs) {
    const auto j = static_cast<std::uint32_t>(p >> 32);
    c.indices[cursor[j]++] = static_cast<std::uint32_t>(p);
  }
  // After the scatter, cursor[j] is the end of bin j: shift back to get the starts.
  for (std::size_t j = c.tiles.size(); j > 0; --j) c.starts[j] = c.starts[j - 1];
  c.starts[0] = 0;
  return c.pairs.size();
}

void TileChunks::build(std::span<const Chunk> chunks, int tiles) {
  first_.assign(static_cast<std::size_t>(tiles) + 1, 0);
  for (const Chunk& c : chunks)
    for (const std::uint32_t t : c.tiles) ++first_[t + 1];
  busy_ = 0;
  for (int t = 0; t < tiles; ++t) {
    busy_ += first_[t + 1] != 0;
    first_[t + 1] += first_[t];
  }
  // Chunks in order, each appended to its tiles' lists: every list is in chunk order.
  entries_.resize(first_[tiles]);
  for (std::uint32_t i = 0; i < chunks.size(); ++i)
    for (std::uint32_t j = 0; j < chunks[i].tiles.size(); ++j)
      entries_[first_[chunks[i].tiles[j]]++] = {i, j};
  // After the scatter, first_[t] is the end of tile t's list: shift back to get the starts.
  for (int t = tiles; t > 0; --t) first_[t] = first_[t - 1];
  first_[0] = 0;
}

int TileChunks::busy_tiles_on(const TileGrid& grid, const TileGrid& coarse) const {
  marks_.assign(static_cast<std::size_t>(coarse.count()), 0);
  const int ratio = coarse.size / grid.size;
  int busy = 0;
  for (int t = 0; t < grid.count(); ++t) {
    if (first_[t] == first_[t + 1]) continue;
    const int c = (t / grid.tiles_x / ratio) * coarse.tiles_x + (t % grid.tiles_x) / ratio;
    busy += marks_[c] == 0;
    marks_[c] = 1;
  }
  return busy;
}

std::uint64_t TileChunks::triangles(std::span<const Chunk> chunks, int tile) const {
  std::uint64_t n = 0;
  for (const Entry& e : of(tile)) n += chunks[e.chunk].bin(e.bin).size();
  return n;
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

void append_runs(const Chunk& chunk, std::size_t j, std::vector<raster::BinRun>& runs) {
  const std::span<const std::uint32_t> bin = chunk.bin(j);
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
