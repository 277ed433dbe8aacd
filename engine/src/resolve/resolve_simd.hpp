// resolve/resolve_simd.hpp — the box resolve in SIMD lanes, run by each tile while its samples
// are in cache; the same integer arithmetic as resolve::box_mean() (resolve/resolve.hpp).
//
// Takes: a tile's sample colours in the tile kernels' layout. Gives: the tile's pixels in the
// image.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <xsimd/xsimd.hpp>

#include "mosaic/types.hpp"
#include "raster/tile.hpp"
#include "simd/lane_types.hpp"

namespace mosaic::resolve {

template <class A>
struct ResolveSimd : simd::LaneTypes<A> {
  using B = simd::LaneTypes<A>;
  using B::L;
  using typename B::I;
  static constexpr int kBlockSize = raster::kBlockSize;
  static constexpr int kBlockPixels = raster::kBlockPixels;
  static constexpr int kVectors = kBlockPixels / L;
  static constexpr int kMaxTileSize = raster::kMaxTileSize;
  /// The bytes of a packed pixel that stay where they are when r and b trade places.
  static constexpr std::int32_t kGreenAlpha = static_cast<std::int32_t>(0xff00ff00u);

  /// The box filter of every pixel of a tile into `image` (rows `image_stride` bytes apart; b,
  /// g, r, a order when `bgra`): `color` is the tile's samples, [block][sample][pixel of
  /// block], `side` blocks a row; `resolved` is scratch of kMaxTileSize² pixels.
  static void box_tile(const std::uint32_t* color, int side, int S, const raster::TileRect& tile,
                       std::uint32_t* resolved, std::uint8_t* image, std::size_t image_stride,
                       bool bgra) {
    const int shift = std::countr_zero(static_cast<unsigned>(S));
    // Two channels per 32-bit lane, one in each 16-bit half (r and b, then g and a): a half's sum
    // is at most 16 * 255 + 8 < 2^16, so it never carries into the other, and after the shift
    // the mask drops what the upper half shifted into the lower.
    const I round((S / 2) * 0x00010001), even(0x00ff00ff);
    for (int by = 0; by * kBlockSize < tile.height; ++by) {
      for (int bx = 0; bx * kBlockSize < tile.width; ++bx) {
        const int blk = by * side + bx;
        const std::int32_t* cblk = reinterpret_cast<const std::int32_t*>(
            color + static_cast<std::size_t>(blk) * S * kBlockPixels);
        for (int v = 0; v < kVectors; ++v) {
          I out;
          if (S == 1) {
            out = I::load_aligned(cblk + v * L);
          } else {
            I rb(0), ga(0);
            for (int s = 0; s < S; ++s) {
              const I c = I::load_aligned(cblk + s * kBlockPixels + v * L);
              rb += c & even;
              ga += (c >> 8) & even;
            }
            // resolve::box_mean(): (sum + S/2) / S, with S a power of two.
            rb = ((rb + round) >> shift) & even;
            ga = ((ga + round) >> shift) & even;
            out = rb | (ga << 8);
          }
          // b, g, r, a for a BGRA surface: r and b trade bytes 0 and 2.
          if (bgra)
            out = (out & I(kGreenAlpha)) | ((out >> 16) & I(0xff)) | ((out & I(0xff)) << 16);
          // The lanes' pixels are whole rows of the block (half a row with four lanes): copied
          // row piece by row piece, not pixel by pixel.
          constexpr int kPiece = L < kBlockSize ? L : kBlockSize;
          alignas(64) std::int32_t lanes[L];
          out.store_aligned(lanes);
          for (int l = 0; l < L; l += kPiece) {
            const int p = v * L + l;
            std::memcpy(resolved + (by * kBlockSize + p / kBlockSize) * kMaxTileSize +
                            bx * kBlockSize + p % kBlockSize,
                        lanes + l, sizeof(std::int32_t) * kPiece);
          }
        }
      }
    }
    for (int y = 0; y < tile.height; ++y) {
      // Rgba8 is four bytes in r, g, b, a order, the little-endian layout of the packed words.
      std::memcpy(image + static_cast<std::size_t>(tile.y0 + y) * image_stride +
                      static_cast<std::size_t>(tile.x0) * sizeof(Rgba8),
                  resolved + y * kMaxTileSize,
                  sizeof(Rgba8) * static_cast<std::size_t>(tile.width));
    }
  }
};

}  // namespace mosaic::resolve
