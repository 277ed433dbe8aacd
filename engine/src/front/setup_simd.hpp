// front/setup_simd.hpp — the front end with several triangles at once in the double lanes of a
// SIMD register, written once and compiled per instruction set from simd/front_end.cpp, each with
// its own compiler flags; dispatch::front_end() picks one at run time.
//
// Takes and gives exactly what run_front_end() (front/front_end.hpp) does, bit for bit: same
// TriangleSetups in the same order, same counters. The lanes do the common case: a triangle whose
// vertices are finite and inside every clip plane, with a positive W. They repeat the scalar
// code's operations in the scalar code's order (IEEE add, sub, mul and div are correctly rounded,
// and the build disables FMA contraction), so each lane gets the scalar bits. A triangle any lane
// finds uncommon (non-finite, needing clipping, on the eye point) is redone by the scalar front
// end (TriangleFrontEnd) in its place in submission order. A shader draw's varying planes are
// set up in lanes too, as setup_varyings() sets them up.
//
// It also fills the vertex stage's cache (front/vertex_stage.hpp) with the same per-vertex
// operations in lanes of vertices; a draw with a cache reads its triangles' corners from it
// already projected. Varyings are fetched only for the triangles that are drawn. Such a draw is
// first pre-culled in float lanes (precull()): the triangles of a distant mesh, which setup()
// would cull for covering no sample, are counted from their corners' records without a set-up.
//
// The snapped 16.8 coordinates, areas and edge functions are integers below 2^50, computed in
// double lanes: exact, as in the scalar int64 code (fixed_point.hpp has the bit budget).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <utility>
#include <vector>
#include <xsimd/xsimd.hpp>

#include "front/front_end.hpp"
#include "front/sample_cull.hpp"
#include "simd/mask.hpp"
#include "simd/records.hpp"

namespace mosaic::front {

template <class A>
struct FrontEndSimd {
  using D = xsimd::batch<double, A>;
  using B = xsimd::batch_bool<double, A>;
  using M = simd::Mask<A>;
  static constexpr int N = static_cast<int>(D::size);  ///< triangles per batch
  static constexpr std::uint32_t kAllLanes = (1u << N) - 1;

  /// A batch's vertices, structure of arrays: [corner][lane].
  struct Vertices {
    alignas(64) double X[3][N], Y[3][N], Z[3][N], W[3][N];
    std::uint32_t nonfinite = 0;  ///< lanes with a NaN or infinite coordinate
    /// X, Y, Z, W hold Draw::positions as they are: setup() does the rest of VertexFetch (the
    /// non-finite test and the viewport map) in lanes.
    bool raw = false;
    /// X, Y, Z, W hold the corners' projections from the vertex stage instead (px, py, z, q of
    /// ProjectedVertex), and the lanes' clip classes are already known.
    bool cached = false;
    std::uint32_t cached_scalar = 0, cached_outside = 0;
    /// Corner k of lane l is vertex vertex[k][l]: its varyings are fetched by it.
    alignas(64) std::int64_t vertex[3][N];
    alignas(64) double color[3][kColorChannels][N];  ///< vertex colours, submitted corners
    /// With `cached`, the corners' colours as the vertex stage packs them (RGBA8, red lowest):
    /// unpacked into `color` by unpack_colors() only for a batch that draws a lane.
    alignas(64) std::uint64_t rgba[3][N];
  };

  /// One vertex per lane after VertexFetch: the clip tests, the perspective divide and snapping.
  struct Projection {
    D px, py, z, q;  ///< as front/vertex_stage.hpp keeps them
    B nonfinite;     ///< a raw lane with a NaN or infinite coordinate
    B clip;          ///< vertex_code::kClip
    B beyond[6];     ///< vertex_code's clip planes, in its bit order
  };

  /// A lane's plane before rounding to float.
  struct PlaneLanes {
    alignas(64) double base[N], ddx[N], ddy[N];
  };

  /// What the lanes computed, for the scalar store into TriangleSetup.
  struct Results {
    /// What became of each lane's triangle, one bit per lane, in the order the scalar code tests:
    /// left to the scalar code, culled by clipping or an empty box (outside), by its facing, of
    /// zero area, or for a box that holds no sample position; the lanes in none of these are drawn.
    std::uint32_t scalar, outside, face, degenerate, no_sample;
    std::uint32_t interpolated;  ///< drawn with differing vertex colours: the planes below are set
    /// Lanes whose q plane and colour or varying planes all convert to finite floats.
    std::uint32_t planes_finite;
    std::uint32_t back;  ///< winding not DrawState::front_face (TriangleSetup::back_face())
    alignas(64) double ea[3][N], eb[3][N], ec[3][N];  ///< edge coefficients (integers)
    alignas(64) double bx0[N], by0[N], bx1[N], by1[N];
    alignas(64) double x0[N], y0[N], z_min[N], z_max[N];
    PlaneLanes z, q;
    PlaneLanes c_q[kColorChannels];
    // What the planes of vertex colours and varyings need of the geometry (oriented corners),
    // and 1/W normalised by the largest corner's.
    alignas(64) double xs[3][N], ys[3][N], area_px2[N], qo[3][N], qn[3][N];
    alignas(64) double ccw_lanes[N];  ///< 1 where corners 1 and 2 swapped to orient them, else 0

    // A shader draw's varyings: the drawn lanes' (oriented corners, corner 0 first), and their
    // planes, varying k·q.
    alignas(64) double vary[3][kMaxVaryings][N];
    PlaneLanes vary_q[kMaxVaryings];
  };

  static D load(const double* p) { return D::load_aligned(p); }
  /// The lanes f(0) .. f(N - 1), put together in registers.
  template <class Fn, std::size_t... l>
  [[gnu::always_inline]] static D lanes_of(Fn f, std::index_sequence<l...>) {
    return D({f(static_cast<int>(l))...});
  }

  /// std::min({a, b, c}): the first smallest, so a signed zero comes out as the scalar's does.
  static D min3(D a, D b, D c) {
    const D m = xsimd::select(b < a, b, a);
    return xsimd::select(c < m, c, m);
  }
  /// std::max({a, b, c}): the first largest.
  static D max3(D a, D b, D c) {
    const D m = xsimd::select(a < b, b, a);
    return xsimd::select(m < c, c, m);
  }
  /// (v - v) is 0 exactly when v is finite (NaN otherwise); a compare, no classification table.
  static B finite(D v) { return (v - v) == D(0.0); }

  /// snap() of setup.cpp in lanes, as a double holding the 16.8 integer: clamp, then round to
  /// nearest with ties to even, one rounding instruction on every ISA here (its mode is in the
  /// instruction, not the MXCSR). The + 0 makes a -0 (from a small negative input) +0, which the
  /// scalar int32 always is: x0 and the planes see it.
  static D snap(D px) {
    constexpr double kLimit = kGuardBandPx;
    constexpr double kUnitsPerPx = kSubpixelOne;
    px = xsimd::select(px < D(-kLimit), D(-kLimit), xsimd::select(D(kLimit) < px, D(kLimit), px));
    return xsimd::nearbyint(px * D(kUnitsPerPx)) + D(0.0);
  }

  /// The lanes whose value converts to a finite float (the conversion plane() makes).
  static B float_finite(D d) {
    return xsimd::abs(M::to_float(d)) <= D(double{std::numeric_limits<float>::max()});
  }

