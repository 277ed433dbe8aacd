// raster/depth_test.hpp — the per-sample depth comparison, shared by every rasterizer.
#pragma once

#include "mosaic/types.hpp"

namespace mosaic::raster {

/// True when a sample at depth `z` passes `test` against the stored depth.
inline bool depth_passes(DepthTest test, float z, float stored) {
  switch (test) {
    case DepthTest::kLess:
      return z < stored;
    case DepthTest::kLessEqual:
      return z <= stored;
    case DepthTest::kGreater:
      return z > stored;
    case DepthTest::kGreaterEqual:
      return z >= stored;
    case DepthTest::kAlways:
      return true;
  }
  return true;
}

}  // namespace mosaic::raster
