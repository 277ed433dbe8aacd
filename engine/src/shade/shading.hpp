// shade/shading.hpp — what the rasterizers need to colour a sample of a draw that has a shader or
// blending: the draw's shader in plain form, perspective-correct varyings, and source-over
// blending in 8 bits. Shared by the reference (scalar, here) and the tile kernels (lane-wise, in
// shade/shade_simd.hpp, in the same order of operations).
//
// Takes: a triangle's setup and its draw. Gives: the colour of one pixel or sample.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "front/setup.hpp"
#include "mosaic/draw.hpp"
#include "mosaic/shader.hpp"

namespace mosaic::shade {

// The tile kernels store and load whole SIMD vectors (up to 64 bytes) in a batch's arrays.
static_assert(offsetof(ShaderInput, y) % 64 == 0 && offsetof(ShaderInput, varying) % 64 == 0 &&
              offsetof(ShaderInput, ddx) % 64 == 0 && offsetof(ShaderInput, ddy) % 64 == 0);
static_assert(offsetof(ShaderOutput, g) % 64 == 0 && offsetof(ShaderOutput, b) % 64 == 0 &&
              offsetof(ShaderOutput, a) % 64 == 0);

/// A draw's shading, as the kernels read it (one per draw of the frame).
struct DrawShading {
  ShaderFunction function = nullptr;  ///< nullptr: colour from the setup (flat or vertex colour)
  const void* state = nullptr;
  int varyings = 0;          ///< varying planes per triangle (Draw::varyings.size())
  bool derivatives = false;  ///< the shader reads ShaderInput::ddx and ddy
  bool discards = false;     ///< the shader may discard: depth is written after it runs
  /// Whether the draw leaves the specialised colour kernels: it has a shader or blends.
  bool generic = false;
};

/// Fills `out` with the shading of every draw of a frame; leaves it empty when no draw needs the
/// generic path, so that the kernels test one size per triangle and nothing else. `out` is the
/// caller's, so that a renderer reuses its memory frame after frame.
void frame_shading(std::span<const Draw> draws, std::vector<DrawShading>& out);

/// round(x / 255) for 0 <= x <= 255 · 255, exactly (x / 255 is never a tie: 255 is odd), with
/// shifts only, so that SIMD lanes compute it the same way: t = x + 128, (t + (t >> 8)) >> 8.
constexpr std::uint32_t div255(std::uint32_t x) {
  const std::uint32_t t = x + 128;
  return (t + (t >> 8)) >> 8;
}

/// BlendMode::kSourceOver of `src` over `dst` (straight alpha, 8 bits).
constexpr Rgba8 blend_over(Rgba8 src, Rgba8 dst) {
  const std::uint32_t a = src.a, ia = 255 - a;
  return {static_cast<std::uint8_t>(div255(src.r * a + dst.r * ia)),
          static_cast<std::uint8_t>(div255(src.g * a + dst.g * ia)),
          static_cast<std::uint8_t>(div255(src.b * a + dst.b * ia)),
          static_cast<std::uint8_t>(div255(255 * a + dst.a * ia))};
}

/// Varying k of triangle `t` at (x, y): its attr·q plane over its q plane (planes[planes_base]),
/// as colour is.
inline float varying_at(const front::TriangleSetup& t, const front::Plane* planes, int k, float q,
                        float x, float y) {
  return front::eval_plane(planes[t.planes_base + 1 + static_cast<std::uint32_t>(k)], t.x0, t.y0, x,
                           y) /
         q;
}

/// The derivative of a varying v = P / Q along one axis, from the slopes of its planes there:
/// (dP - v dQ) / Q, in this order on every path.
inline float varying_slope(float dp, float dq, float v, float q) { return (dp - v * dq) / q; }

/// All ones if triangle `t` faces the viewer, else 0: ANDed with lane bits,
/// ShaderInput::front_facing.
inline std::uint32_t front_lanes(const front::TriangleSetup& t) { return t.back_face() ? 0u : ~0u; }

/// A shader's colour at one pixel or sample: kept (RGBA8), or discarded.
struct Shaded {
  Rgba8 color;
  bool discarded = false;
};

/// One shader output channel to 8 bits: to_unorm8(v * 255).
inline std::uint8_t output_to_unorm8(float v) { return front::to_unorm8(v * 255.0f); }

/// The colour of triangle `t` of a generic draw at (x, y), for the reference: the shader run on a
/// batch whose only active lane is `lane` (the lane the tile kernels give this pixel), or the
/// setup's colour without a shader; discarded only if the shader declares discards and drops it.
Shaded shade_one(const front::TriangleSetup& t, const DrawShading& s, const front::Plane* planes,
                 float x, float y, int lane);

}  // namespace mosaic::shade