  /// make_plane() of setup.cpp in lanes, in its operation order (the division is not a
  /// multiplication by a reciprocal: that would round differently). Returns the lanes whose
  /// plane is finite as floats (is_finite() of plane()).
  static B make_plane(const D (&X)[3], const D (&Y)[3], D area_px2, D f0, D f1, D f2,
                      PlaneLanes& out) {
    const D ddx = ((f1 - f0) * (Y[2] - Y[0]) - (f2 - f0) * (Y[1] - Y[0])) / area_px2;
    const D ddy = ((f2 - f0) * (X[1] - X[0]) - (f1 - f0) * (X[2] - X[0])) / area_px2;
    f0.store_aligned(out.base);
    ddx.store_aligned(out.ddx);
    ddy.store_aligned(out.ddy);
    return float_finite(f0) && float_finite(ddx) && float_finite(ddy);
  }

  /// The oriented corners' 1/W normalised as setup_triangle() does (only ratios matter, so the
  /// largest is 1), into r.qn, and its plane into r.q.
  static B q_plane(const D (&Xs)[3], const D (&Ys)[3], D area, Results& r) {
    const D Qo[3] = {load(r.qo[0]), load(r.qo[1]), load(r.qo[2])};
    const D qmax = max3(Qo[0], Qo[1], Qo[2]);
    const D qn[3] = {Qo[0] / qmax, Qo[1] / qmax, Qo[2] / qmax};
    for (int k = 0; k < 3; ++k) qn[k].store_aligned(r.qn[k]);
    return make_plane(Xs, Ys, area, qn[0], qn[1], qn[2], r.q);
  }

  /// Oriented corners: 1 and 2 swap where the triangle was counter-clockwise on screen.
  static std::array<D, 3> oriented(B ccw, const D (&a)[3]) {
    return {a[0], xsimd::select(ccw, a[2], a[1]), xsimd::select(ccw, a[1], a[2])};
  }

  /// The interpolated vertex colours of setup_triangle() for the drawn lanes: which interpolate
  /// (their corners' colours differ), and their planes.
  static void color_planes(const Vertices& v, std::uint32_t drawn, Results& r) {
    const B ccw = load(r.ccw_lanes) != D(0.0);
    std::array<D, 3> c[kColorChannels];
    B equal(true);
    for (int ch = 0; ch < kColorChannels; ++ch) {
      const D cs[3] = {load(v.color[0][ch]), load(v.color[1][ch]), load(v.color[2][ch])};
      c[ch] = oriented(ccw, cs);
      equal = equal && c[ch][0] == c[ch][1] && c[ch][0] == c[ch][2];
    }
    r.interpolated = M::bits(!equal) & drawn;
    r.planes_finite = 0;
    if (!r.interpolated) return;
    const D Xs[3] = {load(r.xs[0]), load(r.xs[1]), load(r.xs[2])};
    const D Ys[3] = {load(r.ys[0]), load(r.ys[1]), load(r.ys[2])};
    const D area = load(r.area_px2);
    B finite = q_plane(Xs, Ys, area, r);
    const D qn[3] = {load(r.qn[0]), load(r.qn[1]), load(r.qn[2])};
    for (int ch = 0; ch < kColorChannels; ++ch)
      finite = finite && make_plane(Xs, Ys, area, c[ch][0] * qn[0], c[ch][1] * qn[1],
                                    c[ch][2] * qn[2], r.c_q[ch]);
    r.planes_finite = M::bits(finite);
  }

  /// setup_varyings() after the culls: the varyings gathered by vertex (floats widened to double,
  /// as TriangleFrontEnd::run() reads them) in oriented corner order, then their planes over
  /// setup()'s geometry.
  static void varying_planes(const TriangleFrontEnd& scalar, const Vertices& v, Results& r) {
    const Draw& draw = scalar.fetch.draw;
    const int nvary = scalar.nvary;
    const B ccw = load(r.ccw_lanes) != D(0.0);
    const auto stride = static_cast<std::int64_t>(attribute_row(draw));
    const D Xs[3] = {load(r.xs[0]), load(r.xs[1]), load(r.xs[2])};
    const D Ys[3] = {load(r.ys[0]), load(r.ys[1]), load(r.ys[2])};
    const D area = load(r.area_px2);
    B finite = q_plane(Xs, Ys, area, r);
    const D qn[3] = {load(r.qn[0]), load(r.qn[1]), load(r.qn[2])};
    for (int j = 0; j < nvary; ++j) {
      const float* column = draw.attributes.data() + draw.varyings[j];
      // Read lane by lane from the corners' vertex numbers in memory and put together in
      // registers: xsimd's gather of floats into doubles extracts each index through a store of
      // the whole vector, and a vector load of lanes just stored one by one waits for them all.
      const auto corner = [&](int k) {
        return lanes_of([&](int l) { return static_cast<double>(column[v.vertex[k][l] * stride]); },
                        std::make_index_sequence<N>{});
      };
      const D a[3] = {corner(0), corner(1), corner(2)};
      const auto o = oriented(ccw, a);
      for (int k = 0; k < 3; ++k) o[k].store_aligned(r.vary[k][j]);
      finite =
          finite && make_plane(Xs, Ys, area, o[0] * qn[0], o[1] * qn[1], o[2] * qn[2], r.vary_q[j]);
    }
    r.planes_finite = M::bits(finite);
  }

  /// VertexFetch of one corner, out of line so that fetch() stays small enough to inline into
  /// run(); a transformed vertex's matrix product costs more than the call.
  [[gnu::noinline]] static bool fetch_vertex(const VertexFetch& fetch, std::uint32_t i,
                                             ClipVertex& c) {
    return fetch(i, c);
  }

  /// Fetches triangles t0 .. t0 + n - 1 into lanes; the lanes past n repeat lane 0, so that they
  /// compute something harmless (their results are not read).
  static void fetch(const TriangleFrontEnd& scalar, std::uint32_t t0, int n, Vertices& v) {
    const Draw& draw = scalar.fetch.draw;
    v.nonfinite = 0;
    v.cached = false;
    v.raw = draw.positions_xyz.empty();
    if (v.raw) {  // the common case, where VertexFetch's remaining work is cheaper in lanes
      for (int l = 0; l < N; ++l) {
        const std::uint32_t t = t0 + static_cast<std::uint32_t>(l < n ? l : 0);
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t i = scalar.fetch.vertex(t, k);
          v.vertex[k][l] = i;
          const glm::vec4 p = draw.positions[i];
          v.X[k][l] = p.x;
          v.Y[k][l] = p.y;
          v.Z[k][l] = p.z;
          v.W[k][l] = p.w;
          if (scalar.per_vertex) store_color(v, k, l, scalar.fetch.color(i));
        }
      }
      return;
    }
    for (int l = 0; l < N; ++l) {
      const std::uint32_t t = t0 + static_cast<std::uint32_t>(l < n ? l : 0);
      bool ok = true;
      for (int k = 0; k < 3; ++k) {
        ClipVertex c{};
        const std::uint32_t i = scalar.fetch.vertex(t, k);
        v.vertex[k][l] = i;
        ok = ok && fetch_vertex(scalar.fetch, i, c);
        v.X[k][l] = c.X;
        v.Y[k][l] = c.Y;
        v.Z[k][l] = c.Z;
        v.W[k][l] = c.W;
        if (scalar.per_vertex) store_color(v, k, l, c.color);
      }
      if (!ok) v.nonfinite |= 1u << l;
    }
  }

