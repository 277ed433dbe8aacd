// raster/tile_kernel.hpp — the tile rasterizer, written once and compiled per instruction set
// (simd/tile_kernel.cpp, built per instruction set with its own compiler flags).
//
// Takes: a tile, its bin and the frame state (raster/tile.hpp). Gives: the tile resolved into
// the image. For each triangle, in submission order, it walks the 8×8-pixel blocks of the
// triangle's bounding box inside the tile:
//   1. trivial reject / accept of the block from the edge functions at its corners (int64,
//      stepped from block to block along a row);
//   2. hierarchical z (raster/hiz.hpp): reject the block if the triangle is entirely behind it,
//      or skip the per-sample depth test if it is entirely in front (a row of three or more
//      blocks is classified at once, in double lanes: HizSimd::classify_row());
//   3. coverage: one bit per sample of the block, in the order of its sample memory (pixel-major,
//      raster/tile.hpp: a vector holds every sample of a few pixels), from SIMD int32 edge
//      functions stepped from the block corner a row at a time (exact: the corner value is
//      int64, and a block whose values could leave int32 is evaluated in double lanes, exact for
//      integers below 2^53); from 8 samples on only over the block rows that no single edge
//      excludes whole (one vector test per block: a thin triangle reaches a few rows of a block);
//   4. depth (float plane, the same operations as the reference) and the per-sample test;
//   5. colour (shade/shade_simd.hpp): once per pixel (MSAA) or per sample (SSAA), written where
//      the test passed.
// A draw with a shader or blending (generic, shade/shade_simd.hpp) takes the same steps 1-4, keeps
// each sample's passing lanes, and then colours the block in batches of kShaderBatch pixels:
// one call of the shader's batch function per batch (not per pixel), then blending per sample.
// A triangle whose box is a few pixels of one block (setup shrinks a tiny triangle's box to its
// covered samples) skips the walker: pixel_impl() makes the same tests, writes and counts in
// scalar code. A box within 2×2 blocks takes the lean small-box walker (small_box()), which
// evaluates the coverage of only the block rows its box meets, in depth-only draws at one sample
// and in flat, interpolated or shaded colour draws at 1x and 4x.
// A depth-only draw leaves a block that one triangle covers and wins whole as that
// triangle's depth plane (TileScratch::plane), whose samples are written when something reads
// them: under overdraw, once instead of once per triangle.
// The kernel a triangle gets is specialised on what its draw uses (raster/kernel_traits.hpp;
// pick() chooses once per bin run): the depth test and write, the colour mode, MSAA or SSAA — a
// depth-only draw shades nothing and touches no colour memory, and at one sample its kernel is
// specialised once more (the occluder pass). The tile clears and resolves only the buffers the
// frame uses (TileFrame::keep_color, keep_depth).
// At the end the tile's samples are resolved (box filter, resolve/resolve_simd.hpp) while they
// are still in cache, and its blocks' exact depth bounds go to the frame's hierarchical z when
// asked for.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <tuple>
#include <utility>
#include <xsimd/xsimd.hpp>

#include "front/draw_area.hpp"
#include "raster/hiz.hpp"
#include "raster/kernel_traits.hpp"
#include "raster/sample_patterns.hpp"
#include "raster/tile.hpp"
#include "resolve/clear_tile.hpp"
#include "resolve/resolve_simd.hpp"
#include "shade/shade_simd.hpp"
#include "simd/lane_types.hpp"

namespace mosaic::raster {

template <class A>
struct TileKernelImpl : simd::LaneTypes<A> {
  using B = simd::LaneTypes<A>;
  using B::kDLanes;
  using B::kLaneBits;
  using B::L;
  using typename B::D;
  using typename B::F;
  using typename B::I;
  using typename B::M;
  using Sh = shade::ShadeSimd<A>;
  static constexpr int kDVectors =
      kBlockPixels / kDLanes;                        ///< double vectors per sample of a block
  static constexpr int kVectors = kBlockPixels / L;  ///< vectors per sample of a block
  static_assert(kBlockPixels % L == 0);
  /// Vectors until the lanes' pixel columns repeat, and the rows that period advances by.
  static constexpr int kPeriod = L >= kBlockSize ? 1 : kBlockSize / L;
  static constexpr int kPeriodRows = L >= kBlockSize ? L / kBlockSize : 1;
  /// Coverage words (64 lanes each) whose vectors fit one 64-bit word of vector bits.
  static constexpr int kGroup = 64 / kVectors;
  /// The most vectors a block row of samples takes (pixel-major: 8 pixels × kMaxSamples), and
  /// double vectors.
  static constexpr int kRowVectors = kBlockSize * kMaxSamples / L;
  static constexpr int kRowDVectors = kBlockSize * kMaxSamples / kDLanes;
  static constexpr int kDOffsets = std::max(kDVectors, kRowDVectors);
  static_assert(kVectors <= 32 && kGroup >= 1);

  /// Lane l of vector v holds pixel p = v * L + l of the block: column p % 8, row p / 8.
  static I lane_col(int v) {
    alignas(64) std::int32_t c[L];
    for (int l = 0; l < L; ++l) c[l] = (v * L + l) % kBlockSize;
    return I::load_aligned(c);
  }
  static I lane_row(int v) {
    alignas(64) std::int32_t r[L];
    for (int l = 0; l < L; ++l) r[l] = (v * L + l) / kBlockSize;
    return I::load_aligned(r);
  }

  struct Context {
    const TileFrame& f;
    const TileRect& tile;
    TileScratch& sc;
    TileStats& st;
    std::span<const SampleOffset> pattern;
    int side = 0;    ///< blocks per tile row: the frame's tile size / kBlockSize
    int blocks = 0;  ///< blocks per tile: side²
    std::uint64_t valid[kMaxBlocksPerTile];  ///< pixels of each block inside the image
    /// Hierarchical z of the whole tile: bounds of its blocks' bounds, always conservative (a
    /// block's bounds widening widens them at once), and rescanned from the blocks only when
    /// some block's bounds narrowed and the loose bounds failed to reject a triangle.
    float tile_zmin = 0, tile_zmax = 0;
    bool tile_z_loose = false;
    I col[kVectors], row[kVectors];  ///< each lane's pixel column and row in its block
    /// The same as floats, the sample offsets from the pixel corner, and the plane array of the
    /// bin run being drawn: what shading needs of the block's lanes.
    typename Sh::Lanes ln;
    /// Per vector k of a block's sample memory (pixel-major: lane l holds sample g % S of pixel
    /// g / S, g = k * L + l), the lanes' sample positions from the block's corner, col + ox[s] and
    /// row + oy[s]. Every term and sum is exact in float (multiples of 1/16 below 2^4), so a
    /// block's sample position corner + sxy[k] equals the reference's (corner + col) + ox[s] bit
    /// for bit; the depth loop then needs only the vector's index k.
    const F* sx = nullptr;
    const F* sy = nullptr;
    /// Pixel-major coverage (two or more samples): lane l of a block row's vector j holds sample
    /// (j * L + l) % S of the row's pixel (j * L + l) / S; rx, ry are its position from the row's
    /// first pixel corner, in 16.8 (sample offset included), so that an edge's value there is
    /// its corner value plus a * rx + b * ry.
    const I* rx = nullptr;
    const I* ry = nullptr;
    /// Interpolated colour (MSAA): lane l of vector k takes the colour of lane pick[k % S][l] of
    /// its pixels' row vector k / S (the colours are made once per row vector of pixels).
    const I* pick = nullptr;
    std::int64_t soff[2][kMaxSamples];  ///< sample offset from the pixel corner, in 16.8
    /// A shader draw's pixels waiting for a whole batch; written before anything else colours
    /// the tile (another draw's run, the resolve).
    typename Sh::ShadeQueue queue;
    /// Pixels of each block the draw being drawn may cover: `valid`, or sc.clipped when its clip
    /// rectangle (viewport ∩ scissor, front/draw_area.hpp) cuts the tile. Hierarchical z counts
    /// a block's samples from `valid`: samples outside the rectangle still hold depths.
    const std::uint64_t* cover = nullptr;
    /// The blocks [x0, x1) × [y0, y1) where `cover` is not empty (the image and clip rectangle
    /// cut a tile in rectangles), for valid and for sc.clipped: a triangle hidden in the whole
    /// tile counts its rejected blocks from them, without reading `cover`.
    struct BlockRect {
      int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    };
    BlockRect cover_blocks{}, valid_blocks{}, clipped_blocks{};
    PixelRect clipped_rect{};  ///< the rectangle (target pixels) sc.clipped was made for
    bool clipped_made = false;
    int planes = 0;  ///< blocks whose depth plane is pending (TileScratch::plane_pending)
  };

  using TriangleFn = void (*)(Context&, const front::TriangleSetup&);
  /// A draw state's kernel for any box (the block walker), for a box of a few pixels, and for a
  /// box within 2×2 blocks (draw_triangle() chooses).
  struct Kernel {
    TriangleFn box = nullptr, pixel = nullptr, small = nullptr;
  };
  /// The forms of the block walker: for any box; the same with depth planes (depth-only draws
  /// that write depth).
  enum class Walk { kBlocks, kPlanes };

  /// The rows [r0, r1) of a block that a triangle's box meets. No sample outside the box is
  /// covered, so the other rows' coverage is known to be empty without evaluating it.
  struct BoxRows {
    int r0 = 0, r1 = kBlockSize;
  };
  /// The kernels of one draw's triangles: those without colour planes, and those with.
  struct DrawKernels {
    Kernel flat, interpolated;
  };
  /// Draws `t` with the kernel its colour and box ask for, by the blocks its box spans (tiles
  /// start on block boundaries, so a box's blocks are in the tile the bin holds it for): a box of
  /// at most kPixelPathMax pixels in one block takes pixel_impl(), without the block walker's
  /// per-triangle setup (most triangles of a distant mesh have a box of a pixel or a few), one
  /// within 2×2 blocks the small-box walker, and the rest the block walker.
  static void draw_triangle(Context& cx, const DrawKernels& kernels,
                            const front::TriangleSetup& t) {
    const Kernel& k = front::is_flat(t) ? kernels.flat : kernels.interpolated;
    const int wide = ((t.bx1 - 1) >> kBlockShift) - (t.bx0 >> kBlockShift);
    const int tall = ((t.by1 - 1) >> kBlockShift) - (t.by0 >> kBlockShift);
    if ((wide | tall) == 0 && (t.bx1 - t.bx0) * (t.by1 - t.by0) <= kPixelPathMax)
      return k.pixel(cx, t);
    ((wide | tall) < 2 ? k.small : k.box)(cx, t);
  }

  // The specialisations of triangle_impl() a draw's state asks for. Called once per bin run (a
  // run's triangles come from one draw), not per triangle.
  static DrawKernels pick(const TileFrame& f, std::uint32_t draw) {
    const DrawState& ds = f.states[draw];
    if (!ds.color_write) {
      // A depth-only draw shades nothing; at one sample (the occluder pass) it is specialised.
      const Kernel k = f.samples == 1 ? by_depth<ColorMode::kNone, false, 1>(ds)
                                      : by_depth<ColorMode::kNone, false, 0>(ds);
      return {k, k};
    }
    if (!f.shading.empty() && f.shading[draw].generic) {
      if (f.shading[draw].discards) {
        const Kernel k = by_depth<ColorMode::kDiscarding, false, 0>(ds);
        return {k, k};
      }
      const Kernel k = generic_kernel(ds, f.samples);
      return {k, k};
    }
    const Kernel flat = by_samples<ColorMode::kFlat>(ds, f.samples);
    if (f.ssaa) return {flat, by_depth<ColorMode::kInterpolated, true, 0>(ds)};
    return {flat, by_samples<ColorMode::kInterpolated>(ds, f.samples)};
  }
  // At one sample the common kernels know it, so that the per-sample loops unroll, and at 4x
  // so do the default depth state's (a less test that writes). Knowing every count for every
  // state doubled the specialisations, and the sanitizer builds' compile time with them.
  template <ColorMode kColor>
  static Kernel by_samples(const DrawState& ds, int samples) {
    if (samples == 1) return by_depth<kColor, false, 1>(ds);
    if (samples == 4 && is_default_depth(ds))
      return kernel<KernelTraits<DepthTest::kLess, true, kColor, false, 4>>();
    return by_depth<kColor, false, 0>(ds);
  }
  // A shaded draw's kernel: the default depth state's is specialised at one sample and at 4x,
  // the sample counts whose per-sample loops then unroll; other states take the frame's count.
  static Kernel generic_kernel(const DrawState& ds, int samples) {
    if (is_default_depth(ds) && samples == 1)
      return kernel<KernelTraits<DepthTest::kLess, true, ColorMode::kGeneric, false, 1>>();
    if (is_default_depth(ds) && samples == 4)
      return kernel<KernelTraits<DepthTest::kLess, true, ColorMode::kGeneric, false, 4>>();
    return by_depth<ColorMode::kGeneric, false, 0>(ds);
  }
  static bool is_default_depth(const DrawState& ds) {
    return ds.depth_test == DepthTest::kLess && ds.depth_write;
  }
  template <ColorMode kColor, bool kSsaa, int kSamples>
  static Kernel by_depth(const DrawState& ds) {
    switch (ds.depth_test) {
      case DepthTest::kLess:
        return with_write<DepthTest::kLess, kColor, kSsaa, kSamples>(ds.depth_write);
      case DepthTest::kLessEqual:
        return with_write<DepthTest::kLessEqual, kColor, kSsaa, kSamples>(ds.depth_write);
      case DepthTest::kGreater:
        return with_write<DepthTest::kGreater, kColor, kSsaa, kSamples>(ds.depth_write);
      case DepthTest::kGreaterEqual:
        return with_write<DepthTest::kGreaterEqual, kColor, kSsaa, kSamples>(ds.depth_write);
      case DepthTest::kAlways:
        break;
    }
    return with_write<DepthTest::kAlways, kColor, kSsaa, kSamples>(ds.depth_write);
  }
  template <DepthTest kTest, ColorMode kColor, bool kSsaa, int kSamples>
  static Kernel with_write(bool write) {
    if (write) return kernel<KernelTraits<kTest, true, kColor, kSsaa, kSamples>>();
    return kernel<KernelTraits<kTest, false, kColor, kSsaa, kSamples>>();
  }
  template <class K>
  static Kernel kernel() {
    // Boxes within 2×2 blocks: small_box() for depth-only draws at one sample and for flat,
    // interpolated and shaded colour in the default depth state at 1x and 4x (the only states
    // whose traits fix 4 samples); the block walker otherwise.
    // A shader that discards writes depth after shading, which only the block walker does.
    if constexpr (K::kLateZ)
      return {&triangle_impl<K>, &triangle_impl<K>, &triangle_impl<K>};
    else if constexpr (K::kOneSample && K::kColor == ColorMode::kNone && kUsesPlanes<K>)
      return {&depth_only_walker<K, &triangle_impl<K>>, &pixel_impl<K>,
              &depth_only_walker<K, &small_box<K>>};
    else if constexpr (K::kOneSample && K::kColor == ColorMode::kNone)
      return {&triangle_impl<K>, &pixel_impl<K>, &small_box<K>};
    else if constexpr ((K::kSamples == 1 || K::kSamples == 4) && !K::kSsaa &&
                       K::kTest == DepthTest::kLess && K::kWrite)  // the default depth state
      return {&triangle_impl<K>, &pixel_impl<K>, &small_box<K>};
    else if constexpr (kUsesPlanes<K>)
      return {&depth_only_walker<K, &triangle_impl<K>>, &pixel_impl<K>,
              &depth_only_walker<K, &triangle_impl<K>>};
    else
      return {&triangle_impl<K>, &pixel_impl<K>, &triangle_impl<K>};
  }

