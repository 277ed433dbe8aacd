// The box-query projection compiled for sse41 (flags in simd/CMakeLists.txt). Nothing else belongs
// here: the algorithm lives once, in engine/src/occlusion/box_project.hpp.
#include "occlusion/box_project.hpp"

namespace mosaic::simd {

void project_boxes_sse41(const Box* boxes, std::size_t n, const occlusion::BoxView& view,
                         occlusion::Projected* out) {
  occlusion::BoxProjectSimd<xsimd::sse4_1>::run(boxes, n, view, out);
}

}  // namespace mosaic::simd
