// raster/hiz.hpp's row classification compiled for one instruction set, as the tile kernels
// are (simd/CMakeLists.txt's mosaic_isa_target()), behind a plain function:
// tests/test_hiz_rows.cpp checks each set's against the scalar range and test of every block.
#include <cstdint>

#include "raster/hiz.hpp"
#include "raster/tile.hpp"
#include "simd/isa.hpp"

namespace mosaic::simd::MOSAIC_ISA {

// HizSimd::classify_row() for `test`, over the n blocks from px0 of the block row at py0 of
// triangle t, clamped to [t.z_min, t.z_max]: the ranges to blo, bhi and the answers' bits.
void probe_classify_row(const front::TriangleSetup& t, DepthTest test, int px0, int py0, int n,
                        const float* zmin, const float* zmax, float* blo, float* bhi,
                        std::uint32_t* rejected, std::uint32_t* accepted) {
  using Rows = raster::BlockDepthRows<raster::kBlockSize>;
  using H = raster::HizSimd<Arch>;
  const Rows d(t);
  const Rows::Row row = Rows::row(t, py0);
  const auto run = [&]<DepthTest kTest>() {
    return H::template classify_row<kTest>(d, row, px0, n, t.z_min, t.z_max, zmin, zmax, blo, bhi);
  };
  H::RowClass c;
  switch (test) {
    case DepthTest::kLess:
      c = run.template operator()<DepthTest::kLess>();
      break;
    case DepthTest::kLessEqual:
      c = run.template operator()<DepthTest::kLessEqual>();
      break;
    case DepthTest::kGreater:
      c = run.template operator()<DepthTest::kGreater>();
      break;
    case DepthTest::kGreaterEqual:
      c = run.template operator()<DepthTest::kGreaterEqual>();
      break;
    case DepthTest::kAlways:
      c = run.template operator()<DepthTest::kAlways>();
      break;
  }
  *rejected = c.rejected;
  *accepted = c.accepted;
}

}  // namespace mosaic::simd::MOSAIC_ISA
