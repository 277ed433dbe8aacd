// The tile kernel compiled for sse4_1 (flags in simd/CMakeLists.txt). Nothing else belongs here:
// the algorithm lives once, in engine/src/raster/tile_kernel.hpp.
#include "raster/tile_kernel.hpp"

namespace mosaic::simd {

void tile_kernel_sse41(const raster::TileFrame& f, const raster::TileRect& tile,
                       std::span<const raster::BinRun> bin, raster::TileScratch& sc,
                       raster::TileStats& st) {
  raster::TileKernelImpl<xsimd::sse4_1>::run(f, tile, bin, sc, st);
}

}  // namespace mosaic::simd
