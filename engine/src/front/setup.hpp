// front/setup.hpp — snapping and triangle setup.
//
// Takes: three window-space vertices (pixels, after the perspective divide) with depth, 1/w and
// colour. Gives: a TriangleSetup — three exact integer edge functions with the fill rule folded
// in, a pixel bounding box, and float planes for depth and colour — or nothing for a triangle
// that is culled. Every rasterizer (reference and SIMD) consumes the same TriangleSetup, so
// they round depth and colour identically.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <optional>
#include <utility>
#include <vector>

#include "front/clip.hpp"
#include "front/fixed_point.hpp"
#include "mosaic/draw.hpp"
#include "mosaic/types.hpp"
#include "raster/sample_patterns.hpp"

namespace mosaic::front {

/// A vertex after the perspective divide, before snapping.
struct ScreenVertex {
  double x = 0, y = 0;                         ///< pixels, y down
  float z = 0;                                 ///< depth in [0, 1]
  double q = 1;                                ///< 1 / w, for perspective-correct colour
  std::array<double, kColorChannels> color{};  ///< 0..255 per channel
};

/// E(x, y) = a*x + b*y + c over 16.8 coordinates (front/fixed_point.hpp has the bit budget).
/// A sample is inside the edge iff E >= 0: the fill rule's bias is already folded into c.
struct EdgeFunction {
  std::int64_t a = 0, b = 0, c = 0;
  constexpr std::int64_t operator()(std::int64_t x, std::int64_t y) const {
    return a * x + b * y + c;
  }
};

/// A linear function of the pixel position, anchored at the snapped first vertex (x0, y0):
/// value(x, y) = (base + ddx * (x - x0)) + ddy * (y - y0), evaluated in float32 in exactly this
/// order by every rasterizer (the build disables FMA contraction). Trivial, so that arrays of
/// planes copy and grow as plain memory: `Plane{}` is zero, a `Plane p;` is unset.
struct Plane {
  float base, ddx, ddy;
};

/// An allocator whose resize() leaves the new elements of a trivial type unset, for arrays that
/// the caller fills at once after growing them.
template <class T>
struct GrowUnset : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = GrowUnset<U>;
  };
  GrowUnset() = default;
  template <class U>
  GrowUnset(const GrowUnset<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// A chunk's out-of-line planes (see TriangleSetup): the front ends grow it by a triangle's
/// planes and then store them, without zeroing them first.
using PlaneArray = std::vector<Plane, GrowUnset<Plane>>;

/// No coefficient is infinite or NaN: a plane that fails is replaced by a constant.
inline bool is_finite(const Plane& p) {
  return std::isfinite(p.base) && std::isfinite(p.ddx) && std::isfinite(p.ddy);
}

inline float eval_plane(const Plane& p, float x0, float y0, float x, float y) {
  const float v = p.base + p.ddx * (x - x0);
  return v + p.ddy * (y - y0);
}

/// Clamps like SSE's maxps / minps with the constant second: NaN becomes `lo`.
inline float clamp_like_simd(float v, float lo, float hi) {
  const float m = v > lo ? v : lo;
  return m < hi ? m : hi;
}

/// planes_base of a triangle without planes: flat colour (`color`), and no shader varyings.
inline constexpr std::uint32_t kNoPlanes = UINT32_MAX;

/// Planes of an interpolated-colour triangle in its chunk's plane array: q, then c_q per channel.
inline constexpr std::uint32_t kColorPlanes = static_cast<std::uint32_t>(1 + kColorChannels);

/// Everything every tile kernel reads for every triangle, and nothing else: two cache lines (the
/// kernels prefetch exactly those), aligned so that they never straddle a third. The front end
/// writes one per triangle, so every byte here is written once and read back once per frame;
/// what only some triangles need lives out of line in the chunk's plane array (bin::Chunk::planes,
/// a PlaneArray), from index planes_base:
/// - interpolated vertex colour (not a shader draw): planes[planes_base] is q, 1/w normalised
///   so that its largest vertex value is 1, and planes[planes_base + 1 + ch] is colour·q of
///   channel ch (kColorPlanes in all); colour = (colour·q) / q;
/// - a shader draw with varyings: planes[planes_base] is q as above, and
///   planes[planes_base + 1 + k] is varying k·q;
/// - otherwise (flat colour, or a shader draw without varyings) planes_base is kNoPlanes.
struct alignas(64) TriangleSetup {
  std::array<EdgeFunction, 3> edge;
  float x0 = 0, y0 = 0;                    ///< plane anchor: the snapped first vertex, in pixels
  int bx0 = 0, by0 = 0, bx1 = 0, by1 = 0;  ///< pixels [bx0, bx1) × [by0, by1) that may be covered
  Plane z{};
  float z_min = 0, z_max = 0;  ///< depth is clamped to the vertices' range
  Rgba8 color;                 ///< the colour when planes_base is kNoPlanes
  /// Bits 0..30: the index of the draw, for its state; bit 31: the triangle is a back face (its
  /// winding is not DrawState::front_face). One word, written with one store.
  std::uint32_t draw_word = 0;
  std::uint32_t planes_base = kNoPlanes;  ///< see above

  static constexpr std::uint32_t kDrawBits = 0x7fff'ffffu;
  std::uint32_t draw() const { return draw_word & kDrawBits; }
  bool back_face() const { return (draw_word >> 31) != 0; }
  void set_draw(std::uint32_t index, std::uint32_t back) { draw_word = index | (back << 31); }
};

static_assert(sizeof(TriangleSetup) == 128, "two cache lines: see above");

/// Draws a frame may hold: TriangleSetup keeps a draw's index in 31 bits.
inline constexpr std::uint32_t kMaxDraws = TriangleSetup::kDrawBits;

/// Whether a triangle without a shader is shaded with `color` (no planes) or interpolates.
inline bool is_flat(const TriangleSetup& t) { return t.planes_base == kNoPlanes; }

/// keep_color_planes()'s append alone, for planes known to be finite (the SIMD front end tests
/// them in lanes).
inline void append_color_planes(const std::array<Plane, kColorPlanes>& p, PlaneArray& planes,
                                TriangleSetup& out) {
  out.planes_base = static_cast<std::uint32_t>(planes.size());
  planes.insert(planes.end(), p.begin(), p.end());
}

/// Appends an interpolated-colour triangle's planes (q, then colour·q per channel) to `planes`
/// and points out.planes_base at them, unless one overflows float (a sub-1/65536 px² sliver with
/// extreme colour slopes): that triangle stays flat, and its caller gives it its first vertex's
/// colour. Shared by the scalar and SIMD front ends, which must agree bit for bit.
inline void keep_color_planes(const std::array<Plane, kColorPlanes>& p, PlaneArray& planes,
                              TriangleSetup& out) {
  for (const Plane& pl : p)
    if (!is_finite(pl)) return;
  append_color_planes(p, planes, out);
}

/// The snapped, oriented corners and area a triangle's planes are built on (setup_triangle()
/// gives it, setup_varyings() takes it). Left uninitialised until setup_triangle() fills it: the
/// front end makes one per triangle, and zeroing it cost every draw, shader or not.
struct PlaneBasis {
  std::array<double, 3> X, Y;  ///< snapped corners in pixels, clockwise on screen
  std::array<int, 3> idx;      ///< which input vertex each corner is
  double area_px2;             ///< twice the area, in px²
};

/// Depth of the triangle at a sample position (pixels).
inline float sample_depth(const TriangleSetup& t, float x, float y) {
  return clamp_like_simd(eval_plane(t.z, t.x0, t.y0, x, y), t.z_min, t.z_max);
}

/// Colour of the triangle at a shading position (pixels); `planes` is its chunk's plane array.
Rgba8 shade(const TriangleSetup& t, const Plane* planes, float x, float y);

/// Converts an interpolated channel value to 8 bits: clamp to [0, 255] (NaN to 0), round half up.
inline std::uint8_t to_unorm8(float v) {
  return static_cast<std::uint8_t>(static_cast<int>(clamp_like_simd(v, 0.0f, 255.0f) + 0.5f));
}

/// Why setup produced no triangle. kNoSample: the box holds no sample position; kNoCoveredSample:
/// it holds a few, and the triangle covers none of them (front/sample_cull.hpp).
enum class SetupReject { kNone, kFace, kDegenerate, kOutside, kNoSample, kNoCoveredSample };

/// A pixel's sample positions from its corner in 16.8 units (raster::sample_x_fixed(0, o)), for
/// setup's cull of triangles whose box holds no sample position; `count` 0 culls nothing.
struct SampleSpots {
  /// Positions a pixel can have: the largest pattern's.
  static constexpr int kMax = static_cast<int>(raster::kPattern16.size());
  int count = 0;
  std::array<std::int32_t, kMax> x{}, y{};
  /// The spots of the standard pattern of `samples` samples (0: none).
  static SampleSpots of(int samples) {
    SampleSpots sp;
    for (const raster::SampleOffset o : raster::sample_pattern(samples)) {
      sp.x[sp.count] = static_cast<std::int32_t>(raster::sample_x_fixed(0, o));
      sp.y[sp.count++] = static_cast<std::int32_t>(raster::sample_y_fixed(0, o));
    }
    return sp;
  }
};

/// Whether some sample position of `sp` lies in the closed box [minx, maxx] × [miny, maxy] (16.8)
/// within the pixels [bx0, bx1) × [by0, by1): sample s of column px is at px * 256 + x[s], so the
/// columns holding one in range are ceil((minx - x[s]) / 256) .. floor((maxx - x[s]) / 256).
inline bool box_holds_sample(const SampleSpots& sp, std::int32_t minx, std::int32_t maxx,
                             std::int32_t miny, std::int32_t maxy, int bx0, int bx1, int by0,
                             int by1) {
  for (int s = 0; s < sp.count; ++s) {
    const int cx0 = std::max(bx0, -((sp.x[s] - minx) >> kSubpixelBits));
    const int cx1 = std::min(bx1 - 1, (maxx - sp.x[s]) >> kSubpixelBits);
    const int cy0 = std::max(by0, -((sp.y[s] - miny) >> kSubpixelBits));
    const int cy1 = std::min(by1 - 1, (maxy - sp.y[s]) >> kSubpixelBits);
    if (cx0 <= cx1 && cy0 <= cy1) return true;
  }
  return false;
}

/// Rounds a pixel coordinate to 16.8, to nearest, a tie going up (towards +infinity) so that a
/// shape moved by whole pixels snaps to the same shape. |x| is at most kGuardBandPx after clipping;
/// anything beyond (only rounding on extreme input) is clamped to it. x must not be NaN.
std::int32_t snap(double px);

struct DrawArea;  // front/draw_area.hpp

/// Snaps and sets up a triangle in `area`'s viewport pixels, keeps its box to the area's clip
/// rectangle, and moves it into the target's pixels.
/// `flat_color` is used when `per_vertex_color` is false. Differing vertex colours append
/// kColorPlanes planes to `planes`; without `planes` (callers that use only coverage and depth)
/// none are set up, and the triangle gets its first vertex's colour, as one whose planes overflow
/// float does. `basis`, when given, receives the corners the planes were built on (for
/// setup_varyings() and sort_depth()). With `spots`, a triangle whose box holds none of them
/// (kNoSample), or that covers none of the few its box holds (kNoCoveredSample), is rejected
/// before its planes are built.
SetupReject setup_triangle(const std::array<ScreenVertex, 3>& v, const DrawState& state,
                           const DrawArea& area, bool per_vertex_color, Rgba8 flat_color,
                           TriangleSetup& out, PlaneArray* planes = nullptr,
                           PlaneBasis* basis = nullptr, const SampleSpots* spots = nullptr);

/// The painter's algorithm's key of a set-up triangle: its mean vertex depth, summed in the
/// oriented order. Not stored in TriangleSetup: only the painter's path needs it.
inline float sort_depth(const std::array<ScreenVertex, 3>& v, const PlaneBasis& basis) {
  const auto& i = basis.idx;
  return static_cast<float>((double{v[i[0]].z} + double{v[i[1]].z} + double{v[i[2]].z}) / 3.0);
}

/// Appends q and `count` varying planes of a set-up triangle to `planes` and points
/// out.planes_base at them (kNoPlanes when count is 0). values[i][k] is varying k at input vertex
/// i (v[i]). Planes that overflow float (a tiny sliver with steep varyings) become the constants
/// of the first corner.
void setup_varyings(const std::array<ScreenVertex, 3>& v, const PlaneBasis& basis,
                    const std::array<const double*, 3>& values, int count, TriangleSetup& out,
                    PlaneArray& planes);

}  // namespace mosaic::front