  /// The packed colours of a cached batch into `color`, in lanes: each channel's byte as a
  /// double, exactly (its bits put under 2^52's exponent, then 2^52 taken away).
  static void unpack_colors(Vertices& v) {
    using U = xsimd::batch<std::uint64_t, A>;
    const U exponent(0x4330000000000000u);  // the bits of 2^52
    const D two52(0x1p52);
    for (int k = 0; k < 3; ++k) {
      const U c = U::load_aligned(v.rgba[k]);
      for (int ch = 0; ch < kColorChannels; ++ch) {
        const U byte = (c >> (8 * ch)) & U(0xffu);
        (xsimd::bitwise_cast<D>(byte | exponent) - two52).store_aligned(v.color[k][ch]);
      }
    }
  }

  static void store_color(Vertices& v, int k, int l, const std::array<double, kColorChannels>& c) {
    for (int ch = 0; ch < kColorChannels; ++ch) v.color[k][ch][l] = c[ch];
  }

  /// fetch() for a draw with a vertex cache: the corners' projections in lanes (each lane's record
  /// loaded whole, the batch's records transposed), and the lanes' clip classes from the
  /// corners' codes, as setup() finds them from the positions.
  static void fetch_cached(const VertexCache& cache, const std::uint32_t (&corners)[3 * N],
                           Vertices& v) {
    namespace vc = vertex_code;
    // The record's 64-bit words, as simd::Records<A> transposes them.
    static_assert(offsetof(ProjectedVertex, px) == 0 && offsetof(ProjectedVertex, py) == 4 &&
                  offsetof(ProjectedVertex, z) == 8 && offsetof(ProjectedVertex, code) == 12 &&
                  offsetof(ProjectedVertex, q) == 16 && offsetof(ProjectedVertex, rgba) == 24);
    using R = simd::Records<A>;
    using U = xsimd::batch<std::uint64_t, A>;
    v.nonfinite = 0;
    v.raw = false;
    v.cached = true;
    U all(0xffu), any(0u);
    for (int k = 0; k < 3; ++k) {
      const void* rows[N];
      for (int l = 0; l < N; ++l) {
        const std::uint32_t i = corners[3 * l + k];
        v.vertex[k][l] = i;
        rows[l] = &cache.data[i];
      }
      D word[4];
      R::columns(rows, word);
      R::low_floats(word[0]).store_aligned(v.X[k]);   // px
      R::high_floats(word[0]).store_aligned(v.Y[k]);  // py
      R::low_floats(word[1]).store_aligned(v.Z[k]);   // z
      word[2].store_aligned(v.W[k]);                  // q
      // rgba in the low half; unpack_colors() reads only its four bytes.
      xsimd::bitwise_cast<U>(word[3]).store_aligned(v.rgba[k]);
      const U code = xsimd::bitwise_cast<U>(word[1]) >> 32;
      all &= code;
      any |= code;
    }
    // Each class as the sign bit of its lane: all corners outside one clip plane (a code below
    // 64 plus 2^63 - 1 reaches 2^63 exactly when it is not 0), any corner not finite, or any
    // corner past the guard band or the near plane.
    static_assert(vc::kClipPlanes == 63 && vc::kClip == 1 << 6 && vc::kNonFinite == 1 << 7);
    const auto sign_bits = [](U u) { return M::signs(xsimd::bitwise_cast<D>(u)); };
    const std::uint32_t outside =
        sign_bits((all & U(vc::kClipPlanes)) + U(std::numeric_limits<std::int64_t>::max()));
    const std::uint32_t nonfinite = sign_bits(any << 56), clip = sign_bits(any << 57);
    v.cached_scalar = nonfinite | (clip & ~outside);
    v.cached_outside = outside;
  }

  /// The vertex indices of triangles t0 .. t0 + n - 1, three a triangle, into `corners`; the
  /// places past them repeat triangle t0's, as the lanes past n do.
  static void batch_indices(const IndexSpan& indices, std::uint32_t t0, int n,
                            std::uint32_t (&corners)[3 * N]) {
    const std::size_t first = 3 * std::size_t{t0};
    const int m = 3 * n;
    if (indices.empty()) {
      for (int j = 0; j < m; ++j) corners[j] = static_cast<std::uint32_t>(first + j);
    } else if (indices.is_16_bit()) {
      const std::uint16_t* narrow = indices.narrow().data() + first;
      for (int j = 0; j < m; ++j) corners[j] = narrow[j];
    } else if (n == N) {  // a copy of known size: vector moves, not a string instruction
      std::memcpy(corners, indices.wide().data() + first, sizeof corners);
    } else {
      std::memcpy(corners, indices.wide().data() + first, sizeof(std::uint32_t) * m);
    }
    for (int j = m; j < 3 * N; ++j) corners[j] = corners[j % 3];
  }

  /// The vertex indices of the n triangles listed in `ids`, three a triangle, into `corners` (as
  /// batch_indices() makes them); the places past them repeat the first triangle's.
  static void listed_indices(const VertexFetch& fetch, const std::uint32_t* ids, int n,
                             std::uint32_t (&corners)[3 * N]) {
    for (int l = 0; l < N; ++l)
      for (int k = 0; k < 3; ++k) corners[3 * l + k] = fetch.vertex(ids[l < n ? l : 0], k);
  }

  /// The projection of VertexFetch's output in lanes, one vertex per lane: for raw positions the
  /// non-finite test and the viewport map first, as VertexFetch does them.
  static Projection project(D X, D Y, D Z, D W, bool raw, const VertexFetch& fetch, D w, D h) {
    constexpr double kGuard = kGuardBandPx;
    Projection p;
    p.nonfinite = B(false);
    if (raw) {
      p.nonfinite = !(finite(X) && finite(Y) && finite(Z) && finite(W));
      fetch.to_window(X, Y, W, X, Y);
    }
    // clip_triangle()'s tests: beyond a side of the viewport (or the near or far plane); outside
    // the guard band or the depth range.
    p.beyond[0] = X < D(0.0);
    p.beyond[1] = X > w * W;
    p.beyond[2] = Y < D(0.0);
    p.beyond[3] = Y > h * W;
    p.beyond[4] = Z < D(0.0);
    p.beyond[5] = Z > W;
    const D gw = D(kGuard) * W;
    const B outside = Z < D(0.0) || W - Z < D(0.0) || X + gw < D(0.0) || gw - X < D(0.0) ||
                      Y + gw < D(0.0) || gw - Y < D(0.0);
    // The perspective divide (divide() of front_end.cpp). W <= 0 or a non-finite result is left
    // to the scalar code, which counts it.
    p.q = D(1.0) / W;
    const D x = X * p.q, y = Y * p.q;
    const B divide_ok = W > D(0.0) && finite(x) && finite(y) && finite(p.q);
    p.z = M::to_float(Z * p.q);  // ScreenVertex::z is a float
    p.px = snap(x);
    p.py = snap(y);
    p.clip = outside || !divide_ok;
    return p;
  }

