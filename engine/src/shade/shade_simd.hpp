// shade/shade_simd.hpp — shading in SIMD lanes for the tile kernels: interpolated vertex colour,
// a draw's shader called once per batch of kShaderBatch pixels, and source-over blending, each in
// the same order of operations as its scalar twin (front/setup.hpp, shade/shading.hpp).
//
// Takes: a triangle's setup and planes, and the lanes' pixel positions in a block. Gives: packed
// RGBA8 lanes, or, for a shaded draw, the colour samples of a block where its samples passed the
// depth test, blended when the draw blends. A shader's partly covered batches wait in a queue
// (ShadeQueue) that packs the pixels of many triangles and blocks into whole batches.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "front/setup.hpp"
#include "raster/tile.hpp"
#include "shade/shading.hpp"
#include "simd/lane_types.hpp"

namespace mosaic::shade {

template <class A>
struct ShadeSimd : simd::LaneTypes<A> {
  using B = simd::LaneTypes<A>;
  using B::kLaneBits;
  using B::L;
  using typename B::F;
  using typename B::I;
  using typename B::M;
  static constexpr int kVectors = raster::kBlockPixels / L;  ///< vectors per sample of a block
  static constexpr int kBlockPixels = raster::kBlockPixels;

  /// Where a block's lanes are: each vector's pixel columns and rows (floats), each sample's
  /// offset from the pixel corner, and the plane array of the triangles being drawn.
  struct Lanes {
    F colf[kVectors], rowf[kVectors];
    F ox[raster::kMaxSamples], oy[raster::kMaxSamples];
    float oxs[raster::kMaxSamples], oys[raster::kMaxSamples];  ///< ox, oy as scalars
    const front::Plane* planes = nullptr;
  };

  /// Pixels (MSAA) or samples (SSAA) of one shader draw that wait for a shader call. They are
  /// gathered from any triangles and blocks of a tile, so that a call shades up to kShaderBatch
  /// of them: a small triangle covers a few lanes of a block's batch, and a call costs the whole
  /// batch. Entries are written in the order they were queued, so draw order and blending hold.
  struct ShadeQueue {
    ShaderInput in;                        ///< the entries' positions and varyings, lane by lane
    std::uint32_t* color[kShaderBatch];    ///< each entry's first colour sample
    std::uint32_t samples[kShaderBatch];   ///< bit s: write color[l] + s * kBlockPixels
    int n = 0;                             ///< entries queued
    std::uint32_t front_facing = 0;        ///< ShaderInput::front_facing of the entries queued
    const DrawShading* shading = nullptr;  ///< the draw of every entry queued
    bool blend = false;                    ///< whether that draw blends
  };

  static std::int32_t bits_of(Rgba8 c) { return std::bit_cast<std::int32_t>(c); }

  // eval_plane() of front/setup.hpp, lane-wise, in the same order of operations.
  [[gnu::always_inline]] static F plane(const front::Plane& p, float x0, float y0, F x, F y) {
    const F v = F(p.base) + F(p.ddx) * (x - F(x0));
    return v + F(p.ddy) * (y - F(y0));
  }
  // clamp_like_simd() of front/setup.hpp.
  [[gnu::always_inline]] static F clamp(F v, float lo, float hi) {
    const F m = xsimd::select(v > F(lo), v, F(lo));
    return xsimd::select(m < F(hi), m, F(hi));
  }
  // to_unorm8() of front/setup.hpp: clamp, add one half, truncate.
  [[gnu::always_inline]] static I unorm8(F v) {
    return xsimd::to_int(clamp(v, 0.0f, 255.0f) + F(0.5f));
  }

  // front::shade(), lane-wise: packed RGBA8 at positions (x, y).
  // `planes` is the chunk's plane array.
  static I shade(const front::TriangleSetup& t, const front::Plane* planes, F x, F y) {
    if (front::is_flat(t)) return I(bits_of(t.color));
    return interpolate(t, planes + t.planes_base, x, y);
  }
  // The interpolated colour of a triangle whose q and colour·q planes are p[0 .. kColorPlanes).
  [[gnu::always_inline]] static I interpolate(const front::TriangleSetup& t, const front::Plane* p,
                                              F x, F y) {
    const F q = plane(p[0], t.x0, t.y0, x, y);
    const I r = unorm8(plane(p[1], t.x0, t.y0, x, y) / q);
    const I g = unorm8(plane(p[2], t.x0, t.y0, x, y) / q);
    const I b = unorm8(plane(p[3], t.x0, t.y0, x, y) / q);
    const I a = unorm8(plane(p[4], t.x0, t.y0, x, y) / q);
    return r | (g << 8) | (b << 16) | (a << 24);
  }

