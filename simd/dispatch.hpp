// simd/dispatch.hpp — which tile kernels and SIMD front ends this build has, which this CPU runs,
// and picking one.
#pragma once

#include <vector>

#include "front/front_end.hpp"
#include "mosaic/types.hpp"
#include "occlusion/box_project.hpp"
#include "raster/tile.hpp"

namespace mosaic::simd {

/// SIMD instruction sets this build compiled kernels for and this CPU can run, worst first.
std::vector<Isa> runnable_isas();

/// The tile kernel for `isa` (one of runnable_isas()), or nullptr.
raster::TileKernel tile_kernel(Isa isa);

/// The SIMD front end for `isa` (one of runnable_isas()), or nullptr. It gives exactly what
/// front::run_front_end() gives (front/setup_simd.hpp).
front::FrontEnd front_end(Isa isa);

/// The vertex stage for `isa` (one of runnable_isas()), or nullptr: it fills the cache that the
/// SIMD front end of the same ISA reads (front/vertex_stage.hpp).
front::VertexStage vertex_stage(Isa isa);

/// Projects boxes for the batched box queries, as occlusion::project_boxes() does.
using BoxProjector = void (*)(const Box* boxes, std::size_t n, const occlusion::BoxView& view,
                              occlusion::Projected* out);

/// The SIMD box projection for `isa` (one of runnable_isas()), or nullptr. It gives exactly what
/// occlusion::project_boxes() gives.
BoxProjector box_projector(Isa isa);

}  // namespace mosaic::simd