  /// The vertex stage: vertices [begin, end) of `draw` projected into `cache` in lanes.
  static void project_vertices(const Draw& draw, int width, int height, std::uint32_t begin,
                               std::uint32_t end, const VertexCache& cache) {
    namespace vc = vertex_code;
    // Projected into the draw's viewport, whose pixels setup works in (front/draw_area.hpp).
    const DrawArea area = DrawArea::of(draw.state, width, height);
    const VertexFetch fetch(draw, area.width, area.height);
    const bool raw = draw.positions_xyz.empty();
    const D w(static_cast<double>(area.width)), h(static_cast<double>(area.height));
    alignas(64) double X[N], Y[N], Z[N], W[N];
    alignas(64) double px[N], py[N], z[N], q[N], codes[N];
    for (std::uint32_t i0 = begin; i0 < end; i0 += N) {
      const int n = static_cast<int>(std::min<std::uint32_t>(N, end - i0));
      std::uint32_t nonfinite = 0;
      for (int l = 0; l < N; ++l) {
        const std::uint32_t i = i0 + static_cast<std::uint32_t>(l < n ? l : 0);
        if (raw) {
          const glm::vec4 p = draw.positions[i];
          X[l] = p.x;
          Y[l] = p.y;
          Z[l] = p.z;
          W[l] = p.w;
        } else {
          ClipVertex c{};
          if (!fetch(i, c)) nonfinite |= 1u << l;
          X[l] = c.X;
          Y[l] = c.Y;
          Z[l] = c.Z;
          W[l] = c.W;
        }
      }
      const Projection p = project(load(X), load(Y), load(Z), load(W), raw, fetch, w, h);
      p.px.store_aligned(px);
      p.py.store_aligned(py);
      p.z.store_aligned(z);
      p.q.store_aligned(q);
      // The code's bits summed in lanes (each bit once: exact).
      D code = xsimd::select(p.clip, D(vc::kClip), D(0.0));
      code += xsimd::select(p.nonfinite, D(vc::kNonFinite), D(0.0));
      for (int j = 0; j < 6; ++j) code += xsimd::select(p.beyond[j], D(1 << j), D(0.0));
      code.store_aligned(codes);
      const bool with_color = draw.color_source == ColorSource::kPerVertex;
      for (int l = 0; l < n; ++l) {
        ProjectedVertex& out = cache.data[i0 + static_cast<std::uint32_t>(l)];
        // Exact: the snapped coordinates are integers of at most 2^23, z already a float.
        out.px = static_cast<float>(px[l]);
        out.py = static_cast<float>(py[l]);
        out.z = static_cast<float>(z[l]);
        out.q = q[l];
        out.code = static_cast<std::uint32_t>(codes[l]) | ((nonfinite >> l) & 1u) * vc::kNonFinite;
        if (with_color) {
          const Rgba8 c = draw.colors[i0 + static_cast<std::uint32_t>(l)];
          out.rgba = std::uint32_t{c.r} | (std::uint32_t{c.g} << 8) | (std::uint32_t{c.b} << 16) |
                     (std::uint32_t{c.a} << 24);
        }
      }
    }
  }

  /// One 16.8 unit in pixels: dividing by 256 is exact in float and double.
  static constexpr double kPxPerUnit = 1.0 / kSubpixelOne;

  /// Whether the lanes' triangles face the viewer, from their winding on screen.
  template <class BB>
  static BB facing_viewer(BB ccw, const DrawState& state) {
    return state.front_face == FrontFace::kCounterClockwise ? ccw : !ccw;
  }
  /// Whether DrawState::cull culls the lanes' triangles, from their facing.
  template <class BB>
  static BB culled_by_face(BB front, const DrawState& state) {
    return state.cull == CullMode::kBack    ? !front
           : state.cull == CullMode::kFront ? front
                                            : BB(false);
  }

  /// A triangle's pixel box, kept to its draw area's clip rectangle, whether that is empty, and
  /// whether it holds a sample position (box_holds_sample() of setup.hpp).
  template <class V>
  struct PixelBox {
    V bx0, by0, bx1, by1;
    xsimd::batch_bool<typename V::value_type, A> empty, holds;
  };
  /// PixelBox from the snapped corners' extremes (16.8 units), in double lanes, or in float
  /// lanes when every corner is an integer of at most 2^23 in magnitude: every step is exact
  /// either way (integers below 2^24, and divisions by 256).
  template <class V>
  static PixelBox<V> pixel_box(V minx, V maxx, V miny, V maxy, const DrawArea& area,
                               const SampleSpots& spots) {
    using T = typename V::value_type;
    const V per_unit(static_cast<T>(kPxPerUnit)), unit(static_cast<T>(kSubpixelOne));
    // Kept to the area's clip rectangle [cx0, cx1) × [cy0, cy1), in the viewport's pixels; the
    // floor of v / 256 is the scalar arithmetic shift.
    const V cx0(static_cast<T>(area.x0)), cy0(static_cast<T>(area.y0));
    const V cx1(static_cast<T>(area.x1)), cy1(static_cast<T>(area.y1));
    PixelBox<V> b;
    b.bx0 = xsimd::max(cx0, xsimd::floor(minx * per_unit));
    b.by0 = xsimd::max(cy0, xsimd::floor(miny * per_unit));
    b.bx1 = xsimd::min(cx1, xsimd::floor(maxx * per_unit) + V(T(1)));
    b.by1 = xsimd::min(cy1, xsimd::floor(maxy * per_unit) + V(T(1)));
    b.empty = b.bx0 >= b.bx1 || b.by0 >= b.by1;
    // A box at least a pixel wide and tall that the clip rectangle does not cut holds every
    // sample position: when all lanes' boxes are such, the answer is known without the loop.
    const auto whole = maxx - minx >= unit && maxy - miny >= unit && minx >= cx0 * unit &&
                       miny >= cy0 * unit && maxx < cx1 * unit && maxy < cy1 * unit;
    b.holds = decltype(whole)(spots.count == 0 || xsimd::all(whole));
    for (int s = 0; s < spots.count && !xsimd::all(b.holds); ++s) {
      const V sx(static_cast<T>(spots.x[s])), sy(static_cast<T>(spots.y[s]));
      const V sx0 = xsimd::max(b.bx0, xsimd::ceil((minx - sx) * per_unit));
      const V sx1 = xsimd::min(b.bx1 - V(T(1)), xsimd::floor((maxx - sx) * per_unit));
      const V sy0 = xsimd::max(b.by0, xsimd::ceil((miny - sy) * per_unit));
      const V sy1 = xsimd::min(b.by1 - V(T(1)), xsimd::floor((maxy - sy) * per_unit));
      b.holds = b.holds || (sx0 <= sx1 && sy0 <= sy1);
    }
    return b;
  }