  template <DepthTest kTest>
  static std::uint32_t passes(F z, F stored) {
    if constexpr (kTest == DepthTest::kLess) return M::bits(z < stored);
    if constexpr (kTest == DepthTest::kLessEqual) return M::bits(z <= stored);
    if constexpr (kTest == DepthTest::kGreater) return M::bits(z > stored);
    if constexpr (kTest == DepthTest::kGreaterEqual) return M::bits(z >= stored);
    return kLaneBits;
  }

  /// Whether a kernel's draws leave and meet depth planes (TileScratch::plane): depth-only draws
  /// that write depth. draw_run() takes every pending plane before a draw that does not
  /// (uses_planes(), the same test on the draw's state, as pick() maps it to traits).
  template <class K>
  static constexpr bool kUsesPlanes = (K::kColor == ColorMode::kNone) && K::kWrite;
  static bool uses_planes(const DrawState& ds) { return !ds.color_write && ds.depth_write; }

  /// The reference's depth plane in lanes, at sample positions (fx, fy) in pixels:
  /// (base + ddx * (x - x0)) + ddy * (y - y0), clamped to [lo, hi]. The walkers and take_plane()
  /// evaluate depth only through it, so a plane written late has the bits of one written at once.
  struct DepthLanes {
    F x0, y0, base, ddx, ddy, lo, hi;
    DepthLanes(const front::Plane& z, float px, float py, float zlo, float zhi)
        : x0(px), y0(py), base(z.base), ddx(z.ddx), ddy(z.ddy), lo(zlo), hi(zhi) {}
    [[gnu::always_inline]] F at(F fx, F fy) const {
      return Sh::clamp((base + ddx * (fx - x0)) + ddy * (fy - y0), lo, hi);
    }
  };

  // The block walker of a depth-only draw that writes depth, for t. Only such draws meet pending
  // planes (draw_run() takes them before any other draw). The walker with planes takes a block's
  // plane before it touches the block and leaves a whole block it covers and wins as a plane: it
  // draws a triangle that may cover whole blocks (may_cover_a_block()), and any in a tile with
  // planes. The plain walker draws the rest, so that a tile of small triangles pays nothing for
  // planes: the block walker or small_box(). (Each walker is a function of its own: the choice
  // inside the plain one cost it registers.)
  template <class K, TriangleFn kPlain>
  static void depth_only_walker(Context& cx, const front::TriangleSetup& t) {
    if (cx.planes || may_cover_a_block(t)) return triangle_impl<K, Walk::kPlanes>(cx, t);
    kPlain(cx, t);
  }

  // The lean small-box walker, for a box within 2×2 blocks at a fixed 1 or 4 samples (depth-only
  // draws at one sample, the occluder pass, and flat, interpolated and shaded colour): per block
  // the block walker's corner test, hierarchical z, coverage (of the box's rows only, at 4x),
  // depth test, colour or the shading queue, counters and bounds, without its machinery for
  // larger boxes (row rejects, per-block depth ranges), run-time sample counts and late depth
  // writes. A depth-only draw that writes depth reaches it through depth_only_walker().
  template <class K>
  [[gnu::noinline]] static void small_box(Context& cx, const front::TriangleSetup& t) {
    static_assert((K::kSamples == 1 || K::kSamples == 4) && !K::kSsaa && !K::kLateZ);
    constexpr int S = K::kSamples;
    constexpr DepthTest kTest = K::kTest;
    constexpr bool kFlat = K::kColor == ColorMode::kFlat;
    constexpr bool kInterpolated = K::kColor == ColorMode::kInterpolated;
    constexpr bool kGeneric = K::kGeneric;
    const TileRect& tile = cx.tile;
    const auto [x_lo, x_hi, y_lo, y_hi, bxb, bxe, byb, bye] = box_in_tile(t, tile);
    if (x_lo >= x_hi || y_lo >= y_hi) return;
    // The box's depth range bounds each of its blocks' (as the block walker's small box).
    float rlo = t.z_min, rhi = t.z_max;
    if constexpr (kTest != DepthTest::kAlways) {
      const bool whole = x_lo == t.bx0 && x_hi == t.bx1 && y_lo == t.by0 && y_hi == t.by1;
      if (!whole)
        std::tie(rlo, rhi) =
            BlockDepthRange(t).over(x_lo, y_lo, x_hi - x_lo, y_hi - y_lo, t.z_min, t.z_max);
      if (hidden_in_tile<kTest>(cx, rlo, rhi, bxb, bxe, byb, bye)) return;
    }
    // Edge offsets to the lanes, exact modulo 2^32: at one sample a block's vectors by periods
    // (coverage32), at several a block row's vectors, pixel-major (coverage32_rows).
    constexpr int kOffsets = S == 1 ? kPeriod : kBlockSize * S / L;
    std::int64_t a[3], b[3], elo[3], ehi[3];
    I eoff[3][S == 1 ? kPeriod : kRowVectors], down[3];
    std::uint32_t centre[3] = {};
    for (int e = 0; e < 3; ++e) {
      a[e] = t.edge[e].a;
      b[e] = t.edge[e].b;
      const std::int64_t da = a[e] * kBlockSpan, db = b[e] * kBlockSpan;
      elo[e] = std::min<std::int64_t>(0, da) + std::min<std::int64_t>(0, db);
      ehi[e] = std::max<std::int64_t>(0, da) + std::max<std::int64_t>(0, db);
      if constexpr (S == 1) {
        const I as(static_cast<std::int32_t>(a[e] * kSubpixel));
        const I bs(static_cast<std::int32_t>(b[e] * kSubpixel));
        for (int v = 0; v < kOffsets; ++v) eoff[e][v] = as * cx.col[v] + bs * cx.row[v];
        down[e] = I(static_cast<std::int32_t>(b[e] * kSubpixel * kPeriodRows));
        centre[e] = static_cast<std::uint32_t>(kHalf * a[e] + kHalf * b[e]);
      } else {
        const I as(static_cast<std::int32_t>(a[e])), bs(static_cast<std::int32_t>(b[e]));
        for (int j = 0; j < kOffsets; ++j) eoff[e][j] = as * cx.rx[j] + bs * cx.ry[j];
        down[e] = I(static_cast<std::int32_t>(b[e] * kSubpixel));
      }
    }
    const DepthLanes depth(t.z, t.x0, t.y0, t.z_min, t.z_max);
    // The colour: the triangle's, or its planes copied out of the chunk's array (as the walker).
    [[maybe_unused]] const I flat_color(Sh::bits_of(t.color));
    [[maybe_unused]] std::array<front::Plane, front::kColorPlanes> color_planes;
    if constexpr (kInterpolated)
      std::copy_n(cx.ln.planes + t.planes_base, front::kColorPlanes, color_planes.begin());
    for (int by = byb; by < bye; ++by) {
      const int py0 = tile.y0 + by * kBlockSize;
      const F fy_row = F(static_cast<float>(py0));
      // The block rows the box meets (coverage32_rows evaluates those only).
      [[maybe_unused]] const BoxRows rows{std::max(y_lo - py0, 0),
                                          std::min(y_hi - py0, kBlockSize)};
      for (int bx = bxb; bx < bxe; ++bx) {
        const int blk = by * cx.side + bx;
        const int px0 = tile.x0 + bx * kBlockSize;
        std::int64_t eorg[3];
        bool outside = false, fits32 = true;
        for (int e = 0; e < 3; ++e) {
          eorg[e] = a[e] * (std::int64_t{px0} * kSubpixel) +
                    b[e] * (std::int64_t{py0} * kSubpixel) + t.edge[e].c;
          const std::int64_t lo = eorg[e] + elo[e], hi = eorg[e] + ehi[e];
          outside |= hi < 0;
          fits32 &= lo >= std::numeric_limits<std::int32_t>::min() &&
                    hi <= std::numeric_limits<std::int32_t>::max();
        }
        const std::uint64_t inside = cx.cover[blk];
        if (outside || !inside) continue;
        const int hz = hiz_classify<kTest>(rlo, rhi, cx.sc.zmin[blk], cx.sc.zmax[blk]);
        if (hz < 0) {
          ++cx.st.blocks_hiz_rejected;
          continue;
        }
        const bool test = hz == 0;
        if (!test && kTest != DepthTest::kAlways) ++cx.st.blocks_hiz_accepted;
        const std::uint32_t keep = test ? 0u : kLaneBits;
        // Coverage from int32 edge values (exact: fits32), or in double lanes for a block whose
        // values could leave int32 (rare); then the pixels inside the image and clip rectangle.
        std::uint64_t cov[S];
        if (fits32) {
          const auto c0 = static_cast<std::uint32_t>(eorg[0]),
                     c1 = static_cast<std::uint32_t>(eorg[1]),
                     c2 = static_cast<std::uint32_t>(eorg[2]);
          if constexpr (S == 1)
            cov[0] = coverage32(I(static_cast<std::int32_t>(c0 + centre[0])),
                                I(static_cast<std::int32_t>(c1 + centre[1])),
                                I(static_cast<std::int32_t>(c2 + centre[2])), eoff, down);
          else
            coverage32_rows<S>(static_cast<std::int32_t>(c0), static_cast<std::int32_t>(c1),
                               static_cast<std::int32_t>(c2), eoff, down, S, rows, cov);
        } else {
          D doff[3][kDOffsets];
          build_doff(a, b, cx, S, doff);
          coverage_f64(eorg, b, S, doff, cov);
        }
        if (inside != kWholeBlock) {
          std::uint64_t in[S];
          spread_pixels(inside, S, in);
          for (int w = 0; w < S; ++w) cov[w] &= in[w];
        }
        float* dblk = cx.sc.depth.get() + static_cast<std::size_t>(blk) * S * kBlockPixels;
        [[maybe_unused]] std::uint32_t* cblk =
            cx.sc.color.get() + static_cast<std::size_t>(blk) * S * kBlockPixels;
        const F fx_blk = F(static_cast<float>(px0));
        [[maybe_unused]] I pixel_color[kVectors];
        [[maybe_unused]] std::uint32_t shaded = 0;
        std::uint64_t covered = 0, written = 0;
        // Shaded draws: the lanes of each sample that passed, queued for shading after.
        [[maybe_unused]] std::uint64_t passed[kGeneric ? passed_words(S) : 1];
        if constexpr (kGeneric) std::fill_n(passed, passed_words(S), std::uint64_t{0});
        for (int w = 0; w < S; ++w) covered += static_cast<std::uint64_t>(std::popcount(cov[w]));
        // The vectors holding a covered sample, in the order of the block's sample memory.
        std::uint64_t act = 0;
        for (int w = 0; w < S; ++w)
          act |= std::uint64_t{vectors_with_lanes(cov[w])} << (w * kVectors);
        for (; act; act &= act - 1) {
          const std::size_t k = static_cast<std::size_t>(std::countr_zero(act));
          const F fx = fx_blk + cx.sx[k], fy = fy_row + cx.sy[k];
          const F z = depth.at(fx, fy);
          const std::uint32_t pass =
              test_and_write_depth<K>(dblk + k * L, z, lanes_of(cov, k), keep);
          written += static_cast<std::uint64_t>(std::popcount(pass));
          if constexpr (kInterpolated || kGeneric) {
            if (!pass) continue;
          }
          if constexpr (kGeneric) {
            add_lanes(passed, k, pass);
          } else if constexpr (S == 1 && (kFlat || kInterpolated)) {
            // A lane is a pixel: its colour at the pixel centre, made for this vector only.
            I color = flat_color;
            if constexpr (kInterpolated)
              color = Sh::interpolate(t, color_planes.data(), fx_blk + cx.ln.colf[k] + F(0.5f),
                                      fy_row + cx.ln.rowf[k] + F(0.5f));
            std::int32_t* cp = reinterpret_cast<std::int32_t*>(cblk + k * L);
            xsimd::select(M::ints(pass), color, I::load_aligned(cp)).store_aligned(cp);
          } else if constexpr (kFlat || kInterpolated) {
            write_color<K>(cx, t, color_planes.data(), flat_color, fx, fy, fx_blk, fy_row, k, pass,
                           cblk, S, pixel_color, shaded);
          }
        }
        if constexpr (kGeneric) {
          if (written) color_generic(cx, t, blk, px0, py0, passed);
        }
        cx.st.samples_tested += covered;
        cx.st.samples_written += written;
        if (K::kWrite && written)
          keep_block_bounds<kTest>(cx, blk, S, covered, written, rlo, rhi, true);
      }
    }
  }

