// raster/hiz.hpp — hierarchical z: conservative depth bounds of 8×8-pixel blocks, shared by the
// tile kernels, the reference and the occlusion queries.
//
// Takes: a triangle's setup (for its depth over a block), or a frame's per-sample depth. Gives:
// BlockDepthRange (a triangle's depth range over a pixel rectangle, bounding every per-sample
// depth any rasterizer computes there), hiz_hidden() (whether a depth range can pass a test
// against a block's bounds), and the frame-level block bounds built from per-sample depth; for the
// tile kernels, the same tests with the depth test known at compile time, the upkeep of a block's
// bounds as triangles write it, and the SIMD reductions of a tile's and a block's bounds.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <xsimd/xsimd.hpp>

#include "front/setup.hpp"
#include "mosaic/types.hpp"
#include "simd/lane_types.hpp"

namespace mosaic::raster {

/// A triangle's depth over a pixel rectangle, bounding every per-sample depth the rasterizers
/// compute there. Samples of the rectangle [px0, px0 + w) × [py0, py0 + h) lie inside it, so
/// the plane's extremes over that rectangle, evaluated in double, bound the exact plane; the float
/// evaluation of a sample (two products and two sums, then the clamp) errs by at most 2u·mag to
/// first order, where u = 2^-24 and mag = |base| + |ddx·dx| + |ddy·dy|. kMarginScale = 2^-21 = 8u
/// covers that and the final rounding to float with room to spare. Clamping is monotone, so the
/// clamped range bounds the clamped samples.
struct BlockDepthRange {
  static constexpr double kMarginScale = 1.0 / (1 << 21);
  double base, ddx, ddy, x0, y0;
  explicit BlockDepthRange(const front::TriangleSetup& t)
      : base(t.z.base), ddx(t.z.ddx), ddy(t.z.ddy), x0(t.x0), y0(t.y0) {}
  /// The clamped depth range over the pixels [px0, px0 + w) × [py0, py0 + h). Always inlined:
  /// the tile kernels call it per block, and GCC stops inlining it once a kernel file holds many
  /// specialisations (measured: +1.7 % instructions on random-small when it was not).
  [[gnu::always_inline]] std::pair<float, float> over(int px0, int py0, int w, int h, float lo,
                                                      float hi) const {
    const double dx = px0 - x0, dy = py0 - y0, ew = w, eh = h;
    const double corner = base + ddx * dx + ddy * dy;
    const double mag = std::abs(base) + std::abs(ddx) * std::max(std::abs(dx), std::abs(dx + ew)) +
                       std::abs(ddy) * std::max(std::abs(dy), std::abs(dy + eh));
    const double margin = mag * kMarginScale;
    const double ex_lo = std::min(0.0, ddx * ew) + std::min(0.0, ddy * eh);
    const double ex_hi = std::max(0.0, ddx * ew) + std::max(0.0, ddy * eh);
    const float zl = static_cast<float>(corner + ex_lo - margin);
    const float zh = static_cast<float>(corner + ex_hi + margin);
    return {std::clamp(zl, lo, hi), std::clamp(zh, lo, hi)};
  }
};

/// BlockDepthRange::over() for square blocks of kSize pixels, with the same operations in the
/// same order, so the same values: the terms that depend on the triangle only are made once, and
/// those of a row of blocks once per row (the block walker calls it for every block it visits).
template <class A>
struct HizSimd;

template <int kSize>
class BlockDepthRows {
 public:
  BlockDepthRows() = default;  ///< nothing made: assign before use
  explicit BlockDepthRows(const front::TriangleSetup& t)
      : base_(t.z.base),
        ddx_(t.z.ddx),
        x0_(t.x0),
        abs_base_(std::abs(base_)),
        abs_ddx_(std::abs(ddx_)),
        ex_lo_(std::min(0.0, ddx_ * kSize) + std::min(0.0, double{t.z.ddy} * kSize)),
        ex_hi_(std::max(0.0, ddx_ * kSize) + std::max(0.0, double{t.z.ddy} * kSize)) {}
  /// The y terms of over() for the blocks whose top row is py0.
  struct Row {
    double corner, mag;
  };
  static Row row(const front::TriangleSetup& t, int py0) {
    const double ddy = t.z.ddy, dy = py0 - double{t.y0};
    return {ddy * dy, std::abs(ddy) * std::max(std::abs(dy), std::abs(dy + kSize))};
  }
  /// over(px0, py0, kSize, kSize, lo, hi) for the block at px0 of row `row`.
  [[gnu::always_inline]] std::pair<float, float> at(int px0, const Row& row, float lo,
                                                    float hi) const {
    const double dx = px0 - x0_;
    const double corner = base_ + ddx_ * dx + row.corner;
    const double mag =
        abs_base_ + abs_ddx_ * std::max(std::abs(dx), std::abs(dx + kSize)) + row.mag;
    const double margin = mag * BlockDepthRange::kMarginScale;
    const float zl = static_cast<float>(corner + ex_lo_ - margin);
    const float zh = static_cast<float>(corner + ex_hi_ + margin);
    return {std::clamp(zl, lo, hi), std::clamp(zh, lo, hi)};
  }

