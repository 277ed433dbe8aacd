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
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "front/setup.hpp"
#include "raster/tile.hpp"
#include "shade/shading.hpp"
#include "simd/lane_types.hpp"

namespace mosaic::shade {

/// For each byte, the positions of its set bits in order, then zeros: the pixel columns a row of
/// a block's pixel mask holds.
inline constexpr auto kSetBitPositions = [] {
  std::array<std::array<std::int32_t, 8>, 256> table{};
  for (int b = 0; b < 256; ++b) {
    int k = 0;
    for (int i = 0; i < 8; ++i)
      if ((b >> i) & 1) table[b][k++] = i;
  }
  return table;
}();

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
  /// batch. Entries are appended a vector at a time, packed, in the order they were queued, so
  /// draw order and blending hold. The rows hold two batches, so that an append that fills the
  /// batch keeps its overflow for the next call, and a third for the lanes past the last entry
  /// that the varyings' last vector computes.
  /// A triangle's varyings are made once for all its entries, when the next triangle appends
  /// or a batch is shaded (complete()), so that its pixels in several blocks share vectors.
  struct ShadeQueue {
    static constexpr int kRow = 3 * kShaderBatch;
    alignas(64) float x[kRow]{}, y[kRow]{};  ///< each entry's shading position
    alignas(64) float varying[kMaxVaryings][kRow];
    alignas(64) float ddx[kMaxVaryings][kRow], ddy[kMaxVaryings][kRow];
    /// Each entry's first colour sample, as an index into color_base, and the samples it writes
    /// (bit s: index + s; a pixel's samples are side by side, raster/tile.hpp).
    alignas(64) std::int32_t color[kRow];
    alignas(64) std::int32_t samples[kRow]{};
    std::uint64_t front_facing = 0;        ///< bit l: entry l's triangle faces the viewer
    std::uint32_t* color_base = nullptr;   ///< the tile's colour samples
    int n = 0;                             ///< entries queued
    const DrawShading* shading = nullptr;  ///< the draw of every entry queued
    bool blend = false;                    ///< whether that draw blends
    int span = 1;  ///< samples an entry may write: the draw's count (MSAA), or 1 (SSAA)
    /// The triangle of entries pending..n-1, whose varyings and facing are not made yet, and
    /// the plane array its planes_base indexes.
    const front::TriangleSetup* triangle = nullptr;
    const front::Plane* planes = nullptr;
    int pending = 0;
  };

  static std::int32_t bits_of(Rgba8 c) { return std::bit_cast<std::int32_t>(c); }

