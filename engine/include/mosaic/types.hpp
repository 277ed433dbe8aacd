// mosaic/types.hpp — small value types and enums shared by the whole public API.
//
// Takes: nothing. Gives: Rgba8, the draw-state enums (BlendMode too), Space, Isa, and the size
// limit of a target.
#pragma once

#include <cstdint>

namespace mosaic {

/// Largest width or height of a render target, in pixels. With the 16.8 vertex format and the
/// guard band of kGuardBandPx (front/fixed_point.hpp) this keeps every edge function in 64 bits.
inline constexpr int kMaxTargetSize = 16384;

/// An 8-bit-per-channel colour, straight (not premultiplied) alpha.
struct Rgba8 {
  std::uint8_t r = 0, g = 0, b = 0;  ///< red, green, blue, 0 to 255
  std::uint8_t a = 255;              ///< alpha, stored with the colour (255 = opaque)
  friend bool operator==(const Rgba8&, const Rgba8&) = default;
};

/// A rectangle of whole pixels, [x, x + width) × [y, y + height): y down, origin top-left.
struct PixelRect {
  int x = 0, y = 0;           ///< its top-left pixel
  int width = 0, height = 0;  ///< its size in pixels
  friend bool operator==(const PixelRect&, const PixelRect&) = default;
};

/// What a frame's samples hold before its first triangle (Frame::color_load, depth_load).
enum class LoadOp : std::uint8_t {
  kClear,  ///< the target's clear value (RenderTarget::set_clear())
  kLoad,   ///< what the target's previous frame left there: this frame draws over it
};

/// Per-sample depth comparison: a sample is written when `incoming OP stored` holds.
enum class DepthTest : std::uint8_t {
  kLess,          ///< the default: nearer (smaller) depth wins, first writer wins ties
  kLessEqual,     ///< nearer or equal wins, last writer wins ties
  kGreater,       ///< for reversed-Z (clear depth to 0)
  kGreaterEqual,  ///< reversed-Z, last writer wins ties
  kAlways,        ///< no test: draw order decides
};

/// Which triangles are discarded before rasterization.
enum class CullMode : std::uint8_t {
  kNone,   ///< draw both faces
  kBack,   ///< discard triangles facing away (see FrontFace)
  kFront,  ///< discard triangles facing the viewer
};

/// Which winding is the front face, as the triangle appears on screen. OpenGL's default,
/// counter-clockwise in y-up NDC, also appears counter-clockwise on screen.
enum class FrontFace : std::uint8_t {
  kCounterClockwise,  ///< counter-clockwise on screen faces the viewer (OpenGL's default)
  kClockwise,         ///< clockwise on screen faces the viewer
};

/// How a sample lying exactly on an edge is decided. Both rules make two triangles that share an
/// edge cover each such sample exactly once.
enum class FillRule : std::uint8_t {
  kD3D,     ///< top-left rule: samples on a top or left edge are inside (Direct3D, Vulkan)
  kOpenGL,  ///< as OpenGL implementations (llvmpipe) do in y-down window space: bottom or left
};

/// Where a draw's colour comes from.
enum class ColorSource : std::uint8_t {
  kConstant,     ///< Draw::color for every triangle
  kPerTriangle,  ///< Draw::colors[triangle]
  kPerVertex,    ///< Draw::colors[vertex], interpolated perspective-correctly
};

/// How a draw's colour combines with the colour already in a sample, in draw order.
enum class BlendMode : std::uint8_t {
  kNone,  ///< replace it
  /// Source-over with straight alpha, in 8 bits per channel: with the draw's colour s (alpha a)
  /// and the stored colour d, each of r, g, b becomes round((s·a + d·(255 − a)) / 255) and alpha
  /// round((255·a + d_alpha·(255 − a)) / 255), rounded to nearest (there are no ties).
  kSourceOver,
};

/// The coordinate space of Draw::positions.
enum class Space : std::uint8_t {
  kClip,  ///< homogeneous clip space: x, y in [-w, w] visible, depth z/w in [0, 1], w > 0
  /// Window-homogeneous pixels, y down, origin top-left: (x, y, z, w) is the pixel (x / w, y / w)
  /// at depth z / w in [0, 1]. Plain screen triangles have w = 1 (a .tris file's always do).
  /// Another w means what clip space's does: it weights the interpolation perspective-correctly,
  /// and w <= 0 is behind the eye (clipped at the near plane z >= 0). The draw equals the clip-
  /// space draw of x_clip = x / (width / 2) - w, y_clip = w - y / (height / 2).
  kScreen,
};

/// The instruction set the tile kernels run with.
enum class Isa : std::uint8_t {
  kAuto,       ///< the best the CPU supports
  kReference,  ///< the exact scalar reference rasterizer (the oracle; slow)
  kSse41,      ///< SSE4.1 tile kernels, 4 lanes of 32 bits
  kAvx2,       ///< AVX2 tile kernels, 8 lanes
  kAvx512,     ///< AVX-512 (F, CD, DQ, BW, VL) tile kernels, 16 lanes
};

/// Short lower-case name of an ISA ("auto", "reference", "sse4.1", "avx2", "avx512").
const char* to_string(Isa isa) noexcept;

}  // namespace mosaic