  /// clip_triangle()'s classification, the perspective divide and setup_triangle(), in lanes; a
  /// cached v brings its corners already projected. It and set_up() inline into run(), their one
  /// caller: out of line, the call costs more than the facing bits they compute.
  [[gnu::always_inline]] static void setup(const Vertices& v, const VertexFetch& fetch,
                                           const DrawArea& area, bool shaded,
                                           const SampleSpots& spots, Results& r) {
    const D w(static_cast<double>(area.width)), h(static_cast<double>(area.height));
    D px[3], py[3], z[3], q[3];
    std::uint32_t scalar, clip_culled;
    if (v.cached) {
      for (int k = 0; k < 3; ++k) {
        px[k] = load(v.X[k]);
        py[k] = load(v.Y[k]);
        z[k] = load(v.Z[k]);
        q[k] = load(v.W[k]);
      }
      scalar = v.cached_scalar;
      clip_culled = v.cached_outside;
    } else {
      Projection p[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = project(load(v.X[k]), load(v.Y[k]), load(v.Z[k]), load(v.W[k]), v.raw, fetch, w, h);
        px[k] = p[k].px;
        py[k] = p[k].py;
        z[k] = p[k].z;
        q[k] = p[k].q;
      }
      // clip_triangle(): culled when all three vertices are beyond one clip plane; inside when
      // every vertex is inside every one. A triangle in neither case is the scalar code's.
      B culled(false);
      for (int j = 0; j < 6; ++j)
        culled = culled || (p[0].beyond[j] && p[1].beyond[j] && p[2].beyond[j]);
      const std::uint32_t nonfinite =
          v.nonfinite | M::bits(p[0].nonfinite || p[1].nonfinite || p[2].nonfinite);
      scalar = nonfinite | M::bits(!culled && (p[0].clip || p[1].clip || p[2].clip));
      clip_culled = M::bits(culled);
    }
    set_up(px, py, z, q, scalar, clip_culled, fetch.draw.state, area, shaded, spots, r);
  }

  /// setup_triangle() in lanes from the corners' projections, for lanes not in `scalar`.
  [[gnu::always_inline]] static void set_up(const D (&px)[3], const D (&py)[3], const D (&z)[3],
                                            const D (&q)[3], std::uint32_t scalar,
                                            std::uint32_t clip_culled, const DrawState& state,
                                            const DrawArea& area, bool shaded,
                                            const SampleSpots& spots, Results& r) {
    const D area2 = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
    const B degenerate = area2 == D(0.0);
    const B ccw = area2 < D(0.0);
    const B front = facing_viewer(ccw, state);
    const B face = culled_by_face(front, state);
    r.back = M::bits(!front);

    const D minx = min3(px[0], px[1], px[2]), maxx = max3(px[0], px[1], px[2]);
    const D miny = min3(py[0], py[1], py[2]), maxy = max3(py[0], py[1], py[2]);
    const PixelBox<D> box = pixel_box(minx, maxx, miny, maxy, area, spots);
    const D bx0 = box.bx0, by0 = box.by0, bx1 = box.bx1, by1 = box.by1;
    const B box_empty = box.empty, holds = box.holds;
    // Which counter the lane's triangle goes to, in the scalar code's order of tests.
    r.scalar = scalar;
    const std::uint32_t culled = scalar | clip_culled;
    r.degenerate = M::bits(degenerate) & ~culled;
    r.face = M::bits(face) & ~(culled | r.degenerate);
    r.outside = (clip_culled & ~scalar) | (M::bits(box_empty) & ~(culled | r.degenerate | r.face));
    r.no_sample = M::bits(!holds) & ~(culled | r.degenerate | r.face | r.outside);
    r.interpolated = 0;
    if ((r.scalar | r.outside | r.face | r.degenerate | r.no_sample) == kAllLanes)
      return;  // nothing drawn: no edges or planes are needed
    bx0.store_aligned(r.bx0);
    by0.store_aligned(r.by0);
    bx1.store_aligned(r.bx1);
    by1.store_aligned(r.by1);

    // Orient clockwise on screen: corners 1 and 2 swap where the area is negative.
    const D ox[3] = {px[0], xsimd::select(ccw, px[2], px[1]), xsimd::select(ccw, px[1], px[2])};
    const D oy[3] = {py[0], xsimd::select(ccw, py[2], py[1]), xsimd::select(ccw, py[1], py[2])};
    D ea[3], eb[3], ec[3];
    for (int e = 0; e < 3; ++e) {
      const int f = (e + 1) % 3;
      const D dx = ox[f] - ox[e];
      const D dy = oy[f] - oy[e];
      // The fill rule as in setup_triangle(): an excluded edge needs E > 0, i.e. E - 1 >= 0.
      const B horizontal_kept = state.fill_rule == FillRule::kD3D ? dx > D(0.0) : dx < D(0.0);
      const B included = dy < D(0.0) || (dy == D(0.0) && horizontal_kept);
      const D c = ox[e] * oy[f] - ox[f] * oy[e];
      ea[e] = -dy;
      eb[e] = dx;
      ec[e] = xsimd::select(included, c, c - D(1.0));
      ea[e].store_aligned(r.ea[e]);
      eb[e].store_aligned(r.eb[e]);
      ec[e].store_aligned(r.ec[e]);
    }
    const std::uint32_t set_up_lanes =
        kAllLanes & ~(r.scalar | r.outside | r.face | r.degenerate | r.no_sample);
    r.no_sample |= shrink_to_covered(ea, eb, ec, bx0, by0, bx1, by1, area2, spots, set_up_lanes, r);

    // Planes over the oriented corners in pixels (x / 256 is exact: a power of two).
    const D Xs[3] = {ox[0] * D(kPxPerUnit), ox[1] * D(kPxPerUnit), ox[2] * D(kPxPerUnit)};
    const D Ys[3] = {oy[0] * D(kPxPerUnit), oy[1] * D(kPxPerUnit), oy[2] * D(kPxPerUnit)};
    const auto Zo = oriented(ccw, z);
    const D area_px2 = xsimd::abs(area2) * D(kPxPerUnit * kPxPerUnit);
    Xs[0].store_aligned(r.x0);
    Ys[0].store_aligned(r.y0);
    make_plane(Xs, Ys, area_px2, Zo[0], Zo[1], Zo[2], r.z);
    min3(Zo[0], Zo[1], Zo[2]).store_aligned(r.z_min);
    max3(Zo[0], Zo[1], Zo[2]).store_aligned(r.z_max);
    if (shaded) {  // for color_planes() and varying_planes()
      const auto Qo = oriented(ccw, q);
      for (int k = 0; k < 3; ++k) {
        Xs[k].store_aligned(r.xs[k]);
        Ys[k].store_aligned(r.ys[k]);
        Qo[k].store_aligned(r.qo[k]);
      }
      area_px2.store_aligned(r.area_px2);
      xsimd::select(ccw, D(1.0), D(0.0)).store_aligned(r.ccw_lanes);
    }
  }