  /// Vectors per shader batch, and shader batches per block.
  static constexpr int kBatchVectors = kShaderBatch / L;
  static constexpr int kBatches = kBlockPixels / kShaderBatch;
  static_assert(kShaderBatch % L == 0 && kBlockPixels % kShaderBatch == 0);
  static constexpr std::uint32_t kBatchBits = (1u << kShaderBatch) - 1;

  // shade::blend_over(), lane-wise on packed RGBA8 (the same integer operations).
  static I blend_over(I src, I dst) {
    const I byte(0xff), c128(128), c255(255);
    const I a = (src >> 24) & byte, ia = c255 - a;
    const auto div255 = [&](I x) {
      const I u = x + c128;
      return (u + (u >> 8)) >> 8;
    };
    const I r = div255((src & byte) * a + (dst & byte) * ia);
    const I g = div255(((src >> 8) & byte) * a + ((dst >> 8) & byte) * ia);
    const I b = div255(((src >> 16) & byte) * a + ((dst >> 16) & byte) * ia);
    const I al = div255(c255 * a + ((dst >> 24) & byte) * ia);
    return r | (g << 8) | (b << 16) | (al << 24);
  }

  // The colours of batch `g` of a block (pixels 16g .. 16g + 15) at offsets (ox, oy) from the
  // pixel corners: the shader's batch function once, with lanes outside `active` zeroed, or the
  // setup's colour (shade::shade_one() lane-wise). Returns the active lanes the shader discards.
  static std::uint32_t batch_colors(const Lanes& ln, const front::TriangleSetup& t,
                                    const DrawShading& sh, int g, F fx_blk, F fy_blk, F ox, F oy,
                                    std::uint32_t active, I (&out)[kBatchVectors]) {
    if (!sh.function) {
      for (int j = 0; j < kBatchVectors; ++j) {
        const int v = g * kBatchVectors + j;
        out[j] = shade(t, ln.planes, (fx_blk + ln.colf[v]) + ox, (fy_blk + ln.rowf[v]) + oy);
      }
      return 0;
    }
    ShaderInput in;  // filled up to varying_count: the rest is never read
    ShaderOutput res;
    for (int j = 0; j < kBatchVectors; ++j) {
      const int v = g * kBatchVectors + j;
      const F x = (fx_blk + ln.colf[v]) + ox, y = (fy_blk + ln.rowf[v]) + oy;
      x.store_aligned(in.x + j * L);
      y.store_aligned(in.y + j * L);
      if (sh.varyings > 0) {
        const auto lanes = M::floats((active >> (j * L)) & kLaneBits);
        const front::Plane* p = ln.planes + t.planes_base;  // q, then the varyings
        const F q = plane(p[0], t.x0, t.y0, x, y);
        for (int k = 0; k < sh.varyings; ++k) {
          xsimd::select(lanes, plane(p[1 + k], t.x0, t.y0, x, y) / q, F(0.0f))
              .store_aligned(in.varying[k] + j * L);
        }
        for (int k = 0; sh.derivatives && k < sh.varyings; ++k) {
          const F val = F::load_aligned(in.varying[k] + j * L);
          slope(p[1 + k].ddx, p[0].ddx, val, q, lanes).store_aligned(in.ddx[k] + j * L);
          slope(p[1 + k].ddy, p[0].ddy, val, q, lanes).store_aligned(in.ddy[k] + j * L);
        }
      }
    }
    in.active = active;
    in.front_facing = front_lanes(t) & active;
    in.varying_count = sh.varyings;
    sh.function(sh.state, in, res);
    pack_output(res, out);
    return sh.discards ? res.discard & active : 0u;
  }

  // shade::varying_slope() lane-wise, 0 outside `lanes` (inactive lanes hold zeros).
  [[gnu::always_inline]] static F slope(float dp, float dq, F v, F q,
                                        xsimd::batch_bool<float, A> lanes) {
    return xsimd::select(lanes, (F(dp) - v * F(dq)) / q, F(0.0f));
  }

  // A shader's output lanes as packed RGBA8 (shade::output_to_unorm8() lane-wise).
  static void pack_output(const ShaderOutput& res, I (&out)[kBatchVectors]) {
    for (int j = 0; j < kBatchVectors; ++j) {
      const F c255(255.0f);
      const I r = unorm8(F::load_aligned(res.r + j * L) * c255);
      const I g = unorm8(F::load_aligned(res.g + j * L) * c255);
      const I b = unorm8(F::load_aligned(res.b + j * L) * c255);
      const I a = unorm8(F::load_aligned(res.a + j * L) * c255);
      out[j] = r | (g << 8) | (b << 16) | (a << 24);
    }
  }