 private:
  template <class A>
  friend struct HizSimd;  // at() in double lanes
  double base_ = 0, ddx_ = 0, x0_ = 0, abs_base_ = 0, abs_ddx_ = 0, ex_lo_ = 0, ex_hi_ = 0;
};

/// True when no depth in [lo, hi] can pass `test` against any stored depth in [zmin, zmax]. A
/// NaN anywhere makes every comparison false, so the answer is "not hidden" (conservative).
inline bool hiz_hidden(DepthTest test, float lo, float hi, float zmin, float zmax) {
  switch (test) {
    case DepthTest::kLess:
      return lo >= zmax;
    case DepthTest::kLessEqual:
      return lo > zmax;
    case DepthTest::kGreater:
      return hi <= zmin;
    case DepthTest::kGreaterEqual:
      return hi < zmin;
    case DepthTest::kAlways:
      return false;
  }
  return false;
}

/// Exact bounds of every 8×8 block of a frame's per-sample depth (index ((y*W+x)*S+s)), written
/// to zmin / zmax, ceil(W/8) × ceil(H/8) blocks row-major. Blocks at the image's right and bottom
/// edges cover only the pixels inside the image. The tile kernels compute the same values.
inline void block_bounds_from_samples(std::span<const float> depth, int width, int height,
                                      int samples, int block, float* zmin, float* zmax) {
  const int bw = (width + block - 1) / block, bh = (height + block - 1) / block;
  for (int by = 0; by < bh; ++by) {
    for (int bx = 0; bx < bw; ++bx) {
      float lo = depth[(static_cast<std::size_t>(by * block) * width + bx * block) * samples];
      float hi = lo;
      for (int y = by * block; y < std::min(height, (by + 1) * block); ++y)
        for (int x = bx * block; x < std::min(width, (bx + 1) * block); ++x)
          for (int s = 0; s < samples; ++s) {
            const float z = depth[(static_cast<std::size_t>(y) * width + x) * samples + s];
            lo = std::min(lo, z);
            hi = std::max(hi, z);
          }
      zmin[by * bw + bx] = lo;
      zmax[by * bw + bx] = hi;
    }
  }
}

/// Hierarchical z for one block, the test known at compile time (the tile kernels): -1 rejects
/// the block (no sample can pass), 0 needs the per-sample test, 1 accepts every covered sample
/// without it.
template <DepthTest kTest>
[[gnu::always_inline]] inline int hiz_classify(float tlo, float thi, float bz_min, float bz_max) {
  if constexpr (kTest == DepthTest::kLess) return tlo >= bz_max ? -1 : (thi < bz_min ? 1 : 0);
  if constexpr (kTest == DepthTest::kLessEqual) return tlo > bz_max ? -1 : (thi <= bz_min ? 1 : 0);
  if constexpr (kTest == DepthTest::kGreater) return thi <= bz_min ? -1 : (tlo > bz_max ? 1 : 0);
  if constexpr (kTest == DepthTest::kGreaterEqual)
    return thi < bz_min ? -1 : (tlo >= bz_max ? 1 : 0);
  return 1;
}

/// Keeps a block's bounds [zmn, zmx] conservative after a triangle whose depth over the block is
/// in [blo, bhi] wrote some of its samples: each covered sample now holds either the new depth or
/// an old one the test kept because it was nearer. `all_covered`: the triangle covered every
/// sample of the block; `all_written`: it wrote every one.
template <DepthTest kTest>
[[gnu::always_inline]] inline void update_block_bounds(float& zmn, float& zmx, float blo, float bhi,
                                                       bool all_covered, bool all_written) {
  if constexpr (kTest == DepthTest::kLess || kTest == DepthTest::kLessEqual) {
    zmn = all_written ? blo : std::min(zmn, blo);
    if (all_covered) zmx = std::min(zmx, bhi);  // kept depths were nearer: below bhi
  } else if constexpr (kTest == DepthTest::kGreater || kTest == DepthTest::kGreaterEqual) {
    zmx = all_written ? bhi : std::max(zmx, bhi);
    if (all_covered) zmn = std::max(zmn, blo);
  } else {
    zmn = all_written ? blo : std::min(zmn, blo);
    zmx = all_written ? bhi : std::max(zmx, bhi);
  }
}

/// The tile kernels' bound reductions, in SIMD lanes of instruction set A.
template <class A>
struct HizSimd : simd::LaneTypes<A> {
  using B = simd::LaneTypes<A>;
  using B::kDLanes;
  using B::L;
  using typename B::D;
  using typename B::F;
  using typename B::M;