  // The block walker, in one of its forms (Walk).
  template <class K, Walk kWalk = Walk::kBlocks>
  [[gnu::noinline]] static void triangle_impl(Context& cx, const front::TriangleSetup& t) {
    constexpr bool kPlanes = kWalk == Walk::kPlanes;
    constexpr DepthTest kTest = K::kTest;
    constexpr bool kWrite = K::kWrite, kS1 = K::kOneSample;
    constexpr bool kColor = K::kColor != ColorMode::kNone;
    constexpr bool kFlat = K::kColor == ColorMode::kFlat;
    // A shader that discards tests depth first and writes it after shading, for what it keeps.
    constexpr bool kLateZ = K::kLateZ, kGeneric = K::kGeneric;
    const TileFrame& f = cx.f;
    const TileRect& tile = cx.tile;
    const int S = K::kSamples ? K::kSamples : f.samples;
    // An interpolated triangle's colour planes, copied out of the chunk's array once: the
    // compiler then knows no depth or colour store overwrites them, and need not reload them
    // for every vector it shades (it did: +2.7% instructions in this kernel on `default --ssaa`).
    std::array<front::Plane, front::kColorPlanes> color_planes;
    if constexpr (kColor && !kFlat && !kGeneric)
      std::copy_n(cx.ln.planes + t.planes_base, front::kColorPlanes, color_planes.begin());

    const auto [x_lo, x_hi, y_lo, y_hi, bxb, bxe, byb, bye] = box_in_tile(t, tile);
    if (x_lo >= x_hi || y_lo >= y_hi) return;

    // Hierarchical z over the whole tile first: a triangle hidden behind every block the tile
    // has is dropped without visiting one (the common case under heavy overdraw). The plane's
    // double form (BlockDepthRange) is made where a range is evaluated, not for every pair.
    // The triangle's depth over its box in this tile bounds the depth of every sample it covers
    // (they lie in the box), so a triangle whose box meets at most 2×2 blocks uses it for each of
    // its blocks instead of computing one range per block: exact output either way, the ranges
    // only decide which work is skipped.
    float rlo = t.z_min, rhi = t.z_max;
    const bool small_box = bxe - bxb <= 2 && bye - byb <= 2;
    if constexpr (kTest != DepthTest::kAlways) {
      // A small box the tile does not cut: its plane range, clamped to the vertices' depths, is
      // at most [z_min, z_max] and rarely narrower, so the double evaluation is skipped.
      const bool whole = x_lo == t.bx0 && x_hi == t.bx1 && y_lo == t.by0 && y_hi == t.by1;
      if (!(small_box && whole))
        std::tie(rlo, rhi) =
            BlockDepthRange(t).over(x_lo, y_lo, x_hi - x_lo, y_hi - y_lo, t.z_min, t.z_max);
      if (hidden_in_tile<kTest>(cx, rlo, rhi, bxb, bxe, byb, bye)) return;
    }

    // Per-triangle SIMD constants. Offsets are exact modulo 2^32: the int32 lanes wrap, and
    // where the final value is known to fit int32 (fits32 below) the wrapped sum is exact.
    std::int64_t a[3], b[3], estep[3], elo[3], ehi[3];
    I eoff[3][kPeriod], rows_down[3];
    for (int e = 0; e < 3; ++e) {
      a[e] = t.edge[e].a;
      b[e] = t.edge[e].b;
      // One block to the right, and the edge's extremes over a block from its corner value.
      const std::int64_t da = a[e] * kBlockSpan, db = b[e] * kBlockSpan;
      estep[e] = da;
      elo[e] = std::min<std::int64_t>(0, da) + std::min<std::int64_t>(0, db);
      ehi[e] = std::max<std::int64_t>(0, da) + std::max<std::int64_t>(0, db);
      const I as(static_cast<std::int32_t>(a[e] * kSubpixel));
      const I bs(static_cast<std::int32_t>(b[e] * kSubpixel));
      // The lanes' columns repeat every kPeriod vectors, kPeriodRows rows further down: the
      // offsets of the first period, and the step to the next (coverage32 steps them, mod 2^32).
      for (int v = 0; v < kPeriod; ++v) eoff[e][v] = as * cx.col[v] + bs * cx.row[v];
      rows_down[e] = I(static_cast<std::int32_t>(b[e] * kSubpixel * kPeriodRows));
    }
    // One sample: each edge's offset from a pixel's corner to its centre, mod 2^32 like eoff.
    // More: the edges' offsets to the lanes of a block row's vectors (pixel-major, Context::rx),
    // and their step from one block row to the next.
    const bool one = kS1 || S == 1;
    std::uint32_t centre[3];
    const int row_vectors = one ? 0 : kBlockSize * S / L;
    I roff[3][kS1 ? 1 : kRowVectors], row_down[3];
    for (int e = 0; e < 3; ++e) {
      centre[e] = static_cast<std::uint32_t>(kHalf * a[e] + kHalf * b[e]);
      const I as(static_cast<std::int32_t>(a[e])), bs(static_cast<std::int32_t>(b[e]));
      for (int j = 0; j < row_vectors; ++j) roff[e][j] = as * cx.rx[j] + bs * cx.ry[j];
      row_down[e] = I(static_cast<std::int32_t>(b[e] * kSubpixel));
    }
    // From kRowTestSamples samples on, coverage is evaluated only over the block rows whose
    // samples no single edge excludes (a thin triangle's blocks hold a few of their rows), from
    // each edge's largest value over row r's samples in lane r (rows_reached()).
    const bool row_test =
        !kS1 && (K::kSamples == 0 || K::kSamples >= kRowTestSamples) && S >= kRowTestSamples;
    [[maybe_unused]] RowMaxima row_max[3];
    if (row_test)
      for (int e = 0; e < 3; ++e) row_max[e] = row_maxima(cx, a[e], b[e], S);
    // Offsets of the edges from a block's corner to its pixels in double, for blocks whose values
    // could leave int32 (see coverage_f64); built for the first such block only.
    D doff[3][kDOffsets];
    bool doff_built = false;
    const float tlo = t.z_min, thi = t.z_max;
    const DepthLanes depth(t.z, t.x0, t.y0, tlo, thi);
    [[maybe_unused]] const I flat_color(Sh::bits_of(t.color));
    // A larger box's depth range per block (a small one takes rlo, rhi for every block).
    BlockDepthRows<kBlockSize> block_depth;
    if (!small_box) block_depth = BlockDepthRows<kBlockSize>(t);

    for (int by = byb; by < bye; ++by) {
      const int py0 = tile.y0 + by * kBlockSize;
      typename BlockDepthRows<kBlockSize>::Row depth_row{};
      if (!small_box) depth_row = BlockDepthRows<kBlockSize>::row(t, py0);
      // The blocks of this row that no edge rejects: each edge's largest value over a block is
      // linear in the block's x, so each edge bounds bx from one side.
      int row_b = bxb, row_e = bxe;
      const std::int64_t x_base = std::int64_t{tile.x0} * kSubpixel;
      // (A box one or two blocks wide is left to the corner test below: three int64 divisions
      // per block row cost more than testing a second block's corners.)
      for (int e = 0; e < 3 && row_e - row_b > 2; ++e) {
        // max over the block at column bx = a * X(bx) + k, X(bx) = (tile.x0 + 8 bx) * 256.
        const std::int64_t k = b[e] * (std::int64_t{py0} * kSubpixel) + t.edge[e].c +
                               std::max<std::int64_t>(0, a[e] * kBlockSpan) +
                               std::max<std::int64_t>(0, b[e] * kBlockSpan);
        if (a[e] == 0) {
          if (k < 0) row_e = row_b;
        } else if (a[e] > 0) {
          // a * (x_base + bx * span) + k >= 0  <=>  bx >= ceil((-k - a * x_base) / (a * span))
          const std::int64_t num = -k - a[e] * x_base, den = a[e] * kBlockSpan;
          row_b = static_cast<int>(std::max<std::int64_t>(row_b, ceil_div(num, den)));
        } else {
          // bx <= floor((k + a * x_base) / (-a * span))
          const std::int64_t num = k + a[e] * x_base, den = -a[e] * kBlockSpan;
          row_e = static_cast<int>(std::min<std::int64_t>(row_e, floor_div(num, den) + 1));
        }
      }
      const F fy_row = F(static_cast<float>(py0));

      // Edge functions at the corner of block row_b, stepped by one block along the row.
      std::int64_t erow[3];
      for (int e = 0; e < 3; ++e)
        erow[e] = a[e] * ((std::int64_t{tile.x0} + std::int64_t{row_b} * kBlockSize) * kSubpixel) +
                  b[e] * (std::int64_t{py0} * kSubpixel) + t.edge[e].c;
      // 3-5 for block bx of the row, which no edge rejects and hierarchical z keeps: its cover,
      // its edges at the corner, whether each holds over all of the block and whether their values
      // over it fit int32, its depth range, and whether its samples need the depth test.
      const auto draw_block = [&](int bx, std::uint64_t inside, const std::int64_t(&eorg)[3],
                                  bool all_in, bool fits32, float blo, float bhi, bool test)
          __attribute__((always_inline)) {
        const int blk = by * cx.side + bx;
        const int px0 = tile.x0 + bx * kBlockSize;

        if constexpr (kPlanes) {
          // Every sample of the block covered and passing: the plane instead of the samples,
          // with the counts and bounds the depth loop would give.
          if (all_in && !test && inside == kWholeBlock) {
            record_plane(cx, blk, t);
            const std::uint64_t n = std::uint64_t{kBlockPixels} * static_cast<std::uint64_t>(S);
            cx.st.samples_tested += n;
            cx.st.samples_written += n;
            keep_block_bounds<kTest>(cx, blk, S, n, n, blo, bhi, small_box);
            return;
          }
          if (cx.sc.plane_pending[blk]) take_plane(cx, blk);
        }

        // 3–5. Coverage, depth test and writes. The coverage of a group of samples is built first,
        // every vector of the block without a branch; then only the (sample, vector) pairs holding
        // a covered sample are visited, in sample-major order, one bit of `act` each. Looping over
        // the box's rows and branching on empty vectors mispredicted 40 branches per triangle and
        // tile, this 10 (cachegrind branch simulation, random-small 4x, AVX2: 4.9M -> 1.3M).
        // (Folding coverage into the depth loop, one vector at a time, measured 7-11 % more
        // instructions, callgrind, AVX2.)
        // The lane tables' pointers in locals: the stores below could alias cx, to the compiler.
        const F* const sx = cx.sx;
        const F* const sy = cx.sy;
        float* dblk = cx.sc.depth.get() + static_cast<std::size_t>(blk) * S * kBlockPixels;
        [[maybe_unused]] std::uint32_t* cblk =
            kColor ? cx.sc.color.get() + static_cast<std::size_t>(blk) * S * kBlockPixels : nullptr;
        const F fx_blk = F(static_cast<float>(px0));
        [[maybe_unused]] I pixel_color[kVectors];
        [[maybe_unused]] std::uint32_t shaded = 0;
        // Generic draws: the lanes of each sample that passed the depth test, coloured after.
        [[maybe_unused]] std::uint64_t passed[kGeneric ? kMaxSamples : 1];
        static_assert(!kGeneric || L / 2 <= kMaxSamples);
        if constexpr (kGeneric) std::fill_n(passed, passed_words(S), std::uint64_t{0});
        // A block the hierarchical z accepts passes every covered sample without the test.
        const std::uint32_t keep = test ? 0u : kLaneBits;
        std::uint64_t written = 0, covered = 0;
        // Coverage, one bit per lane of the block's sample memory (pixel-major), laid out in
        // cov's words as the memory is.
        std::uint64_t cov[kMaxSamples];
        if (all_in) {
          spread_pixels(inside, S, cov);
        } else {
          const std::uint32_t c0 = static_cast<std::uint32_t>(eorg[0]),
                              c1 = static_cast<std::uint32_t>(eorg[1]),
                              c2 = static_cast<std::uint32_t>(eorg[2]);
          if (fits32 && one) {
            // Edge values at the block's first pixel centre (exact: fits32), mod 2^32.
            cov[0] = coverage32(I(static_cast<std::int32_t>(c0 + centre[0])),
                                I(static_cast<std::int32_t>(c1 + centre[1])),
                                I(static_cast<std::int32_t>(c2 + centre[2])), eoff, rows_down);
          } else if (fits32) {
            if constexpr (!kS1)
              coverage32_rows<K::kSamples>(
                  static_cast<std::int32_t>(c0), static_cast<std::int32_t>(c1),
                  static_cast<std::int32_t>(c2), roff, row_down, S,
                  row_test ? rows_reached(c0, c1, c2, row_max) : BoxRows{}, cov);
          } else {
            if (!doff_built) {
              // S passed through an empty asm: GCC (AVX-512) otherwise ran this pure build for
              // every triangle, ahead of the rare blocks that need it.
              int s = S;
              asm volatile("" : "+r"(s));
              build_doff(a, b, cx, s, doff);
              doff_built = true;
            }
            coverage_f64(eorg, b, S, doff, cov);
          }
          if (inside != kWholeBlock) {
            std::uint64_t in[kMaxSamples];
            spread_pixels(inside, S, in);
            for (int w = 0; w < S; ++w) cov[w] &= in[w];
          }
        }
        for (int w = 0; w < S; ++w) covered += static_cast<std::uint64_t>(std::popcount(cov[w]));
        for (std::size_t s0 = 0; s0 < static_cast<std::size_t>(S); s0 += kGroup) {
          const std::size_t s1 = std::min<std::size_t>(S, s0 + kGroup);
          std::uint64_t act = 0;
          for (std::size_t w = s0; w < s1; ++w)
            act |= std::uint64_t{vectors_with_lanes(cov[w])} << ((w - s0) * kVectors);
          for (; act; act &= act - 1) {
            // Vector i of the group is vector k of the block: lanes k * L .. k * L + L - 1 of
            // its sample memory.
            const std::size_t i = static_cast<std::size_t>(std::countr_zero(act));
            const std::size_t k = s0 * kVectors + i;
            const std::uint32_t lanes = lanes_of(cov, k);
            // Sample positions in pixels (exact in float), then their depth.
            const F fx = fx_blk + sx[k], fy = fy_row + sy[k];
            const F z = depth.at(fx, fy);
            float* dp = dblk + k * L;
            const std::uint32_t pass = test_and_write_depth<K>(dp, z, lanes, keep);
            written += static_cast<std::uint64_t>(std::popcount(pass));
            // Flat colour stores under the mask whatever it is; a shaded colour is worth a branch.
            if constexpr (kColor && !kFlat) {
              if (!pass) continue;
            }
            if constexpr (kGeneric) {
              add_lanes(passed, k, pass);
            } else if constexpr (kColor) {  // a depth-only draw shades nothing, keeps colour
              write_color<K>(cx, t, color_planes.data(), flat_color, fx, fy, fx_blk, fy_row, k,
                             pass, cblk, S, pixel_color, shaded);
            }
          }
        }
        // Every covered sample of a block hierarchical z did not reject reaches the depth test.
        const std::uint64_t tested = covered;
        if constexpr (kGeneric) {
          if (written) color_generic(cx, t, blk, px0, py0, passed);
        }
        if constexpr (kLateZ) {
          // What the shader kept: its depths, and the count of samples written.
          written = 0;
          for (int s = 0; s < S; ++s) {
            written += static_cast<std::uint64_t>(std::popcount(passed[s]));
            for (std::uint64_t vs = kWrite ? vectors_with_lanes(passed[s]) : 0; vs; vs &= vs - 1) {
              const std::size_t k = static_cast<std::size_t>(s * kVectors + std::countr_zero(vs));
              float* dp = dblk + k * L;
              const F z = depth.at(fx_blk + sx[k], fy_row + sy[k]);
              xsimd::select(M::floats(lanes_of(passed, k)), z, F::load_aligned(dp))
                  .store_aligned(dp);
            }
          }
        }
        cx.st.samples_tested += tested;
        cx.st.samples_written += written;

        if (kWrite && written)
          keep_block_bounds<kTest>(cx, blk, S, covered, written, blo, bhi, small_box);
      };
      const int row_n = row_e - row_b;
      if (!small_box && row_n > 2) {
        // Three or more blocks, so all three edges cut the row above and none rejects a block
        // of it: hierarchical z classifies the blocks with pixels to cover in SIMD lanes, and
        // only those it keeps are visited.
        const std::uint32_t cand = cover_in_row(cx, by, row_b, row_e);
        if (!cand) continue;
        const int j0 = std::countr_zero(cand), j1 = 32 - std::countl_zero(cand);
        const int first = by * cx.side + row_b;
        alignas(64) float row_lo[kMaxBlocksPerTileSide + kHizReadPad];
        alignas(64) float row_hi[kMaxBlocksPerTileSide + kHizReadPad];
        const auto rc = HizSimd<A>::template classify_row<kTest>(
            block_depth, depth_row, tile.x0 + (row_b + j0) * kBlockSize, j1 - j0, tlo, thi,
            cx.sc.zmin + first + j0, cx.sc.zmax + first + j0, row_lo + j0, row_hi + j0);
        const std::uint32_t rejected = (rc.rejected << j0) & cand;
        const std::uint32_t accepted = (rc.accepted << j0) & cand;
        cx.st.blocks_hiz_rejected += static_cast<std::uint64_t>(std::popcount(rejected));
        cx.st.blocks_hiz_accepted += static_cast<std::uint64_t>(std::popcount(accepted));
        for (std::uint32_t visit = cand & ~rejected; visit; visit &= visit - 1) {
          const int j = std::countr_zero(visit);
          std::int64_t eorg[3];
          bool all_in = true, fits32 = true;
          for (int e = 0; e < 3; ++e) {
            eorg[e] = erow[e] + j * estep[e];
            const std::int64_t lo = eorg[e] + elo[e], hi = eorg[e] + ehi[e];
            all_in &= lo >= 0;
            fits32 &= lo >= std::numeric_limits<std::int32_t>::min() &&
                      hi <= std::numeric_limits<std::int32_t>::max();
          }
          draw_block(row_b + j, cx.cover[first + j], eorg, all_in, fits32, row_lo[j], row_hi[j],
                     kTest != DepthTest::kAlways && !(accepted >> j & 1u));
        }
        continue;
      }
      for (int bx = row_b; bx < row_e; ++bx) {
        const int blk = by * cx.side + bx;
        const std::uint64_t inside = cx.cover[blk];
        // 1. Edge functions at the block's corner, and their extremes over the block: an edge
        // rejects the block before anything else is computed for it.
        std::int64_t eorg[3];
        bool all_in = true, fits32 = true, outside = false;
        for (int e = 0; e < 3; ++e) {
          eorg[e] = erow[e];
          erow[e] += estep[e];
          const std::int64_t lo = eorg[e] + elo[e], hi = eorg[e] + ehi[e];
          outside |= hi < 0;
          all_in &= lo >= 0;
          fits32 &= lo >= std::numeric_limits<std::int32_t>::min() &&
                    hi <= std::numeric_limits<std::int32_t>::max();
        }
        if (outside || !inside) continue;
        // 2. Hierarchical z, with the triangle's depth range over this block (its box's, if small).
        const auto [blo, bhi] =
            small_box ? std::pair<float, float>{rlo, rhi}
                      : block_depth.at(tile.x0 + bx * kBlockSize, depth_row, tlo, thi);
        const int hz = hiz_classify<kTest>(blo, bhi, cx.sc.zmin[blk], cx.sc.zmax[blk]);
        if (hz < 0) {
          ++cx.st.blocks_hiz_rejected;
          continue;
        }
        const bool test = hz == 0;
        if (!test && kTest != DepthTest::kAlways) ++cx.st.blocks_hiz_accepted;
        draw_block(bx, inside, eorg, all_in, fits32, blo, bhi, test);
      }
    }
  }

