// raster/tile.hpp — what a tile worker takes and gives, shared by every SIMD kernel.
//
// Takes: one screen tile, the triangles binned to it in submission order, and the frame's
// state. Gives: the tile's resolved pixels written into the image (and its samples, when the
// target keeps them) and per-tile counters. A tile's sample colour and depth live in a
// per-worker TileScratch for the whole tile, in cache, until the tile is resolved.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <iterator>
#include <memory>
#include <span>
#include <vector>

#include "front/setup.hpp"
#include "mosaic/draw.hpp"
#include "mosaic/renderer.hpp"
#include "mosaic/types.hpp"
#include "shade/shading.hpp"

namespace mosaic::raster {

/// Block edge in pixels: 8×8 = 64 pixels, so one sample of a block is one 64-bit coverage word.
inline constexpr int kBlockSize = 8;
inline constexpr int kBlockPixels = kBlockSize * kBlockSize;
inline constexpr int kMaxSamples = 16;
/// Tiles are chosen per frame (RendererOptions::tile_size, or tile_size_for()); the scratch
/// memory of a worker is sized for the largest, mosaic::kMaxTileSize.
inline constexpr int kMaxTileSize = mosaic::kMaxTileSize;
inline constexpr int kMaxBlocksPerTileSide = kMaxTileSize / kBlockSize;
inline constexpr int kMaxBlocksPerTile = kMaxBlocksPerTileSide * kMaxBlocksPerTileSide;
static_assert(mosaic::kMinTileSize == kBlockSize, "tiles are whole blocks");

/// Bytes of sample colour and depth a tile holds per pixel and sample (RGBA8 + float depth).
inline constexpr int kBytesPerSample = 8;
/// The most sample memory the automatic tile size lets a tile have: a quarter of the 2 MiB L2 of
/// a core here, so that the tile's samples, the triangles streaming through and the resolve
/// output stay in L2 together. Measured (README, "Scaling past two cores"): 128 px tiles
/// (512 KiB at 4x) beat 64 px at 1x and 4x; at 16x (2 MiB, the whole L2) they lose, and at 8x
/// (1 MiB) neither wins on every scene.
inline constexpr int kAutoTileBytes = 512 * 1024;
/// The tile sizes the automatic choice picks from, largest first.
inline constexpr int kAutoTileSizes[] = {128, 64};

/// The tile edge for a frame with `samples` samples per pixel: the largest of kAutoTileSizes
/// whose samples fit kAutoTileBytes (the smallest if none does).
constexpr int tile_size_for(int samples) {
  for (const int size : kAutoTileSizes)
    if (size * size * samples * kBytesPerSample <= kAutoTileBytes) return size;
  return kAutoTileSizes[std::size(kAutoTileSizes) - 1];
}
static_assert(tile_size_for(1) == 128 && tile_size_for(4) == 128 && tile_size_for(8) == 64 &&
              tile_size_for(16) == 64);

/// The most double lanes of an instruction set mosaic compiles (AVX-512): what a SIMD read of a
/// row of blocks' bounds may pass its end by, plus one.
inline constexpr int kHizReadPad = 8;

static_assert(kBlockPixels == 64, "coverage words are 64-bit: one bit per pixel of a block");

// A block's S samples per pixel lie pixel-major in the tile's sample memory: sample s of pixel p
// (p = row * 8 + column) at word p * S + s of the block's S * 64, so that one vector holds every
// sample of a few pixels, which a small triangle's samples fill better than a row of one sample.
// Masks over a block's samples use the same order: bit g of words[g / 64] is word g's lane.
// (The helpers below are always inlined: the SIMD objects that call them must not export a copy
// compiled with their instruction set.)

/// The pixel mask `pixels` (bit p: pixel p of a block) as a mask of the block's samples: each
/// pixel's bit repeated S times, into words[0 .. S).
[[gnu::always_inline]] inline void spread_pixels(std::uint64_t pixels, int S,
                                                 std::uint64_t* words) {
  if (S == 1 || pixels == ~std::uint64_t{0}) {
    for (int w = 0; w < S; ++w) words[w] = S == 1 ? pixels : ~std::uint64_t{0};
    return;
  }
  const int per_word = kBlockPixels / S;  // pixels a word holds
  const std::uint64_t ones = (std::uint64_t{1} << S) - 1;
  for (int w = 0; w < S; ++w) {
    std::uint64_t m = 0;
    for (std::uint64_t bits = (pixels >> (w * per_word)) & ((std::uint64_t{1} << per_word) - 1);
         bits; bits &= bits - 1)
      m |= ones << (std::countr_zero(bits) * S);
    words[w] = m;
  }
}

namespace detail {
/// kPack[k][j]: for groups of S = 2^k bits, the runs of 2^(j+1) bits every 2^(j+1) * S bits that
/// step j of pack_groups() keeps; kPack[k][6]: the bits at multiples of S.
inline constexpr auto kPack = [] {
  std::array<std::array<std::uint64_t, 7>, 5> t{};
  for (int k = 0; k < 5; ++k) {
    const int S = 1 << k;
    for (int j = 0; j < 6; ++j) {
      const int run = 2 << j, period = run * S;
      for (int at = 0; at < 64; at += period)
        for (int b = 0; b < run && at + b < 64; ++b) t[k][j] |= std::uint64_t{1} << (at + b);
    }
    for (int at = 0; at < 64; at += S) t[k][6] |= std::uint64_t{1} << at;
  }
  return t;
}();
/// Bit g * S of x, for each g < 64 / S, packed into bit g (S a power of two, 2 to 16).
template <int S>
[[gnu::always_inline]] inline std::uint64_t pack_groups(std::uint64_t x) {
  constexpr int k = std::countr_zero(static_cast<unsigned>(S));
  x &= kPack[k][6];
  if constexpr (S == 16) {
    // Four bits 16 apart: one multiply puts bit 16 * g at bit 48 + g, with no carries between.
    constexpr std::uint64_t kGather16 = (std::uint64_t{1} << 48) | (std::uint64_t{1} << 33) |
                                        (std::uint64_t{1} << 18) | (std::uint64_t{1} << 3);
    return (x * kGather16) >> 48;
  } else {
    int j = 0;
    for (int width = 1; width * S < 64; ++j, width *= 2)
      x = (x | (x >> (width * (S - 1)))) & kPack[k][j];
    return x;
  }
}
/// pixels_of() and sample_pixels() for a fixed sample count: the loops unroll.
template <int S>
[[gnu::always_inline]] inline std::uint64_t pixels_of(const std::uint64_t* words) {
  constexpr int per_word = kBlockPixels / S;
  std::uint64_t pixels = 0;
  for (int w = 0; w < S; ++w) {
    std::uint64_t x = words[w];
    for (int k = 1; k < S; k *= 2) x |= x >> k;  // bit g * S: the OR of its group
    pixels |= pack_groups<S>(x) << (w * per_word);
  }
  return pixels;
}
template <int S>
[[gnu::always_inline]] inline std::uint64_t sample_pixels(const std::uint64_t* words, int s) {
  constexpr int per_word = kBlockPixels / S;
  std::uint64_t pixels = 0;
  for (int w = 0; w < S; ++w) pixels |= pack_groups<S>(words[w] >> s) << (w * per_word);
  return pixels;
}
}  // namespace detail

/// The pixels of a block with a sample set in `words` (S words, as above): bit p set where one
/// of pixel p's S bits is.
[[gnu::always_inline]] inline std::uint64_t pixels_of(const std::uint64_t* words, int S) {
  switch (S) {
    case 1:
      return words[0];
    case 2:
      return detail::pixels_of<2>(words);
    case 4:
      return detail::pixels_of<4>(words);
    case 8:
      return detail::pixels_of<8>(words);
    default:
      return detail::pixels_of<16>(words);
  }
}

/// The pixels of a block whose sample s is set in `words`.
[[gnu::always_inline]] inline std::uint64_t sample_pixels(const std::uint64_t* words, int S,
                                                          int s) {
  switch (S) {
    case 1:
      return words[0];
    case 2:
      return detail::sample_pixels<2>(words, s);
    case 4:
      return detail::sample_pixels<4>(words, s);
    case 8:
      return detail::sample_pixels<8>(words, s);
    default:
      return detail::sample_pixels<16>(words, s);
  }
}

/// The triangles of one tile: runs of indices into per-chunk setup arrays, in submission order.
struct BinRun {
  /// `draw` of a run whose triangles come from several draws (the painter's single chunk).
  static constexpr std::uint32_t kMixedDraws = UINT32_MAX;
  const front::TriangleSetup* tris = nullptr;
  std::span<const std::uint32_t> indices;
  const front::Plane* planes = nullptr;  ///< the chunk's planes (TriangleSetup::planes_base)
  std::uint32_t draw = kMixedDraws;      ///< the draw of every triangle in the run
};

/// Frame-wide, read-only inputs of every tile.
struct TileFrame {
  std::span<const DrawState> states;  ///< per draw; the painter's override already applied
  /// Per draw, when some draw of the frame has a shader or blends (shade::frame_shading());
  /// empty otherwise, and every triangle takes the specialised colour kernels.
  std::span<const shade::DrawShading> shading;
  int samples = 1;
  bool ssaa = false;
  /// Tile edge in pixels, a power of two from kBlockSize to kMaxTileSize: every tile but the last
  /// column and row is this size, and a tile's blocks are numbered row-major, tile_size / 8 a row.
  int tile_size = kMaxTileSize;
  Rgba8 clear_color;
  float clear_depth = 1.0f;
  int width = 0, height = 0;
  /// Resolved output: row y starts `image_stride` bytes after row y - 1, four bytes a pixel in
  /// r, g, b, a order, or b, g, r, a with image_bgra (a caller's surface).
  std::uint8_t* image = nullptr;
  std::size_t image_stride = 0;
  bool image_bgra = false;
  /// Optional per-sample depth output: sample s of pixel (x, y) at
  /// sample_depth[y * depth_stride + x * S + s].
  float* sample_depth = nullptr;
  std::size_t depth_stride = 0;
  Rgba8* sample_color = nullptr;  ///< optional per-sample colour output ((y*W+x)*S+s)
  /// The buffers the frame uses. Without colour (every draw depth-only, no sample colour kept)
  /// the tile neither clears nor resolves colour and `image` is left alone; without depth (no
  /// draw tests or writes it) the tile never clears it, and the depth outputs get clear_depth.
  bool keep_color = true, keep_depth = true;
  /// The tile starts from sample_color / sample_depth (the target's previous frame) instead of
  /// the clear values; each implies the matching keep_ and per-sample output.
  bool load_color = false, load_depth = false;
  /// Optional hierarchical-z output: exact min / max depth of every 8×8 block of the image,
  /// ceil(width / 8) per row (Renderer::hierarchical_z()).
  float* hiz_min = nullptr;
  float* hiz_max = nullptr;
  /// Blocks per row of the hierarchical-z output.
  int hiz_stride() const { return (width + kBlockSize - 1) / kBlockSize; }
  bool occluders_nearest_first = false;  ///< Frame::occluders_nearest_first
};

/// Counters one worker accumulates over its tiles.
struct TileStats {
  std::uint64_t blocks_hiz_rejected = 0, blocks_hiz_accepted = 0, samples_tested = 0,
                samples_written = 0;
  std::uint64_t resolve_ns = 0;  ///< time spent resolving, summed over this worker's tiles
  TileStats& operator+=(const TileStats& o) {
    blocks_hiz_rejected += o.blocks_hiz_rejected;
    blocks_hiz_accepted += o.blocks_hiz_accepted;
    samples_tested += o.samples_tested;
    samples_written += o.samples_written;
    resolve_ns += o.resolve_ns;
    return *this;
  }
};

/// A worker's tile memory, 64-byte aligned for any SIMD width. Layout of colour and depth:
/// [block][pixel of block][sample] (pixel-major, above), so a block's samples are contiguous.
struct TileScratch {
  struct Free {
    void operator()(void* p) const { std::free(p); }
  };
  static constexpr std::size_t kValues =
      std::size_t{kMaxBlocksPerTile} * kMaxSamples * kBlockPixels;
  std::unique_ptr<std::uint32_t[], Free> color{
      static_cast<std::uint32_t*>(std::aligned_alloc(64, kValues * sizeof(std::uint32_t)))};
  std::unique_ptr<float[], Free> depth{
      static_cast<float*>(std::aligned_alloc(64, kValues * sizeof(float)))};
  /// Hierarchical z: the nearest and farthest depth in each block. A row of blocks is read a
  /// vector of double lanes at a time, up to kHizReadPad - 1 past its last block.
  alignas(64) float zmin[kMaxBlocksPerTile + kHizReadPad];
  alignas(64) float zmax[kMaxBlocksPerTile + kHizReadPad];
  /// Samples written into each block since its bounds were last made exact from its depths.
  alignas(64) std::uint32_t hiz_written[kMaxBlocksPerTile];
  /// A depth-only draw's triangle that covers a whole block and passes hierarchical z there
  /// leaves its depth plane here instead of writing the block's samples; the samples are
  /// evaluated from it, with the same operations, when something reads them (the tile kernel's
  /// take_plane()). Under heavy overdraw a block's samples are then evaluated once, not once per
  /// triangle. `plane_pending[blk]` is 1 while block blk's samples are its plane's; every
  /// tile ends with none pending, so the next starts clear.
  struct DepthPlane {
    front::Plane z;  ///< TriangleSetup::z
    float x0, y0;    ///< TriangleSetup::x0, y0
    float lo, hi;    ///< TriangleSetup::z_min, z_max
  };
  alignas(64) DepthPlane plane[kMaxBlocksPerTile];
  alignas(64) std::uint8_t plane_pending[kMaxBlocksPerTile] = {};
  /// Pixels of each block inside a draw's clip rectangle and the image (see the tile kernel's
  /// clip_coverage()); kept here, not zeroed per tile, since most tiles never use it.
  alignas(64) std::uint64_t clipped[kMaxBlocksPerTile];
  /// The resolved tile, row-major, kMaxTileSize pixels a row whatever the tile's size.
  alignas(64) std::uint32_t resolved[kMaxTileSize * kMaxTileSize];
  /// A group of occluder runs' triangles in the order a tile draws them
  /// (Frame::occluders_nearest_first): the sort key, the run and the index in the run.
  struct Occluder {
    float key;
    std::uint32_t run, index;
  };
  std::vector<Occluder> occluders;
};

/// A tile: its origin and its size inside the image (smaller than the frame's tile size at the
/// image's right and bottom edges).
struct TileRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
};

/// A tile kernel: one per instruction set, chosen at run time (isa_dispatch.hpp).
using TileKernelFn = void(const TileFrame& frame, const TileRect& tile, std::span<const BinRun> bin,
                          TileScratch& scratch, TileStats& stats);
using TileKernel = TileKernelFn*;

}  // namespace mosaic::raster