  /// Queues one pixel or sample at shading position (x, y) of triangle t: its varyings as
  /// batch_colors() computes them lane-wise (shade::varying_at()), and the colour samples it
  /// writes. A full queue is shaded and written at once. `front` is all ones if t faces the
  /// viewer, else 0.
  static void enqueue(ShadeQueue& q, const front::TriangleSetup& t, const front::Plane* planes,
                      float x, float y, std::uint32_t* color, std::uint32_t samples,
                      std::uint32_t front) {
    const int l = q.n++;
    q.in.x[l] = x;
    q.in.y[l] = y;
    const int nv = q.shading->varyings;
    if (nv > 0) {
      const front::Plane* p = planes + t.planes_base;  // q, then the varyings
      const float qv = front::eval_plane(p[0], t.x0, t.y0, x, y);
      for (int k = 0; k < nv; ++k)
        q.in.varying[k][l] = front::eval_plane(p[1 + k], t.x0, t.y0, x, y) / qv;
      if (q.shading->derivatives) {
        for (int k = 0; k < nv; ++k) {
          const float v = q.in.varying[k][l];
          q.in.ddx[k][l] = varying_slope(p[1 + k].ddx, p[0].ddx, v, qv);
          q.in.ddy[k][l] = varying_slope(p[1 + k].ddy, p[0].ddy, v, qv);
        }
      }
    }
    q.front_facing |= front & (1u << l);
    q.color[l] = color;
    q.samples[l] = samples;
    if (q.n == kShaderBatch) flush(q);
  }

  /// Shades the queued entries in one call (the lanes past them inactive, all zeros) and writes
  /// their colour samples in queue order, blended when the draw blends.
  static void flush(ShadeQueue& q) {
    if (q.n == 0) return;
    const int n = q.n;
    q.n = 0;
    const DrawShading& sh = *q.shading;
    for (int l = n; l < kShaderBatch; ++l) {
      q.in.x[l] = q.in.y[l] = 0.0f;
      for (int k = 0; k < sh.varyings; ++k) q.in.varying[k][l] = 0.0f;
    }
    if (sh.derivatives) {
      for (int k = 0; k < sh.varyings; ++k) {
        std::fill(q.in.ddx[k] + n, q.in.ddx[k] + kShaderBatch, 0.0f);
        std::fill(q.in.ddy[k] + n, q.in.ddy[k] + kShaderBatch, 0.0f);
      }
    }
    q.in.active = static_cast<std::uint32_t>((std::uint64_t{1} << n) - 1);
    q.in.front_facing = q.front_facing;
    q.front_facing = 0;
    q.in.varying_count = sh.varyings;
    ShaderOutput res;
    sh.function(sh.state, q.in, res);
    I packed[kBatchVectors];
    pack_output(res, packed);
    alignas(64) std::int32_t c[kShaderBatch];
    for (int j = 0; j < kBatchVectors; ++j) packed[j].store_aligned(c + j * L);
    for (int l = 0; l < n; ++l) {
      for (std::uint32_t bits = q.samples[l]; bits; bits &= bits - 1) {
        std::uint32_t* word = q.color[l] + std::countr_zero(bits) * kBlockPixels;
        const auto src = std::bit_cast<Rgba8>(c[l]);
        *word = std::bit_cast<std::uint32_t>(
            q.blend ? shade::blend_over(src, std::bit_cast<Rgba8>(*word)) : src);
      }
    }
  }

  /// Bit k set where sample k of block pixel p passed. The common 4x count is unrolled: the
  /// loop over a run-time count cost more than the rest of queueing the pixel.
  static std::uint32_t samples_passed(const std::uint64_t* passed, int S, int p) {
    const auto bit = [&](int k) { return static_cast<std::uint32_t>((passed[k] >> p) & 1) << k; };
    if (S == 4) return bit(0) | bit(1) | bit(2) | bit(3);
    std::uint32_t samples = 0;
    for (int k = 0; k < S; ++k) samples |= bit(k);
    return samples;
  }