  // Blocks [row_b, row_e) of block row `by` whose cover is not empty: bit bx - row_b each.
  [[gnu::always_inline]] static std::uint32_t cover_in_row(const Context& cx, int by, int row_b,
                                                           int row_e) {
    const typename Context::BlockRect& c = cx.cover_blocks;
    if (by < c.y0 || by >= c.y1) return 0;
    const int lo = std::max(row_b, c.x0) - row_b, hi = std::min(row_e, c.x1) - row_b;
    return lo < hi ? ((1u << hi) - 1u) & ~((1u << lo) - 1u) : 0u;
  }

  /// A triangle's box cut to a tile: pixels [x_lo, x_hi) × [y_lo, y_hi) (empty if either is),
  /// and the tile's blocks [bxb, bxe) × [byb, bye) that it meets.
  struct TileBox {
    int x_lo, x_hi, y_lo, y_hi, bxb, bxe, byb, bye;
  };
  [[gnu::always_inline]] static TileBox box_in_tile(const front::TriangleSetup& t,
                                                    const TileRect& tile) {
    TileBox b;
    b.x_lo = std::max(t.bx0, tile.x0);
    b.x_hi = std::min(t.bx1, tile.x0 + tile.width);
    b.y_lo = std::max(t.by0, tile.y0);
    b.y_hi = std::min(t.by1, tile.y0 + tile.height);
    b.bxb = (b.x_lo - tile.x0) / kBlockSize;
    b.bxe = (b.x_hi - tile.x0 + kBlockSize - 1) / kBlockSize;
    b.byb = (b.y_lo - tile.y0) / kBlockSize;
    b.bye = (b.y_hi - tile.y0 + kBlockSize - 1) / kBlockSize;
    return b;
  }

  // Hierarchical z over the whole tile for a triangle whose depth over its box there is in
  // [rlo, rhi]: whether it is hidden behind every block the tile has, in which case the blocks
  // [bxb, bxe) × [byb, bye) its box meets are counted rejected from the tile's block rectangles,
  // without visiting them (the common case under heavy overdraw).
  template <DepthTest kTest>
  [[gnu::always_inline]] static bool hidden_in_tile(Context& cx, float rlo, float rhi, int bxb,
                                                    int bxe, int byb, int bye) {
    bool hidden = hiz_classify<kTest>(rlo, rhi, cx.tile_zmin, cx.tile_zmax) < 0;
    if (!hidden && cx.tile_z_loose) {
      refresh_tile_z(cx);
      hidden = hiz_classify<kTest>(rlo, rhi, cx.tile_zmin, cx.tile_zmax) < 0;
    }
    if (hidden) {
      const typename Context::BlockRect& c = cx.cover_blocks;
      const int w = std::min(bxe, c.x1) - std::max(bxb, c.x0);
      const int h = std::min(bye, c.y1) - std::max(byb, c.y0);
      if (w > 0 && h > 0) cx.st.blocks_hiz_rejected += static_cast<std::uint64_t>(w) * h;
    }
    return hidden;
  }

  // The depth test and write of block vector dp (the lanes in `lanes` covered, `keep` all lanes
  // if hierarchical z accepted the block): the lanes that pass. A lane that fails stores back
  // what it loaded; a shader that discards writes depth after shading (triangle_impl()).
  template <class K>
  [[gnu::always_inline]] static std::uint32_t test_and_write_depth(float* dp, F z,
                                                                   std::uint32_t lanes,
                                                                   std::uint32_t keep) {
    std::uint32_t pass = lanes;
    if constexpr (K::kTest != DepthTest::kAlways || K::kWrite) {
      const F stored = F::load_aligned(dp);
      if constexpr (K::kTest != DepthTest::kAlways) pass &= passes<K::kTest>(z, stored) | keep;
      if constexpr (K::kWrite && !K::kLateZ)
        xsimd::select(M::floats(pass), z, stored).store_aligned(dp);
    }
    return pass;
  }

  // The colour of block vector k where `pass`: the flat colour, or the interpolated one at the
  // samples (SSAA, fx, fy) or at the pixel centres, made once per row vector v of the block's
  // pixels (pixel_color, `shaded` bit v once it is made) and moved to vector k's lanes.
  template <class K>
  [[gnu::always_inline]] static void write_color(const Context& cx, const front::TriangleSetup& t,
                                                 const front::Plane* color_planes, I flat_color,
                                                 F fx, F fy, F fx_blk, F fy_row, std::size_t k,
                                                 std::uint32_t pass, std::uint32_t* cblk, int S,
                                                 I (&pixel_color)[kVectors],
                                                 std::uint32_t& shaded) {
    I color;
    if constexpr (K::kColor == ColorMode::kFlat) {
      color = flat_color;
    } else if constexpr (K::kSsaa) {
      color = Sh::interpolate(t, color_planes, fx, fy);
    } else {
      const std::size_t v = k / static_cast<std::size_t>(S);
      if (!(shaded & (1u << v))) {
        pixel_color[v] = Sh::interpolate(t, color_planes, fx_blk + cx.ln.colf[v] + F(0.5f),
                                         fy_row + cx.ln.rowf[v] + F(0.5f));
        shaded |= 1u << v;
      }
      color = K::kOneSample ? pixel_color[v]
                            : M::permute(pixel_color[v], cx.pick[k % static_cast<std::size_t>(S)]);
    }
    std::int32_t* cp = reinterpret_cast<std::int32_t*>(cblk + k * L);
    xsimd::select(M::ints(pass), color, I::load_aligned(cp)).store_aligned(cp);
  }