  /// shrink_to_covered() of front/sample_cull.hpp in lanes: returns those of `lanes` the cull
  /// tests whose candidate samples all lie outside an edge, and shrinks the boxes in `r` of the
  /// tested lanes that cover one. A tested lane's edge values are integers below 2^50 and each
  /// step adds one, so every sum is exact: the scalar int64 values.
  static std::uint32_t shrink_to_covered(const D (&ea)[3], const D (&eb)[3], const D (&ec)[3],
                                         D bx0, D by0, D bx1, D by1, D area2,
                                         const SampleSpots& spots, std::uint32_t lanes,
                                         Results& r) {
    if (spots.count == 0) return 0;  // no positions: nothing is culled
    const D w = bx1 - bx0, h = by1 - by0, samples(static_cast<double>(spots.count));
    const B tests = w * h * samples <= D(kMaxCullCandidates) &&
                    xsimd::abs(area2) * samples <= D(kCullMaxExpectedSamples * kPixelArea2);
    lanes &= M::bits(tests);
    if (!lanes) return 0;
    // The candidates of the largest box among the tested lanes; each lane's own box masks them.
    alignas(64) double wl[N], hl[N];
    w.store_aligned(wl);
    h.store_aligned(hl);
    int wmax = 0, hmax = 0;
    for (std::uint32_t b = lanes; b; b &= b - 1) {
      wmax = std::max(wmax, static_cast<int>(wl[std::countr_zero(b)]));
      hmax = std::max(hmax, static_cast<int>(hl[std::countr_zero(b)]));
    }
    // Each edge's values at the box's first pixel corner and its steps by one pixel.
    const D one(kSubpixelOne);
    const D step_x[3] = {ea[0] * one, ea[1] * one, ea[2] * one};
    const D step_y[3] = {eb[0] * one, eb[1] * one, eb[2] * one};
    const D corner_x = bx0 * one, corner_y = by0 * one;
    // +inf in a column of the lane's own box, -inf past it: the min with it keeps or drops a
    // candidate without a mask.
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const D inf(kInf), minus_inf(-kInf);
    // column_best, row_best: the largest over each column's and each row's candidates of the
    // smallest edge value, >= 0 where one of them is inside.
    D column[kMaxCullCandidates], column_best[kMaxCullCandidates], row_best[kMaxCullCandidates];
    for (int x = 0; x < wmax; ++x) {
      column[x] = xsimd::select(D(static_cast<double>(x)) < w, inf, minus_inf);
      column_best[x] = minus_inf;
    }
    for (int y = 0; y < hmax; ++y) row_best[y] = minus_inf;
    for (int s = 0; s < spots.count; ++s) {
      const D sx = corner_x + D(static_cast<double>(spots.x[s]));
      const D sy = corner_y + D(static_cast<double>(spots.y[s]));
      D row[3];
      for (int e = 0; e < 3; ++e) row[e] = ea[e] * sx + eb[e] * sy + ec[e];
      for (int y = 0; y < hmax; ++y) {
        const D in_row = xsimd::select(D(static_cast<double>(y)) < h, inf, minus_inf);
        D e0 = row[0], e1 = row[1], e2 = row[2];
        D best = minus_inf;
        for (int x = 0; x < wmax; ++x) {
          const D bound = xsimd::min(column[x], in_row);
          const D v = xsimd::min(xsimd::min(e0, e1), xsimd::min(e2, bound));
          column_best[x] = xsimd::max(column_best[x], v);
          best = xsimd::max(best, v);
          e0 += step_x[0];
          e1 += step_x[1];
          e2 += step_x[2];
        }
        row_best[y] = xsimd::max(row_best[y], best);
        for (int e = 0; e < 3; ++e) row[e] += step_y[e];
      }
    }
    // The covered columns' and rows' range, from the box's first.
    D x_lo = inf, x_hi = minus_inf, y_lo = inf, y_hi = minus_inf;
    for (int x = 0; x < wmax; ++x) {
      const B in = column_best[x] >= D(0.0);
      x_lo = xsimd::min(x_lo, xsimd::select(in, D(static_cast<double>(x)), inf));
      x_hi = xsimd::select(in, D(static_cast<double>(x + 1)), x_hi);
    }
    for (int y = 0; y < hmax; ++y) {
      const B in = row_best[y] >= D(0.0);
      y_lo = xsimd::min(y_lo, xsimd::select(in, D(static_cast<double>(y)), inf));
      y_hi = xsimd::select(in, D(static_cast<double>(y + 1)), y_hi);
    }
    const std::uint32_t covered = M::bits(x_hi >= D(0.0));
    alignas(64) double box[4][N];
    (bx0 + x_lo).store_aligned(box[0]);
    (bx0 + x_hi).store_aligned(box[1]);
    (by0 + y_lo).store_aligned(box[2]);
    (by0 + y_hi).store_aligned(box[3]);
    for (std::uint32_t b = lanes & covered; b; b &= b - 1) {
      const int l = std::countr_zero(b);
      r.bx0[l] = box[0][l];
      r.bx1[l] = box[1][l];
      r.by0[l] = box[2][l];
      r.by1[l] = box[3][l];
    }
    return lanes & ~covered;
  }

  static Plane plane(const PlaneLanes& p, int l) {
    return {static_cast<float>(p.base[l]), static_cast<float>(p.ddx[l]),
            static_cast<float>(p.ddy[l])};
  }

  /// The fields of every lane's TriangleSetup that the lanes computed, into batch[l] as
  /// setup_triangle() would write them: edges, anchor, box, depth plane and range, and
  /// planes_base kNoPlanes; the colour and draw word are the lane's own (finish()). Each setup is
  /// built as 16 words in lanes and the batch's words transposed into its setups (simd::Records).
  static void build_setups(const Results& r, TriangleSetup (&batch)[N]) {
    static_assert(sizeof(TriangleSetup) == 16 * 8 && offsetof(TriangleSetup, edge) == 0 &&
                  sizeof(EdgeFunction) == 24 && offsetof(TriangleSetup, x0) == 72 &&
                  offsetof(TriangleSetup, y0) == 76 && offsetof(TriangleSetup, bx0) == 80 &&
                  offsetof(TriangleSetup, by0) == 84 && offsetof(TriangleSetup, bx1) == 88 &&
                  offsetof(TriangleSetup, by1) == 92 && offsetof(TriangleSetup, z) == 96 &&
                  offsetof(TriangleSetup, z_min) == 108 && offsetof(TriangleSetup, z_max) == 112 &&
                  offsetof(TriangleSetup, color) == 116 &&
                  offsetof(TriangleSetup, draw_word) == 120 &&
                  offsetof(TriangleSetup, planes_base) == 124);
    using R = simd::Records<A>;
    D word[16];
    for (int e = 0; e < 3; ++e) {
      word[3 * e] = R::int64s(load(r.ea[e]));
      word[3 * e + 1] = R::int64s(load(r.eb[e]));
      word[3 * e + 2] = R::int64s(load(r.ec[e]));
    }
    word[9] = R::pack_floats(load(r.x0), load(r.y0));
    word[10] = R::pack_ints(load(r.bx0), load(r.by0));
    word[11] = R::pack_ints(load(r.bx1), load(r.by1));
    word[12] = R::pack_floats(load(r.z.base), load(r.z.ddx));
    word[13] = R::pack_floats(load(r.z.ddy), load(r.z_min));
    word[14] = R::pack_floats(load(r.z_max), D(0.0));  // the colour: finish()
    // The draw word (finish()) and planes_base = kNoPlanes.
    word[15] =
        xsimd::bitwise_cast<D>(xsimd::batch<std::uint64_t, A>(std::uint64_t{kNoPlanes} << 32));
    R::rows(word, 16, batch, sizeof(TriangleSetup));
  }

  /// The rest of lane l's drawn triangle, ts a copy of its build_setups() setup, as
  /// setup_triangle() and TriangleFrontEnd::run() would write it: its colour, appending its
  /// colour planes, if it interpolates, to `planes`, its draw word, and the viewport's move.
  static void finish(const Results& r, const Vertices& v, int l, const DrawArea& area,
                     bool per_vertex, Rgba8 flat, std::uint32_t draw_index, PlaneArray* planes,
                     TriangleSetup& ts) {
    ts.color = flat;
    if (per_vertex) {
      // (A lane whose planes are not all finite stays flat, as keep_color_planes() leaves it.)
      if (planes && (r.interpolated & r.planes_finite & (1u << l))) {
        std::array<Plane, kColorPlanes> p;
        p[0] = plane(r.q, l);
        for (int ch = 0; ch < kColorChannels; ++ch) p[1 + ch] = plane(r.c_q[ch], l);
        append_color_planes(p, *planes, ts);
      }
      if (is_flat(ts) && v.cached) {
        // Corner 0's bytes as the vertex stage packed them (never swapped by the orientation):
        // to_unorm8() of a byte's value is the byte.
        ts.color = std::bit_cast<Rgba8>(static_cast<std::uint32_t>(v.rgba[0][l]));
      } else if (is_flat(ts)) {
        std::uint8_t c[kColorChannels];
        for (int ch = 0; ch < kColorChannels; ++ch)
          c[ch] = to_unorm8(static_cast<float>(v.color[0][ch][l]));
        ts.color = {c[0], c[1], c[2], c[3]};
      }
    }
    ts.set_draw(draw_index, (r.back >> l) & 1u);
    if (area.moved()) area.move(ts);
  }

