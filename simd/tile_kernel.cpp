// The tile kernel of one instruction set (simd/isa.hpp). Nothing else belongs here: the
// algorithm lives once, in engine/src/raster/tile_kernel.hpp.
#include "raster/tile_kernel.hpp"

#include "isa_dispatch.hpp"
#include "simd/isa.hpp"

namespace mosaic::simd::MOSAIC_ISA {

void tile_kernel(const raster::TileFrame& frame, const raster::TileRect& tile,
                 std::span<const raster::BinRun> bin, raster::TileScratch& scratch,
                 raster::TileStats& stats) {
  raster::TileKernelImpl<Arch>::run(frame, tile, bin, scratch, stats);
}

}  // namespace mosaic::simd::MOSAIC_ISA
