#include "bin/binner.hpp"

#include <algorithm>

#include "bin/sample_cull.hpp"

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

BinCounts bin_chunk(Chunk& c, const TileGrid& grid, std::span<const raster::SampleOffset> pattern) {
  BinCounts counts;
  const int tiles = grid.count();
  c.offsets.assign(static_cast<std::size_t>(tiles) + 1, 0);
  c.pairs.clear();
  const int shift = grid.shift;  // (boxes are inside the image: never negative)
  const std::int64_t span = std::int64_t{grid.size} * front::kSubpixelOne;
  for (std::uint32_t i = 0; i < c.tris.size(); ++i) {
    const front::TriangleSetup& t = c.tris[i];
    if (covers_no_sample(t, pattern)) {
      ++counts.no_sample;
      continue;
    }
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
  counts.pairs = c.pairs.size();
  return counts;
}

}  // namespace mosaic::bin