  // triangle_impl() for a triangle whose box is a few pixels of one block (draw_triangle()): the
  // tile's hierarchical z, then few_pixels().
  template <class K>
  static void pixel_impl(Context& cx, const front::TriangleSetup& t) {
    constexpr DepthTest kTest = K::kTest;
    if constexpr (kTest != DepthTest::kAlways) {
      // (The box is whole and small: its depth range is the vertices'.)
      bool hidden = hiz_classify<kTest>(t.z_min, t.z_max, cx.tile_zmin, cx.tile_zmax) < 0;
      if (!hidden && cx.tile_z_loose) {
        refresh_tile_z(cx);
        hidden = hiz_classify<kTest>(t.z_min, t.z_max, cx.tile_zmin, cx.tile_zmax) < 0;
      }
      if (hidden) {
        const typename Context::BlockRect& c = cx.cover_blocks;
        const int bx = (t.bx0 - cx.tile.x0) / kBlockSize, by = (t.by0 - cx.tile.y0) / kBlockSize;
        if (bx >= c.x0 && bx < c.x1 && by >= c.y0 && by < c.y1) ++cx.st.blocks_hiz_rejected;
        return;
      }
    }
    few_pixels<K>(cx, t, t.z_min, t.z_max);
  }

  // The block walk of triangle_impl() for a box of a few pixels in one block, in scalar code:
  // the block's corner test, its hierarchical z with the box's depth range [blo, bhi], each
  // pixel's samples (pixel_samples()) and a shaded draw's colour (shade_pixel()), and the
  // block's counters and bounds as the walker keeps them.
  template <class K>
  [[gnu::always_inline]] static void few_pixels(Context& cx, const front::TriangleSetup& t,
                                                float blo, float bhi) {
    constexpr DepthTest kTest = K::kTest;
    const TileRect& tile = cx.tile;
    const int S = K::kSamples ? K::kSamples : cx.f.samples;
    const int bx = (t.bx0 - tile.x0) / kBlockSize, by = (t.by0 - tile.y0) / kBlockSize;
    const int px0 = tile.x0 + bx * kBlockSize, py0 = tile.y0 + by * kBlockSize;
    const int blk = by * cx.side + bx;
    const std::uint64_t inside = cx.cover[blk];
    for (int e = 0; e < 3; ++e) {
      const std::int64_t a = t.edge[e].a, b = t.edge[e].b;
      const std::int64_t hi =
          a * (std::int64_t{px0} * kSubpixel) + b * (std::int64_t{py0} * kSubpixel) + t.edge[e].c +
          std::max<std::int64_t>(0, a * kBlockSpan) + std::max<std::int64_t>(0, b * kBlockSpan);
      if (hi < 0) return;  // the corner test rejects the block before it is counted
    }
    if (!inside) return;
    const int hz = hiz_classify<kTest>(blo, bhi, cx.sc.zmin[blk], cx.sc.zmax[blk]);
    if (hz < 0) {
      ++cx.st.blocks_hiz_rejected;
      return;
    }
    const bool test = hz == 0;
    if (!test && kTest != DepthTest::kAlways) ++cx.st.blocks_hiz_accepted;
    if constexpr (kUsesPlanes<K>) {
      if (cx.planes && cx.sc.plane_pending[blk]) take_plane(cx, blk);
    }
    std::uint64_t covered = 0, written = 0;
    // A shaded draw: a queued shader under MSAA takes each pixel into its queue at once (a few
    // pixels never fill a batch); otherwise the passed samples are set by lane of the block's
    // sample memory, as the walker has them (at least a vector of words, which shading may
    // load), and the block is coloured after.
    [[maybe_unused]] std::uint64_t passed[K::kGeneric ? kMaxSamples : 1];
    [[maybe_unused]] bool queued = false;
    if constexpr (K::kGeneric) {
      queued = Sh::queues(cx.f.shading[t.draw()]) && !cx.f.ssaa;
      if (!queued) std::fill_n(passed, passed_words(S), std::uint64_t{0});
    }
    const auto pixel = [&](int col, int row) {
      const std::uint32_t kept =
          pixel_samples<K>(cx, t, blk, px0, py0, col, row, inside, test, covered, written);
      if constexpr (K::kGeneric) {
        if (kept) shade_pixel<K>(cx, t, blk, px0, py0, col, row, kept, queued, passed);
      }
    };
    if (t.bx1 - t.bx0 == 1 && t.by1 - t.by0 == 1) {  // the common box: one pixel
      pixel(t.bx0 - px0, t.by0 - py0);
    } else {
      for (int py = t.by0; py < t.by1; ++py)
        for (int px = t.bx0; px < t.bx1; ++px) pixel(px - px0, py - py0);
    }
    if constexpr (K::kGeneric) {
      if (written && !queued) color_generic(cx, t, blk, px0, py0, passed);
    }
    cx.st.samples_tested += covered;
    cx.st.samples_written += written;
    if (K::kWrite && written)
      keep_block_bounds<kTest>(cx, blk, S, covered, written, blo, bhi, true);
  }

  // The samples of pixel (col, row) of block blk (corner px0, py0) for few_pixels(): exact edge
  // values, the reference's depth, and the kernel's colour, at the lanes' positions (block corner
  // plus column and sample offset); adds the samples covered and written. Returns a shaded
  // draw's samples that passed (bit s: sample s), which it leaves to shade_pixel().
  template <class K>
  [[gnu::always_inline]] static std::uint32_t pixel_samples(
      Context& cx, const front::TriangleSetup& t, int blk, int px0, int py0, int col, int row,
      std::uint64_t inside, bool test, std::uint64_t& covered, std::uint64_t& written) {
    const int p = row * kBlockSize + col;
    if (!((inside >> p) & 1)) return 0;
    const int S = K::kSamples ? K::kSamples : cx.f.samples;
    // The pixel's samples, side by side (pixel-major).
    const std::size_t first = (static_cast<std::size_t>(blk) * kBlockPixels + p) * S;
    float* dpix = cx.sc.depth.get() + first;
    [[maybe_unused]] std::uint32_t* cpix =
        K::kColor != ColorMode::kNone ? cx.sc.color.get() + first : nullptr;
    const float fx_blk = static_cast<float>(px0), fy_row = static_cast<float>(py0);
    const float colf = static_cast<float>(col), rowf = static_cast<float>(row);
    const std::int64_t x = std::int64_t{px0 + col} * kSubpixel,
                       y = std::int64_t{py0 + row} * kSubpixel;
    [[maybe_unused]] std::uint32_t pixel_color = 0;
    [[maybe_unused]] bool shaded = false;
    std::uint32_t kept = 0;
    for (int s = 0; s < S; ++s) {
      const std::int64_t sx = x + (K::kOneSample ? kHalf : cx.soff[0][s]);
      const std::int64_t sy = y + (K::kOneSample ? kHalf : cx.soff[1][s]);
      if ((t.edge[0](sx, sy) | t.edge[1](sx, sy) | t.edge[2](sx, sy)) < 0) continue;
      ++covered;
      const float fx = fx_blk + (colf + cx.ln.oxs[s]), fy = fy_row + (rowf + cx.ln.oys[s]);
      const float z = front::sample_depth(t, fx, fy);
      float& d = dpix[s];
      if (test && !passes_one<K::kTest>(z, d)) continue;
      if constexpr (K::kWrite) d = z;
      ++written;
      if constexpr (K::kGeneric) {
        kept |= 1u << s;
      } else if constexpr (K::kColor == ColorMode::kFlat) {
        cpix[s] = static_cast<std::uint32_t>(Sh::bits_of(t.color));
      } else if constexpr (K::kColor == ColorMode::kInterpolated) {
        const front::Plane* planes = cx.ln.planes + t.planes_base;
        if (K::kSsaa) {
          pixel_color = first_lane(Sh::interpolate(t, planes, F(fx), F(fy)));
        } else if (!shaded) {
          pixel_color = first_lane(
              Sh::interpolate(t, planes, F((fx_blk + colf) + 0.5f), F((fy_row + rowf) + 0.5f)));
          shaded = true;
        }
        cpix[s] = pixel_color;
      }
    }
    return kept;
  }

  // A shaded draw's pixel (col, row) of block blk, whose samples `kept` passed: into the
  // shading queue (`queued`), at the pixel centre as the queue's other entries, or into the
  // block's passed words for color_generic().
  template <class K>
  [[gnu::always_inline]] static void shade_pixel(Context& cx, const front::TriangleSetup& t,
                                                 int blk, int px0, int py0, int col, int row,
                                                 std::uint32_t kept, bool queued,
                                                 std::uint64_t* passed) {
    const int S = K::kSamples ? K::kSamples : cx.f.samples;
    const int lane = (row * kBlockSize + col) * S;  // its first sample in the block's memory
    if (!queued) {
      passed[lane / 64] |= std::uint64_t{kept} << (lane % 64);
      return;
    }
    const TileFrame& f = cx.f;
    const std::uint32_t* first =
        cx.sc.color.get() + static_cast<std::size_t>(blk) * S * kBlockPixels + lane;
    Sh::enqueue_pixel(cx.queue, cx.ln, t, f.shading[t.draw()], blends(f, t), S,
                      (static_cast<float>(px0) + static_cast<float>(col)) + 0.5f,
                      (static_cast<float>(py0) + static_cast<float>(row)) + 0.5f,
                      static_cast<std::int32_t>(first - cx.queue.color_base), kept);
  }

  template <DepthTest kTest>
  static bool passes_one(float z, float stored) {
    if constexpr (kTest == DepthTest::kLess) return z < stored;
    if constexpr (kTest == DepthTest::kLessEqual) return z <= stored;
    if constexpr (kTest == DepthTest::kGreater) return z > stored;
    if constexpr (kTest == DepthTest::kGreaterEqual) return z >= stored;
    return true;
  }

  static std::uint32_t first_lane(I v) {
    alignas(64) std::int32_t lanes[L];
    v.store_aligned(lanes);
    return static_cast<std::uint32_t>(lanes[0]);
  }

  // Keeps a block's depth bounds conservative after a triangle wrote `written` of its samples and
  // covered `covered`: every stored depth stays in [zmin, zmax]. A sample the triangle covers ends
  // up holding either its new depth, in [blo, bhi], or an old depth the test kept because it was
  // nearer than the new one.
  template <DepthTest kTest>
  [[gnu::always_inline]] static void keep_block_bounds(Context& cx, int blk, int S,
                                                       std::uint64_t covered, std::uint64_t written,
                                                       float blo, float bhi, bool small_box) {
    const std::uint64_t samples = static_cast<std::uint64_t>(std::popcount(cx.valid[blk])) * S;
    const bool all_covered = covered == samples, all_written = written == samples;
    float& zmn = cx.sc.zmin[blk];
    float& zmx = cx.sc.zmax[blk];
    const float old_lo = zmn, old_hi = zmx;
    update_block_bounds<kTest>(zmn, zmx, blo, bhi, all_covered, all_written);
    // Small triangles never cover a whole block, so the bounds above never tighten on a mesh.
    // Once small triangles (boxes of at most 2×2 blocks) have written a block's worth of samples
    // since the bounds were last tight, they are made exact from its depths: one reduction per
    // block's worth of writes. A cover of the whole block has just tightened them; a large
    // triangle's partial covers are left to it.
    std::uint32_t& since = cx.sc.hiz_written[blk];
    if (all_covered) {
      since = 0;
    } else if (small_box && (since += static_cast<std::uint32_t>(written)) >= samples) {
      since = 0;
      std::tie(zmn, zmx) = exact_block_bounds(cx, blk);
    }
    cx.tile_zmin = std::min(cx.tile_zmin, zmn);
    cx.tile_zmax = std::max(cx.tile_zmax, zmx);
    cx.tile_z_loose |= zmn > old_lo || zmx < old_hi;
  }

  // Whether triangle t's draw blends its colour over the stored one.
  static bool blends(const TileFrame& f, const front::TriangleSetup& t) {
    return f.states[t.draw()].blend == BlendMode::kSourceOver;
  }

  // Colours a block of a shaded or blending draw where its samples passed (shade/shade_simd.hpp).
  static void color_generic(Context& cx, const front::TriangleSetup& t, int blk, int px0, int py0,
                            std::uint64_t* passed) {
    const TileFrame& f = cx.f;
    const int S = f.samples;
    std::uint32_t* cblk = cx.sc.color.get() + static_cast<std::size_t>(blk) * S * kBlockPixels;
    Sh::color_block(cx.ln, cx.queue, t, f.shading[t.draw()], blends(f, t), f.ssaa, S, cblk, px0,
                    py0, passed);
  }

  // Coverage of one sample of a block from the edge values b0..b2 at that sample of its first
  // pixel, exact in int32 (the block passed fits32): bit p set where pixel p's sample is inside.
  // A value is negative, outside its edge, where its sign bit is set, so the OR of the three has
  // its sign bit set exactly where the sample is outside: no comparison is needed. Every vector of
  // the block is computed, rows outside the triangle's box too (they come out empty): a fixed
  // trip count has no branch to mispredict. The values are stepped down the block one period of
  // vectors at a time (eoff: the first period's offsets; down: one period's step).
  static std::uint64_t coverage32(I b0, I b1, I b2, const I (&eoff)[3][kPeriod],
                                  const I (&down)[3]) {
    I e0[kPeriod], e1[kPeriod], e2[kPeriod];
    for (int p = 0; p < kPeriod; ++p) {
      e0[p] = b0 + eoff[0][p];
      e1[p] = b1 + eoff[1][p];
      e2[p] = b2 + eoff[2][p];
    }
    std::uint64_t outside = 0;
    for (int v = 0; v < kVectors; ++v) {
      const int p = v % kPeriod;
      outside |= std::uint64_t{M::signs(e0[p] | e1[p] | e2[p])} << (v * L);
      e0[p] += down[0];
      e1[p] += down[1];
      e2[p] += down[2];
    }
    return ~outside;
  }

