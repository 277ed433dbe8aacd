// The SIMD front end compiled for avx512bw (flags in simd/CMakeLists.txt). Nothing else belongs
// here: the algorithm lives once, in engine/src/front/setup_simd.hpp.
#include "front/setup_simd.hpp"

namespace mosaic::simd {

void front_end_avx512(const Draw& draw, std::uint32_t draw_index, std::uint32_t begin,
                      std::uint32_t end, int width, int height,
                      std::vector<front::TriangleSetup>& out, front::FrontStats& stats,
                      std::vector<front::Plane>* planes, int samples,
                      const front::VertexCache* vertices) {
  front::FrontEndSimd<xsimd::avx512bw>::run(draw, draw_index, begin, end, width, height, out, stats,
                                            planes, samples, vertices);
}

void vertex_stage_avx512(const Draw& draw, int width, int height, std::uint32_t begin,
                         std::uint32_t end, const front::VertexCache& cache) {
  front::FrontEndSimd<xsimd::avx512bw>::vertex_stage(draw, width, height, begin, end, cache);
}

}  // namespace mosaic::simd
