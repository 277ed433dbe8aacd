// The SIMD front end and vertex stage of one instruction set (simd/isa.hpp). Nothing else belongs
// here: the algorithm lives once, in engine/src/front/setup_simd.hpp.
#include "front/setup_simd.hpp"
#include "isa_dispatch.hpp"
#include "simd/isa.hpp"

namespace mosaic::simd::MOSAIC_ISA {

void front_end(const Draw& draw, std::uint32_t draw_index, std::uint32_t begin, std::uint32_t end,
               int width, int height, std::vector<front::TriangleSetup>& out,
               front::FrontStats& stats, front::PlaneArray* planes, int samples,
               const front::VertexCache* vertices) {
  front::FrontEndSimd<Arch>::run(draw, draw_index, begin, end, width, height, out, stats, planes,
                                 samples, vertices);
}

void vertex_stage(const Draw& draw, int width, int height, std::uint32_t begin, std::uint32_t end,
                  const front::VertexCache& cache) {
  front::FrontEndSimd<Arch>::vertex_stage(draw, width, height, begin, end, cache);
}

}  // namespace mosaic::simd::MOSAIC_ISA
