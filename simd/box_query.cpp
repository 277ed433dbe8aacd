// The box-query projection of one instruction set (simd/isa.hpp). Nothing else belongs here: the
// algorithm lives once, in engine/src/occlusion/box_project.hpp.
#include "isa_dispatch.hpp"
#include "occlusion/box_project.hpp"
#include "simd/isa.hpp"

namespace mosaic::simd::MOSAIC_ISA {

void project_boxes(const Box* boxes, std::size_t n, const occlusion::BoxView& view,
                   occlusion::Projected* out) {
  occlusion::BoxProjectSimd<Arch>::run(boxes, n, view, out);
}

}  // namespace mosaic::simd::MOSAIC_ISA