  // Words of a block's passed lanes that color_generic() reads: one a sample, and at least a
  // vector of them, since shading may load a vector of its words.
  static constexpr int passed_words(int S) { return std::max(S, L / 2); }
  // Sets `lanes` in vector k of a block's words, laid out as lanes_of() reads them.
  static void add_lanes(std::uint64_t* words, std::size_t k, std::uint32_t lanes) {
    words[k / kVectors] |= std::uint64_t{lanes} << ((k % kVectors) * L);
  }
  // Lanes of vector k of a block's coverage words, counting vectors across samples: bits
  // k * L .. k * L + L - 1 of the words laid end to end (little-endian), one load.
  static std::uint32_t lanes_of(const std::uint64_t* cov, std::size_t k) {
    static_assert(std::endian::native == std::endian::little);
    const unsigned char* bytes = reinterpret_cast<const unsigned char*>(cov);
    if constexpr (L == 16) {
      std::uint16_t w;
      std::memcpy(&w, bytes + 2 * k, sizeof w);
      return w;
    } else if constexpr (L == 8) {
      return bytes[k];
    } else {
      static_assert(L == 4);
      return (bytes[k / 2] >> (4 * (k % 2))) & kLaneBits;
    }
  }

  // The sample count from which the block walker tests a block's rows before its coverage: a
  // row of 8 or 16 samples is 8 vectors or more (AVX2), which outweighs the mispredicted exit
  // of a loop over the rows a block needs; at 4x the two cost about the same.
  static constexpr int kRowTestSamples = 8;
  // Vectors holding one lane per row of a block (lane r: row r; lanes past the block unused).
  static constexpr int kRowLaneVectors = (kBlockSize + L - 1) / L;
  // An edge's largest value over each block row's samples, from the block's corner: lane r holds
  // b * 256 * r plus the row's largest a * x + b * y (x, y: a sample's offset from the row's
  // corner), mod 2^32 like the coverage offsets.
  using RowMaxima = std::array<I, kRowLaneVectors>;
  static RowMaxima row_maxima(const Context& cx, std::int64_t a, std::int64_t b, int S) {
    std::int64_t m = std::numeric_limits<std::int64_t>::min();
    for (int s = 0; s < S; ++s) m = std::max(m, a * cx.soff[0][s] + b * cx.soff[1][s]);
    m += std::max<std::int64_t>(0, a * (kBlockSize - 1) * kSubpixel);
    alignas(64) std::int32_t lanes[kRowLaneVectors * L];
    for (int r = 0; r < kRowLaneVectors * L; ++r)
      lanes[r] = static_cast<std::int32_t>(static_cast<std::uint32_t>(m + b * kSubpixel * r));
    RowMaxima v;
    for (int j = 0; j < kRowLaneVectors; ++j) v[j] = I::load_aligned(lanes + j * L);
    return v;
  }
  // The rows [r0, r1) of a block, corner edge values c0..c2 (exact in int32: it fits32), outside
  // which no edge holds at any sample of a row: those rows' coverage is empty.
  static BoxRows rows_reached(std::uint32_t c0, std::uint32_t c1, std::uint32_t c2,
                              const RowMaxima (&row_max)[3]) {
    const I v0(static_cast<std::int32_t>(c0)), v1(static_cast<std::int32_t>(c1)),
        v2(static_cast<std::int32_t>(c2));
    std::uint32_t out = 0;
    for (int j = 0; j < kRowLaneVectors; ++j)
      out |= M::signs((v0 + row_max[0][j]) | (v1 + row_max[1][j]) | (v2 + row_max[2][j]))
             << (j * L);
    const std::uint32_t live = ~out & ((1u << kBlockSize) - 1);
    if (!live) return {0, 0};
    return {std::countr_zero(live), 32 - std::countl_zero(live)};
  }

  // Bit v set where vector v of a coverage word (lanes v * L .. v * L + L - 1) has a lane set.
  static std::uint32_t vectors_with_lanes(std::uint64_t m) { return M::nonzero_groups(m); }

  // The tile's depth bounds: the union of its blocks' (blocks outside the image hold the neutral
  // bounds +inf / -inf, see run()).
  static void refresh_tile_z(Context& cx) {
    std::tie(cx.tile_zmin, cx.tile_zmax) = HizSimd<A>::union_of(cx.sc.zmin, cx.sc.zmax, cx.blocks);
    cx.tile_z_loose = false;
  }

  // Coverage of a block of two or more samples, pixel-major, from the edge values c0..c2 at its
  // first pixel's corner, exact in int32 (the block passed fits32): bit g of the words in `cov`
  // (little-endian, end to end) set where lane g's sample is inside, as coverage32() does it. A
  // block row is 8 * S lanes in 8 * S / L vectors (roff: their lanes' offsets
  // from the row's corner); the values step down a row at a time (down).
  // Only the rows of `rows` are evaluated (the others come out 0). A kernel whose traits fix the
  // sample count has the rows inline; the others call one copy per instruction set that picks
  // the count, not one copy of every count per kernel.
  template <int kFixed>
  [[gnu::always_inline]] static void coverage32_rows(std::int32_t c0, std::int32_t c1,
                                                     std::int32_t c2,
                                                     const I (&roff)[3][kRowVectors],
                                                     const I (&down)[3], int S, BoxRows rows,
                                                     std::uint64_t* cov) {
    if constexpr (kFixed > 1)
      coverage32_rows_of<kFixed>(I(c0), I(c1), I(c2), roff, down, rows, cov);
    else
      coverage32_rows_any(c0, c1, c2, roff, down, S, rows, cov);
  }
  [[gnu::noinline]] static void coverage32_rows_any(std::int32_t c0, std::int32_t c1,
                                                    std::int32_t c2,
                                                    const I (&roff)[3][kRowVectors],
                                                    const I (&down)[3], int S, BoxRows rows,
                                                    std::uint64_t* cov) {
    switch (S) {
      case 2:
        return coverage32_rows_of<2>(I(c0), I(c1), I(c2), roff, down, rows, cov);
      case 4:
        return coverage32_rows_of<4>(I(c0), I(c1), I(c2), roff, down, rows, cov);
      case 8:
        return coverage32_rows_of<8>(I(c0), I(c1), I(c2), roff, down, rows, cov);
      default:
        return coverage32_rows_of<16>(I(c0), I(c1), I(c2), roff, down, rows, cov);
    }
  }
  // The same for a fixed count: every row of a block unrolls; the rows of a part of one loop.
  template <int S>
  [[gnu::always_inline]] static void coverage32_rows_of(I c0, I c1, I c2,
                                                        const I (&roff)[3][kRowVectors],
                                                        const I (&down)[3], BoxRows rows,
                                                        std::uint64_t* cov) {
    constexpr int kRowBits = kBlockSize * S;  // a row is S bytes
    const auto outside = [&](int j) {
      return std::uint64_t{M::signs((c0 + roff[0][j]) | (c1 + roff[1][j]) | (c2 + roff[2][j]))};
    };
    // Row r's bits, then the values stepped to the next row.
    const auto row = [&](int r) {
      if constexpr (kRowBits >= 64) {  // 8 and 16 samples: a row is whole words
        for (int w = 0; w < kRowBits / 64; ++w) {
          std::uint64_t out = 0;
          for (int i = 0; i < kVectors; ++i) out |= outside(w * kVectors + i) << (i * L);
          cov[r * (kRowBits / 64) + w] = ~out;
        }
      } else {
        std::uint64_t out = 0;
        for (int j = 0; j < kRowBits / L; ++j) out |= outside(j) << (j * L);
        if constexpr (S == 4) {  // a row is one 32-bit half of a word
          const auto half = static_cast<std::uint32_t>(~out);
          std::memcpy(reinterpret_cast<unsigned char*>(cov) + r * 4, &half, sizeof half);
        } else {
          constexpr std::uint64_t kRowMask = (std::uint64_t{1} << kRowBits) - 1;
          cov[r * kRowBits / 64] |= (~out & kRowMask) << (r * kRowBits % 64);
        }
      }
      c0 += down[0];
      c1 += down[1];
      c2 += down[2];
    };
    if (rows.r0 == 0 && rows.r1 == kBlockSize) {  // a fixed trip count
      if constexpr (kRowBits < 64 && S != 4) std::fill_n(cov, S, std::uint64_t{0});
      for (int r = 0; r < kBlockSize; ++r) row(r);
      return;
    }
    std::fill_n(cov, S, std::uint64_t{0});
    const I r0(rows.r0);
    c0 += down[0] * r0;
    c1 += down[1] * r0;
    c2 += down[2] * r0;
    for (int r = rows.r0; r < rows.r1; ++r) row(r);
  }

  // Coverage of a block whose edge values could leave int32 (edges longer than about 2048 px), in
  // double lanes: every value is an integer below 2^50 in magnitude (the edge budget of
  // front/fixed_point.hpp is 2^49, a block's offsets 2^36), so each conversion and sum is exact,
  // and the sign bit is set exactly where a value is negative (an exact zero sum is +0). eorg:
  // the edge values at the block's first pixel corner; doff from build_doff(). Bits as
  // coverage32_rows() gives them. The scalar int64 loop this replaces took a quarter of
  // random-large's kernel instructions (callgrind, AVX2).
  static void coverage_f64(const std::int64_t (&eorg)[3], const std::int64_t (&b)[3], int S,
                           const D (&doff)[3][kDOffsets], std::uint64_t* cov) {
    // One sample: the 64 pixel centres (doff holds each pixel's offset, centre included);
    // more: a block row of lanes at a time.
    const int row_dvectors = S == 1 ? kDVectors : kBlockSize * S / kDLanes;
    const int rows = S == 1 ? 1 : kBlockSize;
    constexpr int kPerWord = 64 / kDLanes;
    std::uint64_t outside = 0;
    int k = 0;
    for (int r = 0; r < rows; ++r) {
      const std::int64_t down = static_cast<std::int64_t>(r) * kSubpixel;
      const D b0(static_cast<double>(eorg[0] + b[0] * down)),
          b1(static_cast<double>(eorg[1] + b[1] * down)),
          b2(static_cast<double>(eorg[2] + b[2] * down));
      for (int w = 0; w < row_dvectors; ++w, ++k) {
        outside |=
            std::uint64_t{M::signs((b0 + doff[0][w]) | (b1 + doff[1][w]) | (b2 + doff[2][w]))}
            << ((k % kPerWord) * kDLanes);
        if (k % kPerWord == kPerWord - 1) {
          cov[k / kPerWord] = ~outside;
          outside = 0;
        }
      }
    }
  }
  // doff[e][w]: edge e's offset, exact, from a block's first pixel corner to the lanes of double
  // vector w: of the block (one sample, pixel centres), or of a block row (pixel-major samples).
  static void build_doff(const std::int64_t (&a)[3], const std::int64_t (&b)[3], const Context& cx,
                         int S, D (&doff)[3][kDOffsets]) {
    const int count = S == 1 ? kDVectors : kBlockSize * S / kDLanes;
    for (int w = 0; w < count; ++w) {
      alignas(64) double off[3][kDLanes];
      for (int l = 0; l < kDLanes; ++l) {
        const int g = w * kDLanes + l;
        // The lane's position from the corner, in 16.8.
        const std::int64_t x =
            S == 1 ? (g % kBlockSize) * kSubpixel + kHalf : (g / S) * kSubpixel + cx.soff[0][g % S];
        const std::int64_t y = S == 1 ? (g / kBlockSize) * kSubpixel + kHalf : cx.soff[1][g % S];
        for (int e = 0; e < 3; ++e) off[e][l] = static_cast<double>(a[e] * x + b[e] * y);
      }
      for (int e = 0; e < 3; ++e) doff[e][w] = D::load_aligned(off[e]);
    }
  }

  // The start of a tile that draws over the previous frame: its samples inside the image from
  // the target's kept ones, in the order resolve_tile() writes them back (after the clear, so
  // that the pixels past the image's edge hold the clear values as always).
  static void load_tile(Context& cx) {
    const TileFrame& f = cx.f;
    const TileRect& tile = cx.tile;
    const int S = f.samples;
    for (int y = 0; y < tile.height; ++y) {
      for (int x = 0; x < tile.width; ++x) {
        const int blk = (y / kBlockSize) * cx.side + x / kBlockSize;
        const int p = (y % kBlockSize) * kBlockSize + x % kBlockSize;
        const std::size_t in = (static_cast<std::size_t>(tile.y0 + y) * f.width + tile.x0 + x) * S;
        const std::size_t din =
            static_cast<std::size_t>(tile.y0 + y) * f.depth_stride + std::size_t(tile.x0 + x) * S;
        for (int s = 0; s < S; ++s) {
          const std::size_t out = (static_cast<std::size_t>(blk) * kBlockPixels + p) * S + s;
          if (f.load_color) cx.sc.color[out] = std::bit_cast<std::uint32_t>(f.sample_color[in + s]);
          if (f.load_depth) cx.sc.depth[out] = f.sample_depth[din + s];
        }
      }
    }
  }

