#include "simd/dispatch.hpp"

#include <iterator>

namespace mosaic::simd {

// Defined in kernel_*.cpp and front_*.cpp, each compiled with its own -m flags; the build defines
// MOSAIC_HAVE_<ISA> for each it compiles (MOSAIC_SIMD_ISAS in simd/CMakeLists.txt).
#define MOSAIC_DECLARE_ISA(isa)                                                            \
  void tile_kernel_##isa(const raster::TileFrame&, const raster::TileRect&,                \
                         std::span<const raster::BinRun>, raster::TileScratch&,            \
                         raster::TileStats&);                                              \
  void front_end_##isa(const Draw&, std::uint32_t, std::uint32_t, std::uint32_t, int, int, \
                       std::vector<front::TriangleSetup>&, front::FrontStats&,             \
                       std::vector<front::Plane>*, int, const front::VertexCache*);        \
  void vertex_stage_##isa(const Draw&, int, int, std::uint32_t, std::uint32_t,             \
                          const front::VertexCache&);                                      \
  void project_boxes_##isa(const Box*, std::size_t, const occlusion::BoxView&,             \
                           occlusion::Projected*);
#if MOSAIC_HAVE_SSE41
MOSAIC_DECLARE_ISA(sse41)
#endif
#if MOSAIC_HAVE_AVX2
MOSAIC_DECLARE_ISA(avx2)
#endif
#if MOSAIC_HAVE_AVX512
MOSAIC_DECLARE_ISA(avx512)
#endif
#undef MOSAIC_DECLARE_ISA

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
  BoxProjector boxes;
};

constexpr IsaStages kBuilt[] = {
#if MOSAIC_HAVE_SSE41
    {Isa::kSse41, &tile_kernel_sse41, &front_end_sse41, &vertex_stage_sse41, &project_boxes_sse41},
#endif
#if MOSAIC_HAVE_AVX2
    {Isa::kAvx2, &tile_kernel_avx2, &front_end_avx2, &vertex_stage_avx2, &project_boxes_avx2},
#endif
#if MOSAIC_HAVE_AVX512
    {Isa::kAvx512, &tile_kernel_avx512, &front_end_avx512, &vertex_stage_avx512,
     &project_boxes_avx512},
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

BoxProjector box_projector(Isa isa) { return stages(isa).boxes; }

}  // namespace mosaic::simd