  /// Blocks of a row that hierarchical z rejects and accepts: bit j for the row's block j.
  struct RowClass {
    std::uint32_t rejected = 0, accepted = 0;
  };
  /// hiz_classify() of the n blocks (n <= 32) at px0, px0 + kSize, ... of row `row` (none
  /// rejected or accepted for DepthTest::kAlways), against
  /// their bounds zmin[j], zmax[j], with their ranges d.at() clamped to [lo, hi] stored to
  /// blo[j], bhi[j]: the same operations in double lanes, so the same values and answers. Reads
  /// and writes whole vectors: zmin, zmax, blo and bhi hold n rounded up to kDLanes floats.
  template <DepthTest kTest, int kSize>
  static RowClass classify_row(const BlockDepthRows<kSize>& d,
                               const typename BlockDepthRows<kSize>::Row& row, int px0, int n,
                               float lo, float hi, const float* zmin, const float* zmax, float* blo,
                               float* bhi) {
    alignas(64) double step[kDLanes];  // each lane's block offset
    for (int l = 0; l < kDLanes; ++l) step[l] = static_cast<double>(l * kSize);
    const D lane_dx = D::load_aligned(step) - D(d.x0_);
    const D dlo(static_cast<double>(lo)), dhi(static_cast<double>(hi));
    RowClass c;
    for (int j = 0; j < n; j += kDLanes) {
      // BlockDepthRows::at(), operation by operation: px0 - x0 is exact either way.
      const D dx = D(static_cast<double>(px0 + j * kSize)) + lane_dx;
      const D corner = (D(d.base_) + D(d.ddx_) * dx) + D(row.corner);
      const D mag =
          (D(d.abs_base_) + D(d.abs_ddx_) * xsimd::max(xsimd::abs(dx), xsimd::abs(dx + D(kSize)))) +
          D(row.mag);
      const D margin = mag * D(BlockDepthRange::kMarginScale);
      const D zl = M::to_float((corner + D(d.ex_lo_)) - margin);
      const D zh = M::to_float((corner + D(d.ex_hi_)) + margin);
      // std::clamp(z, lo, hi): lo below it, hi above it, else z (a NaN stays).
      const D bl = xsimd::select(zl < dlo, dlo, xsimd::select(dhi < zl, dhi, zl));
      const D bh = xsimd::select(zh < dlo, dlo, xsimd::select(dhi < zh, dhi, zh));
      M::narrow(blo + j, bl);
      M::narrow(bhi + j, bh);
      if constexpr (kTest != DepthTest::kAlways) {  // kAlways: every block kept, none tested
        const D bz_min = M::widen(zmin + j), bz_max = M::widen(zmax + j);
        xsimd::batch_bool<double, A> rej, acc;
        if constexpr (kTest == DepthTest::kLess) {
          rej = bl >= bz_max;
          acc = bh < bz_min;
        } else if constexpr (kTest == DepthTest::kLessEqual) {
          rej = bl > bz_max;
          acc = bh <= bz_min;
        } else if constexpr (kTest == DepthTest::kGreater) {
          rej = bh <= bz_min;
          acc = bl > bz_max;
        } else if constexpr (kTest == DepthTest::kGreaterEqual) {
          rej = bh < bz_min;
          acc = bl >= bz_max;
        }
        c.rejected |= M::bits(rej) << j;
        c.accepted |= M::bits(acc) << j;
      }
    }
    const std::uint32_t in_row = n >= 32 ? ~0u : (1u << n) - 1;
    c.rejected &= in_row;
    c.accepted &= in_row & ~c.rejected;
    return c;
  }

  /// The union of n blocks' bounds (a tile's bounds from its blocks').
  static std::pair<float, float> union_of(const float* zmin, const float* zmax, int n) {
    const int vec = n / L * L;
    F lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (int i = 0; i < vec; i += L) {
      lo = xsimd::min(lo, F::load_aligned(zmin + i));
      hi = xsimd::max(hi, F::load_aligned(zmax + i));
    }
    auto [l, h] = reduce(lo, hi);
    for (int i = vec; i < n; ++i) {
      l = std::min(l, zmin[i]);
      h = std::max(h, zmax[i]);
    }
    return {l, h};
  }

  /// The exact bounds of n stored depths (n a multiple of L, `d` aligned): one block's samples.
  static std::pair<float, float> bounds_of(const float* d, int n) {
    F vlo = F::load_aligned(d), vhi = vlo;
    for (int i = L; i < n; i += L) {
      const F z = F::load_aligned(d + i);
      vlo = xsimd::min(vlo, z);
      vhi = xsimd::max(vhi, z);
    }
    return reduce(vlo, vhi);
  }

  /// The smallest lane of lo and the largest of hi (xsimd 8.1 has no min/max reduction).
  static std::pair<float, float> reduce(F lo, F hi) {
    alignas(64) float ls[L], hs[L];
    lo.store_aligned(ls);
    hi.store_aligned(hs);
    float l = ls[0], h = hs[0];
    for (int i = 1; i < L; ++i) {
      l = std::min(l, ls[i]);
      h = std::max(h, hs[i]);
    }
    return {l, h};
  }
};

}  // namespace mosaic::raster
