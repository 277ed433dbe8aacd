// shade/shade_simd.hpp — shading in SIMD lanes for the tile kernels: interpolated vertex colour,
// a draw's shader called once per batch of kShaderBatch pixels, and source-over blending, each in
// the same order of operations as its scalar twin (front/setup.hpp, shade/shading.hpp).
//
// Takes: a triangle's setup and planes, and the lanes' pixel positions in a block. Gives: packed
// RGBA8 lanes, or, for a shaded draw, the colour samples of a block where its samples passed the
// depth test, blended when the draw blends.
#pragma once

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
    const front::Plane* planes = nullptr;
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
  // setup's colour (shade::shade_one() lane-wise).
  static void batch_colors(const Lanes& ln, const front::TriangleSetup& t, const DrawShading& sh,
                           int g, F fx_blk, F fy_blk, F ox, F oy, std::uint32_t active,
                           I (&out)[kBatchVectors]) {
    if (!sh.function) {
      for (int j = 0; j < kBatchVectors; ++j) {
        const int v = g * kBatchVectors + j;
        out[j] = shade(t, ln.planes, (fx_blk + ln.colf[v]) + ox, (fy_blk + ln.rowf[v]) + oy);
      }
      return;
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
          const F val = plane(p[1 + k], t.x0, t.y0, x, y) / q;
          xsimd::select(lanes, val, F(0.0f)).store_aligned(in.varying[k] + j * L);
        }
      }
    }
    in.active = active;
    in.varying_count = sh.varyings;
    sh.function(sh.state, in, res);
    for (int j = 0; j < kBatchVectors; ++j) {
      const F c255(255.0f);
      const I r = unorm8(F::load_aligned(res.r + j * L) * c255);
      const I gg = unorm8(F::load_aligned(res.g + j * L) * c255);
      const I b = unorm8(F::load_aligned(res.b + j * L) * c255);
      const I a = unorm8(F::load_aligned(res.a + j * L) * c255);
      out[j] = r | (gg << 8) | (b << 16) | (a << 24);
    }
  }

  // Colours a block of a generic draw where its samples passed: per pixel at the pixel centre
  // (MSAA; only pixels some sample of which passed are active) or per sample (SSAA), blended
  // over each sample's colour when the draw blends.
  static void color_block(const Lanes& ln, const front::TriangleSetup& t, const DrawShading& sh,
                          bool blend, bool ssaa, int S, std::uint32_t* cblk, int px0, int py0,
                          const std::uint64_t* passed) {
    const F fx_blk(static_cast<float>(px0)), fy_blk(static_cast<float>(py0));
    for (int g = 0; g < kBatches; ++g) {
      std::uint32_t any = 0;
      for (int s = 0; s < S; ++s)
        any |= static_cast<std::uint32_t>(passed[s] >> (g * kShaderBatch)) & kBatchBits;
      if (!any) continue;
      I pixel[kBatchVectors];
      if (!ssaa) batch_colors(ln, t, sh, g, fx_blk, fy_blk, F(0.5f), F(0.5f), any, pixel);
      for (int s = 0; s < S; ++s) {
        const std::uint32_t bits =
            static_cast<std::uint32_t>(passed[s] >> (g * kShaderBatch)) & kBatchBits;
        if (!bits) continue;
        I sample[kBatchVectors];
        if (ssaa) batch_colors(ln, t, sh, g, fx_blk, fy_blk, ln.ox[s], ln.oy[s], bits, sample);
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
