// isa_dispatch.cpp — which instruction sets' stages this build has (MOSAIC_HAVE_<ISA>, defined by
// engine/CMakeLists.txt from MOSAIC_SIMD_ISAS), which of them this CPU runs, and picking one.
#include "isa_dispatch.hpp"

#include <iterator>

namespace mosaic::dispatch {

namespace {

// CPUID (and, in libgcc, XCR0 for the AVX register state) through the compiler's builtins.
bool cpu_has(Isa isa) {
  __builtin_cpu_init();
  switch (isa) {
    case Isa::kSse41:
      return __builtin_cpu_supports("sse4.1");
    case Isa::kAvx2:
      return __builtin_cpu_supports("avx2");
    case Isa::kAvx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512cd") &&
             __builtin_cpu_supports("avx512vl");
    default:
      return false;
  }
}

// One instruction set's stages, as built.
struct IsaStages {
  Isa isa;
  raster::TileKernel kernel;
  front::FrontEnd front_end;
  front::VertexStage vertex_stage;
  occlusion::BoxProjector boxes;
};

constexpr IsaStages kBuilt[] = {
#if MOSAIC_HAVE_SSE41
    {Isa::kSse41, &simd::sse41::tile_kernel, &simd::sse41::front_end, &simd::sse41::vertex_stage,
     &simd::sse41::project_boxes},
#endif
#if MOSAIC_HAVE_AVX2
    {Isa::kAvx2, &simd::avx2::tile_kernel, &simd::avx2::front_end, &simd::avx2::vertex_stage,
     &simd::avx2::project_boxes},
#endif
#if MOSAIC_HAVE_AVX512
    {Isa::kAvx512, &simd::avx512::tile_kernel, &simd::avx512::front_end,
     &simd::avx512::vertex_stage, &simd::avx512::project_boxes},
#endif
    {Isa::kReference, nullptr, nullptr, nullptr, nullptr},  // the end: no SIMD stages
};

// The stages of `isa` if they were built and the CPU runs them; the end marker otherwise.
const IsaStages& stages(Isa isa) {
  for (const IsaStages& s : kBuilt)
    if (s.kernel != nullptr && s.isa == isa && cpu_has(isa)) return s;
  return kBuilt[std::size(kBuilt) - 1];
}

}  // namespace

std::vector<Isa> runnable_isas() {
  std::vector<Isa> out;
  for (const IsaStages& s : kBuilt)
    if (s.kernel != nullptr && cpu_has(s.isa)) out.push_back(s.isa);
  return out;
}

raster::TileKernel tile_kernel(Isa isa) { return stages(isa).kernel; }

front::FrontEnd front_end(Isa isa) { return stages(isa).front_end; }

front::VertexStage vertex_stage(Isa isa) { return stages(isa).vertex_stage; }

occlusion::BoxProjector box_projector(Isa isa) { return stages(isa).boxes; }

}  // namespace mosaic::dispatch
