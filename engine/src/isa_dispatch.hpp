// isa_dispatch.hpp — the SIMD stages of each instruction set, and the run-time choice among them.
//
// Each stage's template (tile kernel, SIMD front end and vertex stage, box projection) is compiled
// once per instruction set from simd/, with that set's flags, into its own namespace
// mosaic::simd::<isa>. They are declared here, on the engine side, so that engine code reaches
// them without including anything from simd/ but its vocabulary (lane types and masks).
#pragma once

#include <vector>

#include "front/front_end.hpp"
#include "front/vertex_stage.hpp"
#include "mosaic/types.hpp"
#include "occlusion/box_project.hpp"
#include "raster/tile.hpp"

// One instruction set's stages (simd/tile_kernel.cpp, simd/front_end.cpp, simd/box_query.cpp).
// Each line declares a function of the named type.
namespace mosaic::simd::sse41 {
raster::TileKernelFn tile_kernel;
front::FrontEndFn front_end;
front::VertexStageFn vertex_stage;
occlusion::BoxProjectorFn project_boxes;
}  // namespace mosaic::simd::sse41

namespace mosaic::simd::avx2 {
raster::TileKernelFn tile_kernel;
front::FrontEndFn front_end;
front::VertexStageFn vertex_stage;
occlusion::BoxProjectorFn project_boxes;
}  // namespace mosaic::simd::avx2

namespace mosaic::simd::avx512 {
raster::TileKernelFn tile_kernel;
front::FrontEndFn front_end;
front::VertexStageFn vertex_stage;
occlusion::BoxProjectorFn project_boxes;
}  // namespace mosaic::simd::avx512

namespace mosaic::dispatch {

/// SIMD instruction sets this build compiled stages for and this CPU can run, worst first.
std::vector<Isa> runnable_isas();

/// The tile kernel for `isa` (one of runnable_isas()), or nullptr.
raster::TileKernel tile_kernel(Isa isa);

/// The SIMD front end for `isa` (one of runnable_isas()), or nullptr. It gives exactly what
/// front::run_front_end() gives (front/setup_simd.hpp).
front::FrontEnd front_end(Isa isa);

/// The vertex stage for `isa` (one of runnable_isas()), or nullptr: it fills the cache that the
/// SIMD front end of the same ISA reads (front/vertex_stage.hpp).
front::VertexStage vertex_stage(Isa isa);

/// The SIMD box projection for `isa` (one of runnable_isas()), or nullptr. It gives exactly what
/// occlusion::project_boxes() gives.
occlusion::BoxProjector box_projector(Isa isa);

}  // namespace mosaic::dispatch
