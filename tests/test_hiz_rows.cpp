// Hierarchical z of a row of blocks in SIMD lanes (raster/hiz.hpp, HizSimd::classify_row(), as
// each instruction set compiles it: tests/isa/hiz_probe.cpp) against its scalar definition, block
// by block: BlockDepthRows::at() for the block's depth range and hiz_classify() for the answer.
// Ranges bit for bit; rejected and accepted blocks exactly, for every depth test, on planes of
// every slope, with bounds that tie the ranges exactly, NaN bounds, and rows of 1 to 16 blocks.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "raster/hiz.hpp"
#include "raster/tile.hpp"

#define MOSAIC_DECLARE_HIZ_PROBE(ns)                                                              \
  namespace mosaic::simd::ns {                                                                    \
  void probe_classify_row(const front::TriangleSetup& t, DepthTest test, int px0, int py0, int n, \
                          const float* zmin, const float* zmax, float* blo, float* bhi,           \
                          std::uint32_t* rejected, std::uint32_t* accepted);                      \
  }

#if MOSAIC_PROBE_SSE41
MOSAIC_DECLARE_HIZ_PROBE(sse41)
#endif
#if MOSAIC_PROBE_AVX2
MOSAIC_DECLARE_HIZ_PROBE(avx2)
#endif
#if MOSAIC_PROBE_AVX512
MOSAIC_DECLARE_HIZ_PROBE(avx512)
#endif

