// mosaic/draw.hpp — one draw call: triangles, their attributes, their colour or shader, and the
// state they are drawn with.
//
// Takes: nothing (plain data). Gives: Draw and DrawState, which Renderer::render() consumes.
// A Draw only points at the caller's buffers (std::span); they must stay alive for the
// duration of the Renderer::render() call that uses them, and no longer.
#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <span>

#include "mosaic/shader.hpp"
#include "mosaic/types.hpp"

namespace mosaic {

/// Fixed-function state of a draw.
struct DrawState {
  /// Which samples a triangle may write: those where `incoming depth OP stored depth` holds.
  DepthTest depth_test = DepthTest::kLess;
  /// Whether samples that pass the depth test store the triangle's depth (colour is written
  /// either way, unless color_write is off).
  bool depth_write = true;
  /// Whether samples that pass the depth test store the triangle's colour. Off makes a depth-only
  /// draw (an occluder pass): the fast path then runs a kernel that neither shades nor touches
  /// colour memory, and a frame whose draws all have it off keeps no colour at all (see
  /// RenderTarget::color() for what the image then holds).
  bool color_write = true;
  CullMode cull = CullMode::kNone;                      ///< which facing triangles to discard
  FrontFace front_face = FrontFace::kCounterClockwise;  ///< the winding that faces the viewer
  FillRule fill_rule = FillRule::kD3D;                  ///< who owns samples exactly on an edge
  /// How the colour combines with what the samples hold: replace, or source-over alpha in draw
  /// order (per sample, after the depth test; depth is written as without blending).
  BlendMode blend = BlendMode::kNone;
};

/// A list of triangles.
///
/// Positions come either as `positions` (xyzw in `space`), or as `positions_xyz` (object-space
/// xyz with w = 1) multiplied by `transform` into `space` (in double precision). Triangles are
/// `indices` taken three at a time, or vertices 0,1,2, 3,4,5, … when `indices` is empty.
///
/// The colour comes from `shader` when it is set (mosaic/shader.hpp), otherwise from
/// `color_source`. A shader reads varyings: attributes of the vertices (`attributes`,
/// `attribute_count` floats per vertex) interpolated perspective-correctly over the triangle; only
/// the attributes listed in `varyings` are interpolated.
///
/// Renderer::render() checks every draw before it draws any: counts that do not fit together
/// (an attribute buffer too short for the vertices, a varying past attribute_count, more than
/// kMaxVaryings varyings, fewer than the shader reads, varyings without a shader) throw
/// Error{kInvalidDraw}, an index past the last vertex Error{kIndexOutOfRange}.
/// Triangles with a NaN or infinite coordinate after the transform are culled and counted in
/// FrameStats::triangles_nonfinite; they never affect other triangles.
struct Draw {
  Space space = Space::kClip;            ///< the space of `positions`, or of `transform`'s results
  std::span<const glm::vec4> positions;  ///< xyzw in `space`; empty if positions_xyz is used
  std::span<const glm::vec3> positions_xyz;  ///< used instead of `positions` when non-empty
  glm::mat4 transform{1.0f};                 ///< applied to positions_xyz only
  std::span<const std::uint32_t> indices;    ///< size a multiple of 3; every index < vertex count

  ColorSource color_source = ColorSource::kConstant;  ///< which of the two fields below is read
  Rgba8 color{255, 255, 255, 255};                    ///< for kConstant
  std::span<const Rgba8> colors;  ///< one per triangle (kPerTriangle) or per vertex (kPerVertex)

  /// Per-vertex float attributes, interleaved: attribute a of vertex v is
  /// attributes[v * attribute_count + a]. At least vertex count × attribute_count floats.
  std::span<const float> attributes;
  std::uint32_t attribute_count = 0;  ///< floats per vertex in `attributes`
  /// The shader's inputs: varying k is attribute varyings[k]. At most kMaxVaryings, each below
  /// attribute_count, at least shader.varyings_read() of them; empty without a shader.
  std::span<const std::uint32_t> varyings;
  /// The fragment shader; empty (the default) colours the draw from color_source, with the
  /// renderer's specialised kernels.
  Shader shader;

  DrawState state;  ///< depth test and write, culling, fill rule, blending
};

}  // namespace mosaic