  // The end of a tile: its hierarchical z, its image and the per-sample outputs it is asked for.
  static void resolve_tile(Context& cx) {
    const TileFrame& f = cx.f;
    const TileRect& tile = cx.tile;
    const int S = f.samples;
    take_planes(cx);
    if (f.hiz_min) store_hiz(cx);
    if (f.keep_color) resolve_color(cx);
    if (f.sample_color || f.sample_depth) {
      for (int y = 0; y < tile.height; ++y) {
        for (int x = 0; x < tile.width; ++x) {
          const int blk = (y / kBlockSize) * cx.side + x / kBlockSize;
          const int p = (y % kBlockSize) * kBlockSize + x % kBlockSize;
          const std::size_t out =
              (static_cast<std::size_t>(tile.y0 + y) * f.width + tile.x0 + x) * S;
          const std::size_t dout =
              static_cast<std::size_t>(tile.y0 + y) * f.depth_stride + std::size_t(tile.x0 + x) * S;
          for (int s = 0; s < S; ++s) {
            const std::size_t in = (static_cast<std::size_t>(blk) * kBlockPixels + p) * S + s;
            // (Sample colour is asked for only from a tile that keeps colour.)
            if (f.sample_color) f.sample_color[out + s] = std::bit_cast<Rgba8>(cx.sc.color[in]);
            if (f.sample_depth)
              f.sample_depth[dout + s] = f.keep_depth ? cx.sc.depth[in] : f.clear_depth;
          }
        }
      }
    }
  }

  // Exact depth bounds of each of the tile's blocks inside the image, into the frame's
  // hierarchical z. The samples are in cache; the bounds the triangle loop keeps are only
  // conservative between the points where it makes them exact.
  static void store_hiz(Context& cx) {
    const TileFrame& f = cx.f;
    const TileRect& tile = cx.tile;
    const int stride = f.hiz_stride();
    for (int by = 0; by * kBlockSize < tile.height; ++by) {
      for (int bx = 0; bx * kBlockSize < tile.width; ++bx) {
        const int blk = by * cx.side + bx;
        const std::size_t out = static_cast<std::size_t>(tile.y0 / kBlockSize + by) * stride +
                                static_cast<std::size_t>(tile.x0 / kBlockSize + bx);
        // A frame without depth holds only the clear depth.
        const auto [lo, hi] = f.keep_depth ? exact_block_bounds(cx, blk)
                                           : std::pair<float, float>{f.clear_depth, f.clear_depth};
        f.hiz_min[out] = lo;
        f.hiz_max[out] = hi;
      }
    }
  }

  // Points cx.cover at the pixels of each block that draw `draw` may cover: the image's, or, where
  // its clip rectangle cuts the tile, those inside the rectangle too (made once per rectangle).
  static void clip_coverage(Context& cx, std::uint32_t draw) {
    const DrawState& ds = cx.f.states[draw];
    cx.cover = cx.valid;
    cx.cover_blocks = cx.valid_blocks;
    if (!ds.viewport && !ds.scissor) return;
    const PixelRect r = front::DrawArea::of(ds, cx.f.width, cx.f.height).in_target();
    const TileRect& tile = cx.tile;
    if (r.x <= tile.x0 && r.y <= tile.y0 && r.x + r.width >= tile.x0 + tile.width &&
        r.y + r.height >= tile.y0 + tile.height)
      return;
    cx.cover = cx.sc.clipped;
    if (cx.clipped_made && cx.clipped_rect == r) {
      cx.cover_blocks = cx.clipped_blocks;
      return;
    }
    for (int blk = 0; blk < cx.blocks; ++blk) {
      const int px0 = tile.x0 + (blk % cx.side) * kBlockSize;
      const int py0 = tile.y0 + (blk / cx.side) * kBlockSize;
      const int c0 = std::clamp(r.x - px0, 0, kBlockSize);
      const int c1 = std::clamp(r.x + r.width - px0, 0, kBlockSize);
      const int r0 = std::clamp(r.y - py0, 0, kBlockSize);
      const int r1 = std::clamp(r.y + r.height - py0, 0, kBlockSize);
      const std::uint64_t row = c0 < c1 ? ((std::uint64_t{1} << c1) - (std::uint64_t{1} << c0)) : 0;
      std::uint64_t m = 0;
      for (int y = r0; y < r1; ++y) m |= row << (y * kBlockSize);
      cx.sc.clipped[blk] = cx.valid[blk] & m;
    }
    cx.clipped_blocks = cx.cover_blocks = nonempty_blocks(cx, cx.sc.clipped);
    cx.clipped_rect = r;
    cx.clipped_made = true;
  }

  // The smallest block rectangle outside which every block of `cover` is empty; in a tile's
  // image part and clip rectangle the nonempty blocks fill it.
  static typename Context::BlockRect nonempty_blocks(const Context& cx,
                                                     const std::uint64_t* cover) {
    typename Context::BlockRect r{cx.side, 0, cx.side, 0};
    for (int blk = 0; blk < cx.blocks; ++blk) {
      if (!cover[blk]) continue;
      const int bx = blk % cx.side, by = blk / cx.side;
      r = {std::min(r.x0, bx), std::max(r.x1, bx + 1), std::min(r.y0, by), std::max(r.y1, by + 1)};
    }
    return r;
  }

  // Whether t may hold a whole block, the only case where the plane walker gains. Its box, W × H
  // pixels, must hold one: (W - 8)(H - 8) >= 64, the square a right triangle with legs W and H
  // holds. And each edge's value must rise across the triangle (to twice its area, at the
  // opposite vertex) by at least its rise across a block, (|a| + |b|) · kBlockSpan.
  static bool may_cover_a_block(const front::TriangleSetup& t) {
    const int w = t.bx1 - t.bx0 - kBlockSize, h = t.by1 - t.by0 - kBlockSize;
    if (w <= 0 || h <= 0 || w * h < kBlockPixels) return false;
    // (x0, y0) is the snapped first vertex: whole 16.8 units.
    const auto x = static_cast<std::int64_t>(t.x0 * kSubpixel);
    const auto y = static_cast<std::int64_t>(t.y0 * kSubpixel);
    const std::int64_t twice_area = std::max({t.edge[0](x, y), t.edge[1](x, y), t.edge[2](x, y)});
    for (const front::EdgeFunction& e : t.edge)
      if ((std::abs(e.a) + std::abs(e.b)) * kBlockSpan > twice_area) return false;
    return true;
  }

  // Block blk's samples become triangle t's depth plane, evaluated later (take_plane()).
  static void record_plane(Context& cx, int blk, const front::TriangleSetup& t) {
    cx.sc.plane[blk] = {t.z, t.x0, t.y0, t.z_min, t.z_max};
    cx.planes += 1 - cx.sc.plane_pending[blk];
    cx.sc.plane_pending[blk] = 1;
  }
  // Writes the samples of every block whose plane is pending.
  static void take_planes(Context& cx) {
    for (int blk = 0; blk < cx.blocks && cx.planes; ++blk)
      if (cx.sc.plane_pending[blk]) take_plane(cx, blk);
  }

  // Writes the samples of a block whose plane is pending, as triangle_impl()'s depth loop writes
  // a covered and accepted block: the same sample positions and operations, so the same bits.
  [[gnu::noinline]] static void take_plane(Context& cx, int blk) {
    cx.sc.plane_pending[blk] = 0;
    --cx.planes;
    const TileScratch::DepthPlane& p = cx.sc.plane[blk];
    const int S = cx.f.samples;
    const F fx_blk(static_cast<float>(cx.tile.x0 + (blk % cx.side) * kBlockSize));
    const F fy_row(static_cast<float>(cx.tile.y0 + (blk / cx.side) * kBlockSize));
    const DepthLanes depth(p.z, p.x0, p.y0, p.lo, p.hi);
    float* d = cx.sc.depth.get() + static_cast<std::size_t>(blk) * S * kBlockPixels;
    for (int k = 0; k < S * kVectors; ++k)
      depth.at(fx_blk + cx.sx[k], fy_row + cx.sy[k]).store_aligned(d + k * L);
  }

  // The exact bounds of the depths a block of the tile holds (a block with image pixels; no
  // plane pending: the walkers take a block's plane before they write it, resolve_tile() all).
  static std::pair<float, float> exact_block_bounds(const Context& cx, int blk) {
    const int S = cx.f.samples;
    const float* d = cx.sc.depth.get() + static_cast<std::size_t>(blk) * S * kBlockPixels;
    const std::uint64_t valid = cx.valid[blk];
    if (valid == ~std::uint64_t{0}) return HizSimd<A>::bounds_of(d, S * kBlockPixels);
    // A block cut by the image's right or bottom edge.
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (int p = 0; p < kBlockPixels; ++p)
      if ((valid >> p) & 1)
        for (int s = 0; s < S; ++s) {
          lo = std::min(lo, d[p * S + s]);
          hi = std::max(hi, d[p * S + s]);
        }
    return {lo, hi};
  }

  // The box filter of every pixel, into the image (resolve/resolve_simd.hpp).
  static void resolve_color(Context& cx) {
    const TileFrame& f = cx.f;
    resolve::ResolveSimd<A>::box_tile(cx.sc.color.get(), cx.side, f.samples, cx.tile,
                                      cx.sc.resolved, f.image, f.image_stride, f.image_bgra);
  }