namespace {

using mosaic::DepthTest;
using mosaic::Isa;
using mosaic::front::TriangleSetup;
using mosaic::raster::kBlockSize;

using ClassifyRow = void (*)(const TriangleSetup&, DepthTest, int, int, int, const float*,
                             const float*, float*, float*, std::uint32_t*, std::uint32_t*);
struct Probe {
  Isa isa;
  ClassifyRow classify_row;
};

// The sets this build compiled that this CPU runs.
std::vector<Probe> probes() {
  std::vector<Probe> all;
#if MOSAIC_PROBE_SSE41
  all.push_back({Isa::kSse41, &mosaic::simd::sse41::probe_classify_row});
#endif
#if MOSAIC_PROBE_AVX2
  all.push_back({Isa::kAvx2, &mosaic::simd::avx2::probe_classify_row});
#endif
#if MOSAIC_PROBE_AVX512
  all.push_back({Isa::kAvx512, &mosaic::simd::avx512::probe_classify_row});
#endif
  std::vector<Probe> runnable;
  for (const Probe& p : all)
    for (const Isa a : mosaic::available_isas())
      if (a == p.isa) runnable.push_back(p);
  return runnable;
}

constexpr DepthTest kTests[] = {DepthTest::kLess, DepthTest::kLessEqual, DepthTest::kGreater,
                                DepthTest::kGreaterEqual, DepthTest::kAlways};
constexpr int kMaxRow = 16;         // blocks in a row of the largest tile
constexpr int kRead = kMaxRow + 8;  // what a row's SIMD reads and writes may reach

int classify(DepthTest test, float lo, float hi, float zmin, float zmax) {
  using mosaic::raster::hiz_classify;
  switch (test) {
    case DepthTest::kLess:
      return hiz_classify<DepthTest::kLess>(lo, hi, zmin, zmax);
    case DepthTest::kLessEqual:
      return hiz_classify<DepthTest::kLessEqual>(lo, hi, zmin, zmax);
    case DepthTest::kGreater:
      return hiz_classify<DepthTest::kGreater>(lo, hi, zmin, zmax);
    case DepthTest::kGreaterEqual:
      return hiz_classify<DepthTest::kGreaterEqual>(lo, hi, zmin, zmax);
    case DepthTest::kAlways:
      return hiz_classify<DepthTest::kAlways>(lo, hi, zmin, zmax);
  }
  return 0;
}

TEST(HizRows, SimdRowsMatchTheScalarRangeAndTestOfEachBlock) {
  const std::vector<Probe> ps = probes();
  if (ps.empty()) GTEST_SKIP() << "no SIMD instruction set built that this CPU runs";
  std::mt19937_64 rng(4242);
  const auto uni = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::uint64_t counts[3] = {};  // rejected, accepted, tested
  for (int k = 0; k < 3000; ++k) {
    TriangleSetup t;
    t.x0 = static_cast<float>(std::floor(uni(-300, 2200) * 256) / 256);
    t.y0 = static_cast<float>(std::floor(uni(-300, 1400) * 256) / 256);
    const double slope = k % 3 == 0 ? 1e-6 : k % 3 == 1 ? 1e-3 : 0.05;
    t.z.base = static_cast<float>(uni(-0.2, 1.2));
    t.z.ddx = k % 7 == 0 ? 0.0f : static_cast<float>(uni(-slope, slope));
    t.z.ddy = k % 5 == 0 ? 0.0f : static_cast<float>(uni(-slope, slope));
    const float a = static_cast<float>(uni(0, 1)), b = static_cast<float>(uni(0, 1));
    t.z_min = std::min(a, b);
    t.z_max = k % 11 == 0 ? t.z_min : std::max(a, b);
    const int n = 1 + static_cast<int>(rng() % kMaxRow);
    const int px0 = kBlockSize * static_cast<int>(rng() % 240);
    const int py0 = kBlockSize * static_cast<int>(rng() % 135);
    // The scalar ranges first: the bounds then tie them at times, exactly.
    float lo[kRead], hi[kRead];
    const mosaic::raster::BlockDepthRows<kBlockSize> rows(t);
    const auto row = mosaic::raster::BlockDepthRows<kBlockSize>::row(t, py0);
    for (int j = 0; j < n; ++j)
      std::tie(lo[j], hi[j]) = rows.at(px0 + j * kBlockSize, row, t.z_min, t.z_max);
    alignas(64) float zmin[kRead], zmax[kRead];
    for (int j = 0; j < kRead; ++j) {
      const float u = static_cast<float>(uni(-0.1, 1.1)), v = static_cast<float>(uni(-0.1, 1.1));
      zmin[j] = std::min(u, v);
      zmax[j] = std::max(u, v);
      if (j < n && rng() % 4 == 0) zmin[j] = rng() % 2 ? lo[j] : hi[j];
      if (j < n && rng() % 4 == 0) zmax[j] = rng() % 2 ? lo[j] : hi[j];
      if (rng() % 50 == 0) (rng() % 2 ? zmin[j] : zmax[j]) = nan;
    }
    for (const DepthTest test : kTests) {
      for (const Probe& p : ps) {
        float blo[kRead], bhi[kRead];
        std::uint32_t rejected = 0, accepted = 0;
        p.classify_row(t, test, px0, py0, n, zmin, zmax, blo, bhi, &rejected, &accepted);
        const std::string what = std::string(mosaic::to_string(p.isa)) + ", test " +
                                 std::to_string(static_cast<int>(test)) + ", case " +
                                 std::to_string(k);
        ASSERT_EQ(rejected >> n, 0u) << what;
        ASSERT_EQ(accepted >> n, 0u) << what;
        for (int j = 0; j < n; ++j) {
          ASSERT_EQ(std::bit_cast<std::uint32_t>(blo[j]), std::bit_cast<std::uint32_t>(lo[j]))
              << what << ", block " << j;
          ASSERT_EQ(std::bit_cast<std::uint32_t>(bhi[j]), std::bit_cast<std::uint32_t>(hi[j]))
              << what << ", block " << j;
          const int want =
              test == DepthTest::kAlways ? 0 : classify(test, lo[j], hi[j], zmin[j], zmax[j]);
          const int got = (rejected >> j & 1u) ? -1 : (accepted >> j & 1u) ? 1 : 0;
          ASSERT_EQ(got, want) << what << ", block " << j;
          ++counts[want + 1];
        }
      }
    }
  }
  // Every answer occurred many times.
  for (const std::uint64_t c : counts) EXPECT_GT(c, 1000u);
}

}  // namespace