  // eval_plane() of front/setup.hpp, lane-wise, in the same order of operations.
  [[gnu::always_inline]] static F plane(const front::Plane& p, float x0, float y0, F x, F y) {
    return plane_at(p, x - F(x0), y - F(y0));
  }
  // The same from the offsets (dx, dy) = (x - x0, y - y0), for planes sharing an origin.
  [[gnu::always_inline]] static F plane_at(const front::Plane& p, F dx, F dy) {
    return (F(p.base) + F(p.ddx) * dx) + F(p.ddy) * dy;
  }
  // clamp_like_simd() of front/setup.hpp: max(v, lo) is v > lo ? v : lo lane-wise (maxps, NaN
  // to lo), min(m, hi) is m < hi ? m : hi; one instruction each instead of a compare and a blend.
  [[gnu::always_inline]] static F clamp(F v, F lo, F hi) {
    return xsimd::min(xsimd::max(v, lo), hi);
  }
  [[gnu::always_inline]] static F clamp(F v, float lo, float hi) { return clamp(v, F(lo), F(hi)); }
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
      const auto lanes = M::floats((active >> (j * L)) & kLaneBits);
      varyings(
          t, ln.planes, sh, x, y,
          [&](float* row, F value) {
            xsimd::select(lanes, value, F(0.0f)).store_aligned(row + j * L);
          },
          in.varying[0], in.ddx[0], in.ddy[0], kShaderBatch);
    }
    in.active = active;
    in.front_facing = front_lanes(t) & active;
    in.varying_count = sh.varyings;
    sh.function(sh.state, in, res);
    pack_output(res, out);
    return sh.discards ? res.discard & active : 0u;
  }

  // shade::varying_slope() lane-wise.
  [[gnu::always_inline]] static F slope(float dp, float dq, F v, F q) {
    return (F(dp) - v * F(dq)) / q;
  }

  // The shader's varyings of triangle t at lanes (x, y), and their derivatives when it reads
  // them (shade::varying_at() lane-wise), each handed to put(row, value): row k of the varying,
  // ddx and ddy arrays starts `stride` floats after row k - 1. Every lane is computed, so each
  // lane's values depend on its own (x, y) only; put() zeroes or drops the lanes not shaded.
  template <class Put>
  [[gnu::always_inline]] static void varyings(const front::TriangleSetup& t,
                                              const front::Plane* planes, const DrawShading& sh,
                                              F x, F y, Put put, float* varying, float* ddx,
                                              float* ddy, int stride) {
    if (sh.varyings == 0) return;
    const front::Plane* p = planes + t.planes_base;  // q, then the varyings
    // The offsets from the triangle's origin, made once for all its planes.
    const F dx = x - F(t.x0), dy = y - F(t.y0);
    const F q = plane_at(p[0], dx, dy);
    if (!sh.derivatives) {
      for (int k = 0; k < sh.varyings; ++k)
        put(varying + k * stride, plane_at(p[1 + k], dx, dy) / q);
      return;
    }
    for (int k = 0; k < sh.varyings; ++k) {
      const F v = plane_at(p[1 + k], dx, dy) / q;
      put(varying + k * stride, v);
      put(ddx + k * stride, slope(p[1 + k].ddx, p[0].ddx, v, q));
      put(ddy + k * stride, slope(p[1 + k].ddy, p[0].ddy, v, q));
    }
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

  /// varyings() for queue entry `at` alone, without derivatives: the reference's own scalar
  /// evaluation (varying_at()), without a vector's broadcasts and divisions for one pixel (a
  /// triangle of a pixel or two, which the few-pixel path queues).
  static void varyings_of_one(const front::TriangleSetup& t, const front::Plane* planes,
                              const DrawShading& sh, ShadeQueue& q, int at) {
    if (sh.varyings == 0) return;
    const float x = q.x[at], y = q.y[at];
    const float w = front::eval_plane(planes[t.planes_base], t.x0, t.y0, x, y);
    for (int k = 0; k < sh.varyings; ++k) q.varying[k][at] = varying_at(t, planes, k, w, x, y);
  }

  /// Makes the varyings and facing of the pending entries (q.pending..q.n-1), those of one
  /// triangle, a vector of packed entries at a time: the triangle's few pixels in each block
  /// share vectors. Each lane's values depend on its own position only, so they equal those
  /// computed at the entry's own lane. (The lanes past q.n hold earlier entries' positions or
  /// zeros: finite.)
  static void complete(ShadeQueue& q) {
    const int from = q.pending;
    if (from >= q.n) return;
    const front::TriangleSetup& t = *q.triangle;
    if (q.n - from == 1 && !q.shading->derivatives) {
      varyings_of_one(t, q.planes, *q.shading, q, from);
    } else {
      for (int at = from; at < q.n; at += L) {
        varyings(
            t, q.planes, *q.shading, F::load_unaligned(q.x + at), F::load_unaligned(q.y + at),
            [&](float* row, F value) { value.store_unaligned(row + at); }, q.varying[0], q.ddx[0],
            q.ddy[0], ShadeQueue::kRow);
      }
    }
    q.front_facing |= (((std::uint64_t{1} << (q.n - from)) - 1) << from) & front_lanes(t);
    q.pending = q.n;
  }
  /// Makes triangle t the one whose entries are appended next.
  static void begin(ShadeQueue& q, const front::TriangleSetup& t, const front::Plane* planes) {
    if (q.triangle == &t && q.planes == planes) return;
    complete(q);
    q.triangle = &t;
    q.planes = planes;
  }

  /// Shades the first kShaderBatch queued entries (or all, if fewer) in one call, the lanes past
  /// them inactive and zero, and writes their colour samples in queue order, blended when the
  /// draw blends. Entries past the batch move to the front.
  static void flush(ShadeQueue& q) {
    if (q.n == 0) return;
    complete(q);
    const int n = std::min(q.n, kShaderBatch);
    const DrawShading& sh = *q.shading;
    ShaderInput in;
    const auto take = [&](const float* from, float* to) {
      for (int j = 0; j < kBatchVectors; ++j) {
        const auto kept = M::floats(lanes_below(n - j * L));
        xsimd::select(kept, F::load_aligned(from + j * L), F(0.0f)).store_aligned(to + j * L);
      }
    };
    take(q.x, in.x);
    take(q.y, in.y);
    for (int k = 0; k < sh.varyings; ++k) take(q.varying[k], in.varying[k]);
    for (int k = 0; sh.derivatives && k < sh.varyings; ++k) {
      take(q.ddx[k], in.ddx[k]);
      take(q.ddy[k], in.ddy[k]);
    }
    in.active = static_cast<std::uint32_t>((std::uint64_t{1} << n) - 1);
    in.front_facing = static_cast<std::uint32_t>(q.front_facing) & in.active;
    in.varying_count = sh.varyings;
    ShaderOutput res;
    sh.function(sh.state, in, res);
    I packed[kBatchVectors];
    pack_output(res, packed);
    if (q.blend)
      write_blended(q, n, packed);
    else
      write_masked(q, n, packed);
    // The overflow of the last append (fewer than kShaderBatch entries) to the front.
    const int rest = q.n - n;
    q.n = rest;
    q.pending = rest;
    q.front_facing >>= n;
    if (rest == 0) return;
    const auto move = [&](float* row) {
      for (int j = 0; j < kBatchVectors; ++j)
        F::load_aligned(row + kShaderBatch + j * L).store_aligned(row + j * L);
    };
    move(q.x);
    move(q.y);
    for (int k = 0; k < sh.varyings; ++k) move(q.varying[k]);
    for (int k = 0; sh.derivatives && k < sh.varyings; ++k) {
      move(q.ddx[k]);
      move(q.ddy[k]);
    }
    for (int j = 0; j < kBatchVectors; ++j) {
      I::load_aligned(q.color + kShaderBatch + j * L).store_aligned(q.color + j * L);
      I::load_aligned(q.samples + kShaderBatch + j * L).store_aligned(q.samples + j * L);
    }
  }

  // The first n queued entries' colours blended over each sample the entry passed, entry by
  // entry in queue order (an entry may blend over an earlier one's colour).
  static void write_blended(const ShadeQueue& q, int n, const I (&packed)[kBatchVectors]) {
    alignas(64) std::int32_t c[kShaderBatch];
    for (int j = 0; j < kBatchVectors; ++j) packed[j].store_aligned(c + j * L);
    for (int l = 0; l < n; ++l) {
      std::uint32_t* first = q.color_base + q.color[l];
      const auto src = std::bit_cast<Rgba8>(c[l]);
      for (std::uint32_t bits = static_cast<std::uint32_t>(q.samples[l]); bits; bits &= bits - 1) {
        std::uint32_t* word = first + std::countr_zero(bits);
        *word = std::bit_cast<std::uint32_t>(shade::blend_over(src, std::bit_cast<Rgba8>(*word)));
      }
    }
  }
  // The same without blending: each entry's colour is stored to each sample it passed, four
  // adjacent samples (a pixel's at 4x) by one masked 128-bit store, without a branch on which
  // passed. The stores keep queue order, so a later entry wins a sample two entries write.
  static void write_masked(const ShadeQueue& q, int n, const I (&packed)[kBatchVectors]) {
    alignas(64) std::int32_t c[kShaderBatch];
    for (int j = 0; j < kBatchVectors; ++j) packed[j].store_aligned(c + j * L);
    std::uint32_t* base = q.color_base;
    if (q.span == 1) {  // one sample: an entry is queued because its sample passed
      for (int l = 0; l < n; ++l) base[q.color[l]] = static_cast<std::uint32_t>(c[l]);
      return;
    }
    if (q.span == 4) {  // the common count, unrolled
      for (int l = 0; l < n; ++l)
        simd::store_samples4(base + q.color[l], static_cast<std::uint32_t>(c[l]),
                             static_cast<std::uint32_t>(q.samples[l]));
      return;
    }
    for (int l = 0; l < n; ++l)  // 8x, 16x (MSAA counts are 1, 4, 8 and 16)
      for (int k = 0; k < q.span; k += 4)
        simd::store_samples4(base + q.color[l] + k, static_cast<std::uint32_t>(c[l]),
                             static_cast<std::uint32_t>(q.samples[l]) >> k);
  }
  /// The lowest `count` lanes' bits (none if count <= 0, all if count >= L).
  static std::uint32_t lanes_below(int count) {
    if (count <= 0) return 0;
    return count >= L ? kLaneBits : (1u << count) - 1;
  }

  /// A block's pixels in `pixels` (bit p: pixel p), into the queue: one entry each, at the
  /// pixel centre with the samples that passed there. The pixels' indices are listed first, a
  /// row of the block at a time from a table, and then appended L at a time: a small
  /// triangle's row of a block holds a pixel or two, and a vector per row cost more.
  /// `color` is the index of the block's first colour sample in the queue's color_base.
  static void enqueue_pixels(ShadeQueue& q, const Lanes& ln, const front::TriangleSetup& t, int S,
                             std::uint64_t pixels, std::int32_t color, F fx_blk, F fy_blk,
                             const std::uint64_t* passed) {
    static_assert(raster::kBlockSize == 8, "a row of a block is one byte of its pixel mask");
    begin(q, t, ln.planes);
    // Room for the last row's eight positions and for the last vector's lanes past the pixels.
    alignas(64) std::int32_t at[kBlockPixels + std::max(8, L)];
    const int m = list_bits(pixels, at);
    for (int j = 0; j < m; j += L) {
      const I p = I::load_aligned(at + j);
      const I col = p & I(raster::kBlockSize - 1), row = p >> 3;  // 8 pixels a row
      const F x = (fx_blk + xsimd::to_float(col)) + F(0.5f);
      const F y = (fy_blk + xsimd::to_float(row)) + F(0.5f);
      const int n = q.n;
      x.store_unaligned(q.x + n);
      y.store_unaligned(q.y + n);
      (I(color) + p * I(S)).store_unaligned(q.color + n);
      sample_bits(passed, S, p).store_unaligned(q.samples + n);
      q.n = n + std::min(L, m - j);
      if (q.n >= kShaderBatch) flush(q);
    }
  }
  /// The positions of the bits of `bits` (not empty) in order into `at`, a byte of it at a time
  /// from a table, over the bytes from the first bit's to the last's; returns how many. `at`
  /// needs room for 64 + max(8, L): the lanes past the count hold other positions or zeros.
  static int list_bits(std::uint64_t bits, std::int32_t* at) {
    int m = 0;
    const int last = (63 - std::countl_zero(bits)) / 8;
    for (int r = std::countr_zero(bits) / 8; r <= last; ++r) {
      const int shift = r * 8;
      const auto byte = static_cast<unsigned>(bits >> shift) & 0xffu;
      const std::array<std::int32_t, 8>& columns = kSetBitPositions[byte];
      for (int i = 0; i < 8; ++i) at[m + i] = columns[i] + shift;
      m += std::popcount(byte);
    }
    if constexpr (L > 8) std::fill_n(at + m + 8, L - 8, 0);  // lanes the bytes did not write
    return m;
  }
  /// The samples of a block set in `passed` (SSAA: each is shaded at its own position), into the
  /// queue in the order of the block's sample memory, L at a time. `color` is the index of the
  /// block's first colour sample in the queue's color_base.
  static void enqueue_lanes(ShadeQueue& q, const Lanes& ln, const front::TriangleSetup& t, int S,
                            const std::uint64_t* passed, std::int32_t color, F fx_blk, F fy_blk) {
    begin(q, t, ln.planes);
    const int log2s = std::countr_zero(static_cast<unsigned>(S));
    alignas(64) std::int32_t at[kBlockPixels + std::max(8, L)];
    for (int w = 0; w < S; ++w) {
      if (!passed[w]) continue;
      const int m = list_bits(passed[w], at);
      for (int j = 0; j < m; j += L) {
        const I g = I::load_aligned(at + j) + I(w * 64);  // the sample's word in the block
        const I p = g >> log2s, smp = g & I(S - 1);
        const F x =
            (fx_blk + xsimd::to_float(p & I(raster::kBlockSize - 1))) + F::gather(ln.oxs, smp);
        const F y = (fy_blk + xsimd::to_float(p >> 3)) + F::gather(ln.oys, smp);
        const int n = q.n;
        x.store_unaligned(q.x + n);
        y.store_unaligned(q.y + n);
        (I(color) + g).store_unaligned(q.color + n);
        I(1).store_unaligned(q.samples + n);
        q.n = n + std::min(L, m - j);
        if (q.n >= kShaderBatch) flush(q);
      }
    }
  }
  /// Per lane, bit k set where sample k of block pixel p (0..63) passed: bits p * S .. p * S +
  /// S - 1 of the passed words, which lie in one 32-bit word (S divides 32). (Lanes past the
  /// listed pixels hold any value: masked to a pixel, so that the word stays in `passed`.)
  /// `passed` holds at least a vector of 32-bit words (max(S, L / 2) 64-bit words).
  static I sample_bits(const std::uint64_t* passed, int S, I p) {
    if (S == 1) return I(1);  // a queued pixel's one sample passed
    const I g = (p & I(raster::kBlockPixels - 1)) * I(S);
    const auto* words = reinterpret_cast<const std::int32_t*>(passed);
    // The block's 2S words fit one vector up to 4x on AVX2 (8x on AVX-512): a lane permute
    // picks each lane's word; more take a gather.
    const I word =
        2 * S <= L ? M::permute(I::load_unaligned(words), g >> 5) : M::gather(words, g >> 5);
    return (word >> (g & I(31))) & I((1 << S) - 1);
  }
  // Writes (or blends) colour[j] lane l to sample s of pixel g * 16 + j * L + l of a block, for
  // the pixels set in `bits`.
  static void write_batch(const I (&color)[kBatchVectors], std::uint32_t bits, int g, int s, int S,
                          bool blend, std::uint32_t* cblk) {
    alignas(64) std::int32_t c[kShaderBatch];
    for (int j = 0; j < kBatchVectors; ++j) color[j].store_aligned(c + j * L);
    for (; bits; bits &= bits - 1) {
      const int l = std::countr_zero(bits);
      put(cblk[static_cast<std::size_t>(g * kShaderBatch + l) * S + s],
          static_cast<std::uint32_t>(c[l]), blend);
    }
  }
  // Writes (or blends) colour[j] lane l to each passed sample of pixel g * kShaderBatch + j * L
  // + l of a block, for the pixels set in `bits`: a pixel's S samples are adjacent words, so a
  // pixel whose samples all passed takes one fill.
  static void write_pixels(const I (&color)[kBatchVectors], std::uint32_t bits, int g, int S,
                           bool blend, const std::uint64_t* passed, std::uint32_t* cblk) {
    alignas(64) std::int32_t c[kShaderBatch];
    for (int j = 0; j < kBatchVectors; ++j) color[j].store_aligned(c + j * L);
    const std::uint32_t all = (std::uint32_t{1} << S) - 1;  // S <= 16
    for (; bits; bits &= bits - 1) {
      const int l = std::countr_zero(bits);
      const int first = (g * kShaderBatch + l) * S;  // the pixel's first sample bit and word
      auto mine = static_cast<std::uint32_t>(passed[first / 64] >> (first % 64)) & all;
      std::uint32_t* word = cblk + first;
      const auto src = static_cast<std::uint32_t>(c[l]);
      if (!blend && mine == all) {
        fill_samples(word, S, src);
        continue;
      }
      for (; mine; mine &= mine - 1) put(word[std::countr_zero(mine)], src, blend);
    }
  }
  // `src` into a sample's colour word, or blended over it.
  static void put(std::uint32_t& word, std::uint32_t src, bool blend) {
    word = blend ? std::bit_cast<std::uint32_t>(
                       shade::blend_over(std::bit_cast<Rgba8>(src), std::bit_cast<Rgba8>(word)))
                 : src;
  }
  // `value` into a pixel's S adjacent sample words, by a fill of constant length per count.
  static void fill_samples(std::uint32_t* word, int S, std::uint32_t value) {
    switch (S) {
      case 1:
        word[0] = value;
        break;
      case 2:
        std::fill_n(word, 2, value);
        break;
      case 4:
        std::fill_n(word, 4, value);
        break;
      case 8:
        std::fill_n(word, 8, value);
        break;
      default:
        std::fill_n(word, 16, value);
        break;
    }
  }
  // Clears every sample of the pixels set in `pixels` from a block's passed words.
  static void clear_pixels(std::uint64_t* passed, int S, std::uint64_t pixels) {
    std::uint64_t words[raster::kMaxSamples];
    raster::spread_pixels(pixels, S, words);
    for (int w = 0; w < S; ++w) passed[w] &= ~words[w];
  }
  // Clears sample s of the pixels set in `pixels` from a block's passed words.
  static void clear_samples(std::uint64_t* passed, int S, std::uint64_t pixels, int s) {
    for (; pixels; pixels &= pixels - 1) {
      const int bit = std::countr_zero(pixels) * S + s;
      passed[bit / 64] &= ~(std::uint64_t{1} << (bit % 64));
    }
  }

  /// Whether a draw's pixels go through the queue: a shader that never discards.
  static bool queues(const DrawShading& sh) { return sh.function != nullptr && !sh.discards; }
  /// Makes draw `sh` the queue's, writing out another draw's entries first; `span` is the
  /// samples an entry may write.
  static void use_draw(ShadeQueue& q, const DrawShading& sh, bool blend, int span) {
    if (q.shading == &sh) return;
    flush(q);
    q.shading = &sh;
    q.blend = blend;
    q.span = span;
  }
  /// Queues one pixel of triangle t for a queued draw under MSAA, as color_block() queues a
  /// partial batch's pixels: its centre (x, y), its first colour sample `color` (an index into
  /// color_base) and the bits of its samples that passed. For triangles of a few pixels, which
  /// never fill a batch of a block.
  static void enqueue_pixel(ShadeQueue& q, const Lanes& ln, const front::TriangleSetup& t,
                            const DrawShading& sh, bool blend, int S, float x, float y,
                            std::int32_t color, std::uint32_t samples) {
    use_draw(q, sh, blend, S);
    begin(q, t, ln.planes);
    const int n = q.n;
    q.x[n] = x;
    q.y[n] = y;
    q.color[n] = color;
    q.samples[n] = static_cast<std::int32_t>(samples);
    q.n = n + 1;
    if (q.n >= kShaderBatch) flush(q);
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
    const bool queued = queues(sh);
    if (queued) use_draw(q, sh, blend, ssaa ? 1 : S);
    const F fx_blk(static_cast<float>(px0)), fy_blk(static_cast<float>(py0));
    // The block's first colour sample as a queue entry's index, for a queued shader.
    const auto first = queued ? static_cast<std::int32_t>(cblk - q.color_base) : 0;
    // A queued shader under SSAA queues every passed sample of the block.
    if (queued && ssaa) return enqueue_lanes(q, ln, t, S, passed, first, fx_blk, fy_blk);
    // Pixels with a passed sample, once for the block: only their batches are visited.
    std::uint64_t any_pixel = S == 4 ? M::nonzero_nibbles(passed) : raster::pixels_of(passed, S);
    // A queued shader (MSAA) shades the batches it covers whole at once, and queues the pixels
    // of the others: found without a branch, since most blocks of a small triangle have none.
    std::uint64_t partial = 0;
    if (queued && !ssaa) {
      std::uint64_t whole = 0;
      for (int g = 0; g < kBatches; ++g) {
        const std::uint64_t batch = std::uint64_t{kBatchBits} << (g * kShaderBatch);
        whole |= (any_pixel & batch) == batch ? batch : 0;
      }
      partial = any_pixel & ~whole;
      any_pixel = whole;
    }
    while (any_pixel) {
      const int g = std::countr_zero(any_pixel) / kShaderBatch;
      const int shift = g * kShaderBatch;
      const auto any = static_cast<std::uint32_t>(any_pixel >> shift) & kBatchBits;
      any_pixel &= ~(std::uint64_t{kBatchBits} << shift);
      if (ssaa) {
        for (int s = 0; s < S; ++s) {
          std::uint32_t bits =
              static_cast<std::uint32_t>(raster::sample_pixels(passed, S, s) >> shift) & kBatchBits;
          if (!bits) continue;
          I sample[kBatchVectors];
          const std::uint32_t dropped =
              batch_colors(ln, t, sh, g, fx_blk, fy_blk, ln.ox[s], ln.oy[s], bits, sample);
          if (dropped) {
            clear_samples(passed, S, std::uint64_t{dropped} << shift, s);
            bits &= ~dropped;
          }
          write_batch(sample, bits, g, s, S, blend, cblk);
        }
        continue;
      }
      if (queued) flush(q);
      I pixel[kBatchVectors];
      const std::uint32_t dropped =
          batch_colors(ln, t, sh, g, fx_blk, fy_blk, F(0.5f), F(0.5f), any, pixel);
      if (dropped) clear_pixels(passed, S, std::uint64_t{dropped} << shift);
      write_pixels(pixel, any & ~dropped, g, S, blend, passed, cblk);
    }
    // After the whole batches: the queue keeps the draw's order, and a triangle's pixels are
    // distinct, so its own writes may come in any order.
    if (partial) enqueue_pixels(q, ln, t, S, partial, first, fx_blk, fy_blk, passed);
  }
};

}  // namespace mosaic::shade