  // Nanoseconds from t0 until now, for TileStats::resolve_ns.
  static std::uint64_t ns_since(std::chrono::steady_clock::time_point t0) {
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0)
            .count());
  }

  /// What the walker needs of a block's lanes for a sample count (Context::sx .. pick), made
  /// once per count: lane g = k * L + l of vector k holds sample g % S of pixel g / S.
  struct LaneTables {
    F sx[kMaxSamples * kVectors], sy[kMaxSamples * kVectors];
    I rx[kRowVectors], ry[kRowVectors];
    I pick[kMaxSamples];
  };
  static const LaneTables& lane_tables(int S) {
    static const std::array<LaneTables, 5> tables = [] {
      std::array<LaneTables, 5> t{};
      for (int k2 = 0; k2 < 5; ++k2) build_lane_tables(1 << k2, t[k2]);
      return t;
    }();
    return tables[std::countr_zero(static_cast<unsigned>(S))];
  }
  static void build_lane_tables(int S, LaneTables& t) {
    const std::span<const SampleOffset> pattern = sample_pattern(S);
    if (pattern.size() != static_cast<std::size_t>(S)) return;  // no such pattern (2x)
    float ox[kMaxSamples], oy[kMaxSamples];
    std::int64_t sx16[kMaxSamples], sy16[kMaxSamples];
    for (int s = 0; s < S; ++s) {
      // The reference's sample position is px + 0.5 + dx / 16; every term and sum is exact.
      ox[s] = 0.5f + static_cast<float>(pattern[s].dx) * (1.0f / 16.0f);
      oy[s] = 0.5f + static_cast<float>(pattern[s].dy) * (1.0f / 16.0f);
      sx16[s] = kHalf + pattern[s].dx * kSampleOffsetScale;
      sy16[s] = kHalf + pattern[s].dy * kSampleOffsetScale;
    }
    for (int k = 0; k < S * kVectors; ++k) {
      alignas(64) float xs[L], ys[L];
      for (int l = 0; l < L; ++l) {
        const int g = k * L + l, p = g / S, smp = g % S;
        xs[l] = static_cast<float>(p % kBlockSize) + ox[smp];
        ys[l] = static_cast<float>(p / kBlockSize) + oy[smp];
      }
      t.sx[k] = F::load_aligned(xs);
      t.sy[k] = F::load_aligned(ys);
    }
    for (int j = 0; S > 1 && j < kBlockSize * S / L; ++j) {
      alignas(64) std::int32_t xs[L], ys[L];
      for (int l = 0; l < L; ++l) {
        const int g = j * L + l;
        xs[l] = static_cast<std::int32_t>((g / S) * kSubpixel + sx16[g % S]);
        ys[l] = static_cast<std::int32_t>(sy16[g % S]);
      }
      t.rx[j] = I::load_aligned(xs);
      t.ry[j] = I::load_aligned(ys);
    }
    for (int r = 0; r < S; ++r) {
      alignas(64) std::int32_t lanes[L];
      for (int l = 0; l < L; ++l) lanes[l] = (r * L + l) / S;
      t.pick[r] = I::load_aligned(lanes);
    }
  }

  static void run(const TileFrame& f, const TileRect& tile, std::span<const BinRun> bin,
                  TileScratch& sc, TileStats& st) {
    // A tile no triangle reaches that loads nothing holds only the clear values: they go to the
    // outputs directly, without clearing and resolving its samples. (Such a "tile" may be a row
    // of empty tiles, up to kMaxTileSize wide: the tile stage merges them.)
    if (bin.empty() && !f.load_color && !f.load_depth) {
      const auto r0 = std::chrono::steady_clock::now();
      resolve::write_clear_tile(f, tile);
      st.resolve_ns += ns_since(r0);
      return;
    }
    Context cx{f,
               tile,
               sc,
               st,
               sample_pattern(f.samples),
               f.tile_size / kBlockSize,
               (f.tile_size / kBlockSize) * (f.tile_size / kBlockSize),
               {},
               f.clear_depth,
               f.clear_depth,
               false,
               {},
               {},
               {},
               {},
               {},
               {},
               {},
               {},
               {},
               {}};
    for (int v = 0; v < kVectors; ++v) {
      cx.col[v] = lane_col(v);
      cx.row[v] = lane_row(v);
      cx.ln.colf[v] = xsimd::to_float(cx.col[v]);
      cx.ln.rowf[v] = xsimd::to_float(cx.row[v]);
    }
    for (int s = 0; s < f.samples; ++s) {
      const SampleOffset o = cx.pattern[s];
      // The reference's sample position is px + 0.5 + dx / 16; every term and sum is exact.
      cx.ln.oxs[s] = 0.5f + static_cast<float>(o.dx) * (1.0f / 16.0f);
      cx.ln.oys[s] = 0.5f + static_cast<float>(o.dy) * (1.0f / 16.0f);
      cx.ln.ox[s] = F(cx.ln.oxs[s]);
      cx.ln.oy[s] = F(cx.ln.oys[s]);
      cx.soff[0][s] = kHalf + o.dx * kSampleOffsetScale;
      cx.soff[1][s] = kHalf + o.dy * kSampleOffsetScale;
    }
    const LaneTables& lt = lane_tables(f.samples);
    cx.sx = lt.sx;
    cx.sy = lt.sy;
    cx.rx = lt.rx;
    cx.ry = lt.ry;
    cx.pick = lt.pick;
    cx.queue.color_base = sc.color.get();
    // Clear the buffers the frame uses, and the tile's hierarchical z.
    const std::size_t n = static_cast<std::size_t>(cx.blocks) * f.samples * kBlockPixels;
    if (f.keep_color) {
      const I cc(Sh::bits_of(f.clear_color));
      for (std::size_t i = 0; i < n; i += L)
        cc.store_aligned(reinterpret_cast<std::int32_t*>(sc.color.get() + i));
    }
    if (f.keep_depth) {
      const F cd(f.clear_depth);
      for (std::size_t i = 0; i < n; i += L) cd.store_aligned(sc.depth.get() + i);
    }
    for (int blk = 0; blk < cx.blocks; ++blk) {
      sc.zmin[blk] = sc.zmax[blk] = f.clear_depth;
      sc.hiz_written[blk] = 0;
      const int bx = blk % cx.side, by = blk / cx.side;
      const int cols = std::clamp(tile.width - bx * kBlockSize, 0, kBlockSize);
      const int rows = std::clamp(tile.height - by * kBlockSize, 0, kBlockSize);
      std::uint64_t m = 0;
      for (int r = 0; r < rows; ++r) m |= ((std::uint64_t{1} << cols) - 1) << (r * kBlockSize);
      cx.valid[blk] = m;
      if (!m) {  // neutral bounds: a block outside the image never widens the tile's
        sc.zmin[blk] = std::numeric_limits<float>::infinity();
        sc.zmax[blk] = -std::numeric_limits<float>::infinity();
      }
    }
    cx.valid_blocks = nonempty_blocks(cx, cx.valid);
    if (f.load_color || f.load_depth) load_tile(cx);
    if (f.load_depth) {
      // Loaded depths: each block's bounds exact from them, the tile's the bounds of those.
      cx.tile_zmin = std::numeric_limits<float>::infinity();
      cx.tile_zmax = -std::numeric_limits<float>::infinity();
      for (int blk = 0; blk < cx.blocks; ++blk) {
        if (!cx.valid[blk]) continue;
        std::tie(sc.zmin[blk], sc.zmax[blk]) = exact_block_bounds(cx, blk);
        cx.tile_zmin = std::min(cx.tile_zmin, sc.zmin[blk]);
        cx.tile_zmax = std::max(cx.tile_zmax, sc.zmax[blk]);
      }
    }
    for (std::size_t r = 0; r < bin.size();) {
      const int order = f.occluders_nearest_first ? occluder_order(f, bin[r]) : 0;
      if (order == 0) {
        draw_run(cx, bin[r++]);
        continue;
      }
      std::size_t e = r + 1;
      while (e < bin.size() && occluder_order(f, bin[e]) == order) ++e;
      draw_nearest_first(cx, bin.subspan(r, e - r), order);
      r = e;
    }
    const auto r0 = std::chrono::steady_clock::now();
    resolve_tile(cx);
    st.resolve_ns += ns_since(r0);
  }

  // Draws one bin run's triangles in submission order.
  static void draw_run(Context& cx, const BinRun& run) {
    const TileFrame& f = cx.f;
    const std::span<const std::uint32_t> idx = run.indices;
    cx.ln.planes = run.planes;
    const bool mixed = run.draw == BinRun::kMixedDraws;
    DrawKernels kernels = mixed ? DrawKernels{} : pick(f, run.draw);
    if (!mixed) {
      clip_coverage(cx, run.draw);
      // Only draws that use planes meet pending ones. (A run of mixed draws, the painter's,
      // writes no depth: it neither leaves nor meets one.)
      if (cx.planes && !uses_planes(f.states[run.draw])) take_planes(cx);
    }
    for (std::size_t k = 0; k < idx.size(); ++k) {
      // A bin's triangles lie far apart in the setup arrays (a tile takes a sparse subset),
      // so each is a cache miss: fetch the setup kPrefetchAhead triangles ahead while this one
      // is drawn (the kernels read its first kPrefetchLines lines).
      if (k + kPrefetchAhead < idx.size()) prefetch_setup(run.tris[idx[k + kPrefetchAhead]]);
      // The next triangle's setup was prefetched an iteration ago: if it has planes (colour
      // or varyings), fetch their first kColorPlanes, which lie elsewhere (the chunk's plane
      // array). mosaic-bench features/interpolated/4x (every triangle interpolated): 62.7 and
      // 63.3 ms without, 58.9 and 59.4 ms with; flat random-small unchanged.
      if (k + 1 < idx.size()) {
        const front::TriangleSetup& next = run.tris[idx[k + 1]];
        if (!front::is_flat(next)) {
          const char* p = reinterpret_cast<const char*>(run.planes + next.planes_base);
          __builtin_prefetch(p);
          __builtin_prefetch(p + kColorPlaneBytes - 1);  // they may straddle two lines
        }
      }
      const front::TriangleSetup& t = run.tris[idx[k]];
      if (mixed) {
        if (cx.queue.n && cx.queue.shading != &f.shading[t.draw()]) Sh::flush(cx.queue);
        kernels = pick(f, t.draw());
        clip_coverage(cx, t.draw());
      }
      draw_triangle(cx, kernels, t);
    }
    Sh::flush(cx.queue);
  }

  // Fetches the lines of a triangle's setup that the kernels read.
  static void prefetch_setup(const front::TriangleSetup& t) {
    const char* p = reinterpret_cast<const char*>(&t);
    for (int l = 0; l < kPrefetchLines; ++l) __builtin_prefetch(p + l * kCacheLine);
  }

  // Whether a run's triangles may be drawn nearest first (Frame::occluders_nearest_first): +1
  // for an occluder draw testing less or less-equal (the smallest depth is nearest), -1 for
  // greater or greater-equal, 0 for any other run. Runs of one sign leave each sample the
  // nearest of its depths in any order.
  static int occluder_order(const TileFrame& f, const BinRun& run) {
    if (run.draw == BinRun::kMixedDraws) return 0;
    const DrawState& ds = f.states[run.draw];
    if (ds.color_write || !ds.depth_write) return 0;
    switch (ds.depth_test) {
      case DepthTest::kLess:
      case DepthTest::kLessEqual:
        return 1;
      case DepthTest::kGreater:
      case DepthTest::kGreaterEqual:
        return -1;
      case DepthTest::kAlways:
        break;
    }
    return 0;
  }

  // Whether the runs' triangles overlap enough in the tile to pay for sorting them (their areas,
  // each at most its box in the tile, add up to kSortOverdraw tiles), and none may store -0.
  static bool worth_sorting(const Context& cx, std::span<const BinRun> runs) {
    const TileRect& tile = cx.tile;
    double covered_px = 0;
    for (const BinRun& run : runs) {
      const std::span<const std::uint32_t> idx = run.indices;
      for (std::size_t k = 0; k < idx.size(); ++k) {
        if (k + kPrefetchAhead < idx.size()) prefetch_setup(run.tris[idx[k + kPrefetchAhead]]);
        const front::TriangleSetup& t = run.tris[idx[k]];
        // A depth range reaching down to -0 may store -0 or +0 at a zero depth by the order.
        if (std::signbit(t.z_min)) return false;
        covered_px += std::min(area_px(t), box_px_in(t, tile));
      }
    }
    return covered_px >= kSortOverdraw * static_cast<double>(tile.width) * tile.height;
  }

  // Draws the triangles of consecutive occluder runs of one order sign, nearest first: sorted by
  // their nearest depth, ties in submission order, so the order is the same at any thread count.
  // Runs not worth_sorting() are drawn in submission order.
  static void draw_nearest_first(Context& cx, std::span<const BinRun> runs, int order) {
    if (!worth_sorting(cx, runs)) {
      for (const BinRun& run : runs) draw_run(cx, run);
      return;
    }
    std::vector<TileScratch::Occluder>& items = cx.sc.occluders;
    items.clear();
    for (std::uint32_t r = 0; r < runs.size(); ++r) {
      const std::span<const std::uint32_t> idx = runs[r].indices;
      for (std::uint32_t k = 0; k < idx.size(); ++k) {
        const front::TriangleSetup& t = runs[r].tris[idx[k]];
        const float key = order > 0 ? t.z_min : -t.z_max;
        items.push_back({std::isnan(key) ? std::numeric_limits<float>::infinity() : key, r, k});
      }
    }
    std::sort(items.begin(), items.end(), [](const auto& p, const auto& q) {
      return p.key < q.key ||
             (p.key == q.key && (p.run < q.run || (p.run == q.run && p.index < q.index)));
    });
    std::uint32_t draw = BinRun::kMixedDraws;
    DrawKernels kernels;
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (i + kPrefetchAhead < items.size()) {
        const TileScratch::Occluder& n = items[i + kPrefetchAhead];
        prefetch_setup(runs[n.run].tris[runs[n.run].indices[n.index]]);
      }
      const BinRun& run = runs[items[i].run];
      if (run.draw != draw) {
        draw = run.draw;
        kernels = pick(cx.f, draw);
        clip_coverage(cx, draw);
      }
      cx.ln.planes = run.planes;
      const front::TriangleSetup& t = run.tris[run.indices[items[i].index]];
      draw_triangle(cx, kernels, t);
    }
  }

  static constexpr std::int64_t floor_div(std::int64_t n, std::int64_t d) {  // d > 0
    return n >= 0 ? n / d : -((-n + d - 1) / d);
  }
  static constexpr std::int64_t ceil_div(std::int64_t n, std::int64_t d) {  // d > 0
    return n >= 0 ? (n + d - 1) / d : -((-n) / d);
  }

  // A triangle's area in px²: its three edge functions sum to twice the area in 1/65536 px²
  // everywhere (less one per excluded edge).
  static double area_px(const front::TriangleSetup& t) {
    const std::int64_t twice = t.edge[0].c + t.edge[1].c + t.edge[2].c;
    return static_cast<double>(twice) / (2.0 * kSubpixel * kSubpixel);
  }
  // The pixels of a triangle's box inside the tile.
  static double box_px_in(const front::TriangleSetup& t, const TileRect& tile) {
    const int w = std::min(t.bx1, tile.x0 + tile.width) - std::max(t.bx0, tile.x0);
    const int h = std::min(t.by1, tile.y0 + tile.height) - std::max(t.by0, tile.y0);
    return w > 0 && h > 0 ? static_cast<double>(w) * h : 0.0;
  }

  static constexpr std::int64_t kSubpixel = 256;  ///< one pixel in 16.8 units
  /// Triangles prefetched ahead: one is ~2000 instructions of work, enough to hide a miss to
  /// L3. Measured (random-small, depth-only 1x, AVX-512, raster stage): no prefetch 32.9 ms, 1 or 2
  /// ahead 24.5 ms, 6 ahead 31 ms.
  static constexpr std::size_t kPrefetchAhead = 2;
  /// Occluders are sorted nearest first when their areas in the tile add up to this many times
  /// the tile: below it, the hierarchical z rejects too little to pay for the sort.
  static constexpr double kSortOverdraw = 2.0;
  static constexpr int kCacheLine = 64;
  /// Lines of a TriangleSetup the kernels read: edges, anchor, box, depth plane, colour, draw and
  /// planes_base, its last field (the setup is line-aligned). The draw's index was once on a third
  /// line, read (for the draw's state) before anything else: a miss per triangle.
  static constexpr int kPrefetchLines =
      static_cast<int>((offsetof(front::TriangleSetup, planes_base) +
                        sizeof(front::TriangleSetup::planes_base) + kCacheLine - 1) /
                       kCacheLine);
  /// Bytes of an interpolated triangle's q and colour planes, prefetched with the next triangle.
  static constexpr int kColorPlaneBytes =
      static_cast<int>(front::kColorPlanes * sizeof(front::Plane));
  /// Boxes of at most this many pixels, in one block, skip the block walker (few_pixels()).
  static constexpr int kPixelPathMax = 4;
  static constexpr int kBlockShift = std::countr_zero(static_cast<unsigned>(kBlockSize));
  static_assert(kBlockSize == 1 << kBlockShift);
  static constexpr std::uint64_t kWholeBlock = ~std::uint64_t{0};  ///< every pixel of a block
  static constexpr std::int64_t kHalf = 128;  ///< half a pixel: the pixel centre
  static constexpr std::int64_t kBlockSpan = kBlockSize * kSubpixel;  ///< a block's width in 16.8
};

}  // namespace mosaic::raster
