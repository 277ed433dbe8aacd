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
  using typename B::M;
  static constexpr int kBlockSize = raster::kBlockSize;
  static constexpr int kBlockPixels = raster::kBlockPixels;
  static constexpr int kVectors = kBlockPixels / L;
  static constexpr int kMaxTileSize = raster::kMaxTileSize;
  /// The bytes of a packed pixel that stay where they are when r and b trade places.
  static constexpr std::int32_t kGreenAlpha = static_cast<std::int32_t>(0xff00ff00u);

  /// The box means of the L pixels of row vector v of a block (cblk): their kS samples each are
  /// the kS vectors from v * kS, a pixel's side by side (raster/tile.hpp).
  template <int kS>
  [[gnu::always_inline]] static I means(const std::int32_t* cblk, int v) {
    I c[kS];
    for (int i = 0; i < kS; ++i) c[i] = I::load_aligned(cblk + (v * kS + i) * L);
    return M::template means<kS>(c);
  }

  /// The box filter of every pixel of a tile into `image` (rows `image_stride` bytes apart; b,
  /// g, r, a order when `bgra`): `color` is the tile's samples, [block][pixel of block][sample]
  /// (raster/tile.hpp), `side` blocks a row; `resolved` is scratch of kMaxTileSize² pixels.
  static void box_tile(const std::uint32_t* color, int side, int S, const raster::TileRect& tile,
                       std::uint32_t* resolved, std::uint8_t* image, std::size_t image_stride,
                       bool bgra) {
    switch (S) {
      case 1:
        box_blocks<1>(color, side, tile, resolved, bgra);
        break;
      case 4:
        box_blocks<4>(color, side, tile, resolved, bgra);
        break;
      case 8:
        box_blocks<8>(color, side, tile, resolved, bgra);
        break;
      default:
        box_blocks<16>(color, side, tile, resolved, bgra);
        break;
    }
    for (int y = 0; y < tile.height; ++y) {
      // Rgba8 is four bytes in r, g, b, a order, the little-endian layout of the packed words.
      std::memcpy(image + static_cast<std::size_t>(tile.y0 + y) * image_stride +
                      static_cast<std::size_t>(tile.x0) * sizeof(Rgba8),
                  resolved + y * kMaxTileSize,
                  sizeof(Rgba8) * static_cast<std::size_t>(tile.width));
    }
  }

  /// The box means of the tile's blocks into `resolved`, for kS samples a pixel.
  template <int kS>
  static void box_blocks(const std::uint32_t* color, int side, const raster::TileRect& tile,
                         std::uint32_t* resolved, bool bgra) {
    for (int by = 0; by * kBlockSize < tile.height; ++by) {
      for (int bx = 0; bx * kBlockSize < tile.width; ++bx) {
        const int blk = by * side + bx;
        const std::int32_t* cblk = reinterpret_cast<const std::int32_t*>(
            color + static_cast<std::size_t>(blk) * kS * kBlockPixels);
        for (int v = 0; v < kVectors; ++v) {
          // resolve::box_mean() per byte: (sum + S/2) / S.
          I out;
          if constexpr (kS == 1)
            out = I::load_aligned(cblk + v * L);
          else
            out = means<kS>(cblk, v);
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
  }
};

}  // namespace mosaic::resolve