  /// The partly covered batch g of a block, into the queue: each pixel with a passed sample, at
  /// its centre with the samples that passed (MSAA), or, under SSAA, sample s of each pixel in
  /// `bits` at the sample's position.
  static void enqueue_batch(ShadeQueue& q, const Lanes& ln, const front::TriangleSetup& t, int g,
                            bool ssaa, int S, int s, std::uint32_t bits, std::uint32_t* cblk,
                            int px0, int py0, const std::uint64_t* passed) {
    const auto fx_blk = static_cast<float>(px0), fy_blk = static_cast<float>(py0);
    const std::uint32_t front = front_lanes(t);
    for (; bits; bits &= bits - 1) {
      const int p = g * kShaderBatch + std::countr_zero(bits);
      const auto col = static_cast<float>(p % raster::kBlockSize);
      const auto row = static_cast<float>(p / raster::kBlockSize);
      if (ssaa) {
        enqueue(q, t, ln.planes, (fx_blk + col) + ln.oxs[s], (fy_blk + row) + ln.oys[s],
                cblk + s * kBlockPixels + p, 1u, front);
        continue;
      }
      enqueue(q, t, ln.planes, (fx_blk + col) + 0.5f, (fy_blk + row) + 0.5f, cblk + p,
              samples_passed(passed, S, p), front);
    }
  }

  // Colours a block of a generic draw where its samples passed: per pixel at the pixel centre
  // (MSAA; only pixels some sample of which passed are active) or per sample (SSAA), blended
  // over each sample's colour when the draw blends. A shader's whole batches are shaded here,
  // after the queue is written (it holds earlier triangles' pixels); partial ones are queued.
  // A shader that discards is never queued: its block is shaded at once, and the lanes it drops
  // are cleared from `passed`, so that the caller writes depth only for those kept.
  static void color_block(const Lanes& ln, ShadeQueue& q, const front::TriangleSetup& t,
                          const DrawShading& sh, bool blend, bool ssaa, int S, std::uint32_t* cblk,
                          int px0, int py0, std::uint64_t* passed) {
    const bool queued = sh.function != nullptr && !sh.discards;
    if (queued && q.shading != &sh) {
      flush(q);
      q.shading = &sh;
      q.blend = blend;
    }
    const F fx_blk(static_cast<float>(px0)), fy_blk(static_cast<float>(py0));
    // Pixels with a passed sample, once for the block: only their batches are visited.
    std::uint64_t any_pixel = 0;
    for (int s = 0; s < S; ++s) any_pixel |= passed[s];
    while (any_pixel) {
      const int g = std::countr_zero(any_pixel) / kShaderBatch;
      const int shift = g * kShaderBatch;
      const auto any = static_cast<std::uint32_t>(any_pixel >> shift) & kBatchBits;
      any_pixel &= ~(std::uint64_t{kBatchBits} << shift);
      if (queued && !ssaa && any != kBatchBits) {
        enqueue_batch(q, ln, t, g, false, S, 0, any, cblk, px0, py0, passed);
        continue;
      }
      if (queued && !ssaa) flush(q);
      I pixel[kBatchVectors];
      std::uint32_t dropped = 0;  // pixels (MSAA) the shader discarded
      if (!ssaa) dropped = batch_colors(ln, t, sh, g, fx_blk, fy_blk, F(0.5f), F(0.5f), any, pixel);
      for (int s = 0; s < S; ++s) {
        std::uint32_t bits = static_cast<std::uint32_t>(passed[s] >> shift) & kBatchBits;
        if (!bits) continue;
        if (queued && ssaa) {
          if (bits != kBatchBits) {
            enqueue_batch(q, ln, t, g, true, S, s, bits, cblk, px0, py0, passed);
            continue;
          }
          flush(q);
        }
        I sample[kBatchVectors];
        if (ssaa)
          dropped = batch_colors(ln, t, sh, g, fx_blk, fy_blk, ln.ox[s], ln.oy[s], bits, sample);
        if (dropped) {
          passed[s] &= ~(std::uint64_t{dropped} << shift);
          bits &= ~dropped;
        }
        const I* color = ssaa ? sample : pixel;
        for (int j = 0; j < kBatchVectors; ++j) {
          const std::uint32_t lanes = (bits >> (j * L)) & kLaneBits;
          if (!lanes) continue;
          std::int32_t* cp = reinterpret_cast<std::int32_t*>(cblk + s * kBlockPixels +
                                                             (g * kBatchVectors + j) * L);
          const I dst = I::load_aligned(cp);
          const I c = blend ? blend_over(color[j], dst) : color[j];
          xsimd::select(M::ints(lanes), c, dst).store_aligned(cp);
        }
      }
    }
  }
};

}  // namespace mosaic::shade
