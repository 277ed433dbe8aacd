// resolve/clear_tile.hpp — the outputs of a tile that holds only the clear values.
//
// Takes: a frame's outputs and a tile no triangle reaches that loads nothing. Gives: what
// clearing the tile's samples and resolving them writes, without touching the samples: the
// clear colour in each pixel (the box filter of equal samples is their value) and per-sample
// colour, the clear depth in each per-sample depth and in the hierarchical z of each block.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include "mosaic/types.hpp"
#include "raster/tile.hpp"

namespace mosaic::resolve {

inline void write_clear_tile(const raster::TileFrame& f, const raster::TileRect& tile) {
  const auto S = static_cast<std::size_t>(f.samples);
  const auto width = static_cast<std::size_t>(tile.width);
  if (f.keep_color) {
    Rgba8 pixel = f.clear_color;
    if (f.image_bgra) std::swap(pixel.r, pixel.b);
    std::uint32_t row[raster::kMaxTileSize];
    std::fill_n(row, width, std::bit_cast<std::uint32_t>(pixel));
    for (int y = 0; y < tile.height; ++y)
      std::memcpy(f.image + static_cast<std::size_t>(tile.y0 + y) * f.image_stride +
                      static_cast<std::size_t>(tile.x0) * sizeof(Rgba8),
                  row, sizeof(Rgba8) * width);
  }
  for (int y = 0; y < tile.height; ++y) {
    const auto py = static_cast<std::size_t>(tile.y0 + y), px = static_cast<std::size_t>(tile.x0);
    if (f.sample_color)
      std::fill_n(f.sample_color + (py * static_cast<std::size_t>(f.width) + px) * S, width * S,
                  f.clear_color);
    if (f.sample_depth)
      std::fill_n(f.sample_depth + py * f.depth_stride + px * S, width * S, f.clear_depth);
  }
  if (f.hiz_min) {
    const int stride = f.hiz_stride();
    const int blocks_x = (tile.width + raster::kBlockSize - 1) / raster::kBlockSize;
    for (int by = 0; by * raster::kBlockSize < tile.height; ++by) {
      const std::size_t out = static_cast<std::size_t>(tile.y0 / raster::kBlockSize + by) * stride +
                              static_cast<std::size_t>(tile.x0 / raster::kBlockSize);
      std::fill_n(f.hiz_min + out, blocks_x, f.clear_depth);
      std::fill_n(f.hiz_max + out, blocks_x, f.clear_depth);
    }
  }
}

}  // namespace mosaic::resolve