  /// Appends lane l's varying planes to `planes` as setup_varyings() does: q and each varying
  /// times q, or, if one of them overflows float, constant planes of corner 0's values.
  static void store_varyings(const Results& r, int l, int nvary, PlaneArray& planes,
                             TriangleSetup& ts) {
    ts.planes_base = static_cast<std::uint32_t>(planes.size());
    // One resize for the triangle's planes (PlaneArray leaves them unset), then plain stores: a
    // push_back per plane cost more than the planes' conversion.
    planes.resize(planes.size() + 1 + static_cast<std::size_t>(nvary));
    Plane* p = planes.data() + ts.planes_base;
    if ((r.planes_finite >> l) & 1u) {  // is_finite() of each, in lanes (varying_planes())
      p[0] = plane(r.q, l);
      for (int k = 0; k < nvary; ++k) p[1 + k] = plane(r.vary_q[k], l);
      return;
    }
    p[0] = {1.0f, 0.0f, 0.0f};
    // Corner 0 is never swapped by the orientation.
    for (int k = 0; k < nvary; ++k) p[1 + k] = {static_cast<float>(r.vary[0][k][l]), 0.0f, 0.0f};
  }

  using Fv = xsimd::batch<float, A>;
  using Iv = xsimd::batch<std::int32_t, A>;
  static constexpr int kFloatLanes = static_cast<int>(Fv::size);  ///< triangles per pre-cull step
  /// Triangles per window of the pre-cull: one window's survivors wait in a list on the stack.
  /// A draw piece's first window is shorter: a piece the pre-cull does not pay for (a mesh seen
  /// close up) then tries it on few triangles.
  static constexpr std::uint32_t kPrecullWindow = 256, kPrecullFirstWindow = 64;
  /// The widest and tallest box (16.8 units) the pre-cull settles: corner differences of at most
  /// 2^11 make twice the area, a difference of two products of at most 2^22, exact in float.
  static constexpr float kPrecullMaxSide = 2048.0f;
  /// A draw piece stops pre-culling after a window of which it culled less than
  /// 1 / kPrecullMinCulled: there the survivors pay for the pre-cull on top of their set-up.
  static constexpr std::uint32_t kPrecullMinCulled = 4;

  /// The pre-cull of a draw with a vertex cache, in float lanes (twice as many as
  /// setup()'s): of triangles [t0, t1), those setup() would cull for lying outside the view, for
  /// zero area, for their facing, or for a box that is empty or holds no sample position, and
  /// whose corners are in the guard band with a box of at most kPrecullMaxSide, are counted in
  /// `stats` as setup() counts them. The others' indices go to `ids` in order (room for
  /// t1 - t0 + kFloatLanes); returns their number. A distant mesh's triangles are nearly all
  /// culled here, from the first 16 bytes of each corner's record, without a set-up.
  static int precull(const TriangleFrontEnd& scalar, const VertexCache& cache, std::uint32_t t0,
                     std::uint32_t t1, std::uint32_t* ids, FrontStats& stats) {
    namespace vc = vertex_code;
    static_assert(offsetof(ProjectedVertex, px) == 0 && offsetof(ProjectedVertex, py) == 4 &&
                  offsetof(ProjectedVertex, code) == 12);
    const DrawState& state = scalar.fetch.draw.state;
    alignas(64) std::int32_t iota[kFloatLanes];
    for (int l = 0; l < kFloatLanes; ++l) iota[l] = l;
    const Iv lane = Iv::load_aligned(iota);
    int kept = 0;
    for (std::uint32_t t = t0; t < t1; t += kFloatLanes) {
      const int n = static_cast<int>(std::min<std::uint32_t>(kFloatLanes, t1 - t));
      const std::uint32_t valid = (1u << n) - 1;
      // Each corner's record; the lanes past n repeat triangle t + n - 1. The records' first
      // 16 bytes (px, py, z, code) are loaded whole and transposed into lanes.
      const void* rows[3][kFloatLanes];
      for (int l = 0; l < kFloatLanes; ++l) {
        const std::uint32_t tri = t + static_cast<std::uint32_t>(std::min(l, n - 1));
        for (int k = 0; k < 3; ++k) rows[k][l] = &cache.data[scalar.fetch.vertex(tri, k)];
      }
      Fv px[3], py[3];
      Iv all(-1), any(0);
      for (int k = 0; k < 3; ++k) {
        Fv head[4];
        simd::Records<A>::heads(rows[k], head);
        px[k] = head[0];
        py[k] = head[1];
        const Iv code = xsimd::bitwise_cast<Iv>(head[3]);
        all &= code;
        any |= code;
      }
      // The classes of fetch_cached() and setup(), in the order setup() counts them.
      const std::uint32_t nonfinite = M::bits((any & Iv(vc::kNonFinite)) != Iv(0));
      const std::uint32_t clip = M::bits((any & Iv(vc::kClip)) != Iv(0));
      const std::uint32_t outside =
          valid & ~nonfinite & M::bits((all & Iv(vc::kClipPlanes)) != Iv(0));
      const Fv minx = xsimd::min(xsimd::min(px[0], px[1]), px[2]);
      const Fv maxx = xsimd::max(xsimd::max(px[0], px[1]), px[2]);
      const Fv miny = xsimd::min(xsimd::min(py[0], py[1]), py[2]);
      const Fv maxy = xsimd::max(xsimd::max(py[0], py[1]), py[2]);
      const Fv side(kPrecullMaxSide);
      const std::uint32_t settled = valid & ~(nonfinite | clip | outside) &
                                    M::bits(maxx - minx <= side && maxy - miny <= side);
      const Fv area2 = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
      const std::uint32_t degenerate = settled & M::bits(area2 == Fv(0.0f));
      const std::uint32_t face =
          settled & ~degenerate &
          M::bits(culled_by_face(facing_viewer(area2 < Fv(0.0f), state), state));
      const PixelBox<Fv> box = pixel_box(minx, maxx, miny, maxy, scalar.area, scalar.spots);
      const std::uint32_t rest = settled & ~(degenerate | face);
      const std::uint32_t empty = rest & M::bits(box.empty);
      const std::uint32_t no_sample = rest & ~empty & M::bits(!box.holds);
      const std::uint32_t culled = outside | degenerate | face | empty | no_sample;
      stats.in += static_cast<std::uint64_t>(std::popcount(culled));
      stats.outside += static_cast<std::uint64_t>(std::popcount(outside | empty));
      stats.degenerate += static_cast<std::uint64_t>(std::popcount(degenerate));
      stats.culled_face += static_cast<std::uint64_t>(std::popcount(face));
      stats.no_sample += static_cast<std::uint64_t>(std::popcount(no_sample));
      const std::uint32_t survivors = valid & ~culled;
      M::compress(Iv(static_cast<std::int32_t>(t)) + lane, survivors)
          .store_unaligned(reinterpret_cast<std::int32_t*>(ids + kept));
      kept += std::popcount(survivors);
    }
    return kept;
  }

