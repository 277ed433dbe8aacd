// The tile kernel compiled for avx512bw (flags in simd/CMakeLists.txt). Nothing else belongs here:
// the algorithm lives once, in engine/src/raster/tile_kernel.hpp.
#include "raster/tile_kernel.hpp"

namespace mosaic::simd {

void tile_kernel_avx512(const raster::TileFrame& f, const raster::TileRect& tile,
                        std::span<const raster::BinRun> bin, raster::TileScratch& sc,
                        raster::TileStats& st) {
  raster::TileKernelImpl<xsimd::avx512bw>::run(f, tile, bin, sc, st);
}

}  // namespace mosaic::simd
