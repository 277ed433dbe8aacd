#include "simd/dispatch.hpp"

namespace mosaic::simd {

// Defined in kernel_*.cpp, each compiled with its own -m flags.
void tile_kernel_sse41(const raster::TileFrame&, const raster::TileRect&,
                       std::span<const raster::BinRun>, raster::TileScratch&, raster::TileStats&);
void tile_kernel_avx2(const raster::TileFrame&, const raster::TileRect&,
                      std::span<const raster::BinRun>, raster::TileScratch&, raster::TileStats&);
void tile_kernel_avx512(const raster::TileFrame&, const raster::TileRect&,
                        std::span<const raster::BinRun>, raster::TileScratch&, raster::TileStats&);

// Defined in front_*.cpp, each compiled with its own -m flags.
void front_end_sse41(const Draw&, std::uint32_t, std::uint32_t, std::uint32_t, int, int,
                     std::vector<front::TriangleSetup>&, front::FrontStats&,
                     std::vector<front::Plane>*, int);
void front_end_avx2(const Draw&, std::uint32_t, std::uint32_t, std::uint32_t, int, int,
                    std::vector<front::TriangleSetup>&, front::FrontStats&,
                    std::vector<front::Plane>*, int);
void front_end_avx512(const Draw&, std::uint32_t, std::uint32_t, std::uint32_t, int, int,
                      std::vector<front::TriangleSetup>&, front::FrontStats&,
                      std::vector<front::Plane>*, int);

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

// The function of `isa` among one per instruction set, or nullptr where the CPU lacks it.
template <class F>
F pick(Isa isa, F sse41, F avx2, F avx512) {
  if (!cpu_has(isa)) return nullptr;
  switch (isa) {
    case Isa::kSse41:
      return sse41;
    case Isa::kAvx2:
      return avx2;
    case Isa::kAvx512:
      return avx512;
    default:
      return nullptr;
  }
}

}  // namespace

std::vector<Isa> runnable_isas() {
  std::vector<Isa> out;
  for (Isa isa : {Isa::kSse41, Isa::kAvx2, Isa::kAvx512})
    if (cpu_has(isa)) out.push_back(isa);
  return out;
}

raster::TileKernel tile_kernel(Isa isa) {
  return pick<raster::TileKernel>(isa, &tile_kernel_sse41, &tile_kernel_avx2, &tile_kernel_avx512);
}

front::FrontEnd front_end(Isa isa) {
  return pick<front::FrontEnd>(isa, &front_end_sse41, &front_end_avx2, &front_end_avx512);
}

}  // namespace mosaic::simd