  /// Whether every index in `indices` is below `limit`: their maximum, in lanes. A chunk's
  /// indices are checked before its triangles read them, and stay in the cache for them.
  template <class T>
  static bool all_below(std::span<const T> indices, std::uint32_t limit) {
    using V = xsimd::batch<T, A>;
    constexpr std::size_t L = V::size;
    V m0(T{0}), m1(T{0});
    std::size_t i = 0;
    for (; i + 2 * L <= indices.size(); i += 2 * L) {
      m0 = xsimd::max(m0, V::load_unaligned(indices.data() + i));
      m1 = xsimd::max(m1, V::load_unaligned(indices.data() + i + L));
    }
    alignas(64) T lanes[L];
    xsimd::max(m0, m1).store_aligned(lanes);
    T m = *std::max_element(lanes, lanes + L);
    for (; i < indices.size(); ++i) m = std::max(m, indices[i]);
    return m < limit;
  }

  /// Whether triangles [begin, end) of `draw` name only vertices it has.
  static bool indices_in_range(const Draw& draw, std::uint32_t begin, std::uint32_t end) {
    const auto first = 3 * std::size_t{begin}, count = 3 * std::size_t{end - begin};
    const auto limit = static_cast<std::uint32_t>(vertex_count(draw));
    if (draw.indices.is_16_bit())
      return limit > 0xffffu || all_below(draw.indices.narrow().subspan(first, count), limit);
    return all_below(draw.indices.wide().subspan(first, count), limit);
  }

  /// run_front_end() with the common case in lanes.
  static void run(const Draw& draw, std::uint32_t draw_index, std::uint32_t begin,
                  std::uint32_t end, int width, int height, std::vector<TriangleSetup>& out,
                  FrontStats& stats, PlaneArray* planes, int samples, const VertexCache* cache) {
    if (!draw.indices.empty() && !indices_in_range(draw, begin, end)) {
      stats.index_out_of_range = true;
      return;
    }
    TriangleFrontEnd scalar(draw, draw_index, width, height, out, stats, planes, samples);
    if (cache && cache->empty()) cache = nullptr;
    const bool shaded = scalar.per_vertex || scalar.nvary > 0;
    // Batch i is fetched into vertices[i % 2] while batch i - 1 is set up. setup()'s vector loads
    // then find fetch()'s scalar stores in the cache rather than still in flight: a load that
    // spans several in-flight stores waits for them all (store forwarding fails). With the build
    // flag of simd/CMakeLists.txt that removes the same wait inside setup(), ms_setup on
    // random-small (1 thread) went from 6.6 to 6.0 ms on AVX2, 5.2 to 5.1 ms on AVX-512.
    Vertices vertices[2];
    Results r;               // every field a batch reads is written by that batch first
    TriangleSetup batch[N];  // the drawn lanes' setups, before each is finished and appended
    // The triangles go through set-up in segments: [begin, end) at once, or, for a draw with a
    // vertex cache, window by window the pre-cull's survivors (listed in `ids`), until a window
    // culls too few and the rest of the range is one segment.
    std::uint32_t ids[kPrecullWindow + kFloatLanes];
    bool precull_on = cache != nullptr;
    for (std::uint32_t next = begin; next < end;) {
      const std::uint32_t first = next;
      std::uint32_t count = end - next;
      const std::uint32_t* listed = nullptr;
      if (precull_on) {
        next = std::min(end, first + (first == begin ? kPrecullFirstWindow : kPrecullWindow));
        count = static_cast<std::uint32_t>(precull(scalar, *cache, first, next, ids, stats));
        listed = ids;
        precull_on = (next - first - count) * kPrecullMinCulled >= next - first;
      } else {
        next = end;
      }
      const auto fetch_batch = [&](std::uint32_t p, Vertices& v) {
        const int n = static_cast<int>(std::min<std::uint32_t>(N, count - p));
        if (!cache) return fetch(scalar, first + p, n, v);
        std::uint32_t corners[3 * N] = {};
        if (listed) {
          listed_indices(scalar.fetch, listed + p, n, corners);
        } else {
          batch_indices(draw.indices, first + p, n, corners);
        }
        fetch_cached(*cache, corners, v);
      };
      // Batch p + N is fetched while batch p is set up (the first pass fetches batch 0 too), from
      // one call: fetch_batch() then inlines.
      std::uint32_t fetched = 0;
      int cur = 0;
      for (std::uint32_t p = 0; p < count; p += N, cur ^= 1) {
        const int n = static_cast<int>(std::min<std::uint32_t>(N, count - p));
        for (; fetched <= p + N && fetched < count; fetched += N)
          fetch_batch(fetched, vertices[(fetched / N) % 2]);
        setup(vertices[cur], scalar.fetch, scalar.area, shaded, scalar.spots, r);
        const std::uint32_t drawn =
            ((1u << n) - 1) & ~(r.scalar | r.outside | r.face | r.degenerate | r.no_sample);
        if (drawn && scalar.per_vertex) {
          if (vertices[cur].cached) unpack_colors(vertices[cur]);
          color_planes(vertices[cur], drawn, r);
        }
        if (drawn && scalar.nvary > 0) varying_planes(scalar, vertices[cur], r);
        // The culled lanes are only counted; the scalar and drawn ones append their setups in
        // submission order.
        const std::uint32_t lanes = (1u << n) - 1;
        stats.in += static_cast<std::uint64_t>(std::popcount(lanes & ~r.scalar));
        stats.outside += static_cast<std::uint64_t>(std::popcount(lanes & r.outside));
        stats.culled_face += static_cast<std::uint64_t>(std::popcount(lanes & r.face));
        stats.degenerate += static_cast<std::uint64_t>(std::popcount(lanes & r.degenerate));
        stats.no_sample += static_cast<std::uint64_t>(std::popcount(lanes & r.no_sample));
        stats.drawn += static_cast<std::uint64_t>(std::popcount(drawn));
        if (drawn) build_setups(r, batch);
        for (std::uint32_t bits = (r.scalar & lanes) | drawn; bits; bits &= bits - 1) {
          const auto l = static_cast<std::uint32_t>(std::countr_zero(bits));
          const std::uint32_t t = listed ? listed[p + l] : first + p + l;
          if ((r.scalar >> l) & 1u) {
            scalar.run(t);
            continue;
          }
          const Rgba8 flat =
              draw.color_source == ColorSource::kPerTriangle ? draw.colors[t] : draw.color;
          TriangleSetup& ts = out.emplace_back(batch[l]);
          finish(r, vertices[cur], static_cast<int>(l), scalar.area, scalar.per_vertex, flat,
                 draw_index, planes, ts);
          if (scalar.nvary > 0) store_varyings(r, static_cast<int>(l), scalar.nvary, *planes, ts);
        }
      }
    }
  }

  /// The vertex stage's entry point (front::VertexStage).
  static void vertex_stage(const Draw& draw, int width, int height, std::uint32_t begin,
                           std::uint32_t end, const VertexCache& cache) {
    project_vertices(draw, width, height, begin, end, cache);
  }
};

}  // namespace mosaic::front
