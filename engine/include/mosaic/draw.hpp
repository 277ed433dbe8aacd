// mosaic/draw.hpp — one draw call: triangles, their attributes, their colour or shader, and the
// state they are drawn with.
//
// Takes: nothing (plain data). Gives: Draw and DrawState, which Renderer::render() consumes.
// A Draw only points at the caller's buffers (std::span); they must stay alive for the
// duration of the Renderer::render() call that uses them, and no longer.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <optional>
#include <ranges>
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
  /// RenderTarget::color() for what the image then holds). Its shader is not run, so a shader
  /// that discards discards nothing there: an alpha-tested depth-only pass is not supported.
  bool color_write = true;
  CullMode cull = CullMode::kNone;                      ///< which facing triangles to discard
  FrontFace front_face = FrontFace::kCounterClockwise;  ///< the winding that faces the viewer
  FillRule fill_rule = FillRule::kD3D;                  ///< who owns samples exactly on an edge
  /// How the colour combines with what the samples hold: replace, or source-over alpha in draw
  /// order (per sample, after the depth test; depth is written as without blending).
  BlendMode blend = BlendMode::kNone;
  /// Where the draw lands in the target: NDC [-1, 1]² maps to these pixels, and Space::kScreen
  /// coordinates count from its top-left corner. Nothing outside it is drawn, so a draw through
  /// a viewport equals the same draw into a target of the viewport's size, placed at (x, y).
  /// Unset, it is the whole target. Whole pixels: width and height 1 to kMaxTargetSize, x and y
  /// within ±kMaxTargetSize (it may reach past the target; that part is not drawn). Depth maps
  /// to [0, 1] as without a viewport.
  std::optional<PixelRect> viewport = std::nullopt;
  /// Coverage is clipped to these pixels, and the binner skips tiles outside them. Unset, there
  /// is no scissor. It may reach past the target (that part clips nothing) or be empty (the
  /// draw draws nothing); x, y, width and height within ±kMaxTargetSize, width and height >= 0.
  std::optional<PixelRect> scissor = std::nullopt;
};

/// A read-only view of size() elements of T, each stride() bytes after the one before: a whole
/// array of T, or one field of an array of interleaved vertex structs, read in place. Elements
/// are read by value (byte copies), so they need no alignment.
template <class T>
class StridedSpan {
 public:
  StridedSpan() = default;
  /// Every element of a contiguous range of T: a std::vector, std::span, std::array or array.
  template <std::ranges::contiguous_range R>
  requires std::same_as<std::ranges::range_value_t<R>, T> StridedSpan(
      const R& range)  // implicit, as std::span's is
      : bytes_(reinterpret_cast<const std::byte*>(std::ranges::data(range))),
        size_(std::ranges::size(range)),
        stride_(sizeof(T)) {}
  /// `count` elements, the first at `first`, each `stride_bytes` after the one before (at least
  /// sizeof(T); Renderer::render() rejects less).
  StridedSpan(const T* first, std::size_t count, std::size_t stride_bytes)
      : bytes_(reinterpret_cast<const std::byte*>(first)), size_(count), stride_(stride_bytes) {}

  T operator[](std::size_t i) const {
    T v;
    std::memcpy(&v, bytes_ + i * stride_, sizeof(T));
    return v;
  }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::size_t stride() const { return stride_; }  ///< bytes from one element to the next
  /// Elements [offset, offset + count), which must lie within this view.
  StridedSpan subspan(std::size_t offset, std::size_t count) const {
    StridedSpan s = *this;
    s.bytes_ += offset * stride_;
    s.size_ = count;
    return s;
  }

 private:
  const std::byte* bytes_ = nullptr;
  std::size_t size_ = 0;
  std::size_t stride_ = sizeof(T);
};

/// A read-only view of a draw's index buffer, of 32-bit or 16-bit indices.
class IndexSpan {
 public:
  IndexSpan() = default;
  /// Every index of a contiguous range of std::uint32_t or std::uint16_t.
  template <std::ranges::contiguous_range R>
  requires std::same_as<std::ranges::range_value_t<R>, std::uint32_t> ||
      std::same_as<std::ranges::range_value_t<R>, std::uint16_t>
      IndexSpan(const R& range)  // implicit, as std::span's is
      : size_(std::ranges::size(range)) {
    if constexpr (std::same_as<std::ranges::range_value_t<R>, std::uint32_t>) {
      wide_ = std::ranges::data(range);
    } else {
      narrow_ = std::ranges::data(range);
    }
  }

  std::uint32_t operator[](std::size_t i) const { return wide_ ? wide_[i] : narrow_[i]; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  bool is_16_bit() const { return narrow_ != nullptr; }
  /// The indices as stored: the 32-bit ones, or the 16-bit ones; the other span is empty.
  std::span<const std::uint32_t> wide() const { return {wide_, wide_ != nullptr ? size_ : 0}; }
  std::span<const std::uint16_t> narrow() const {
    return {narrow_, narrow_ != nullptr ? size_ : 0};
  }

 private:
  const std::uint32_t* wide_ = nullptr;
  const std::uint16_t* narrow_ = nullptr;
  std::size_t size_ = 0;
};

/// A list of triangles.
///
/// Positions come either as `positions` (xyzw in `space`), or as `positions_xyz` (object-space
/// xyz with w = 1) multiplied by `transform` into `space` (in double precision). Triangles are
/// `indices` (32- or 16-bit) taken three at a time, or vertices 0,1,2, 3,4,5, … when `indices`
/// is empty. An interleaved vertex buffer is read in place: positions through a StridedSpan of
/// its position field, attributes with attribute_stride.
///
/// The colour comes from `shader` when it is set (mosaic/shader.hpp), otherwise from
/// `color_source`. A shader reads varyings: attributes of the vertices (`attributes`,
/// `attribute_count` floats per vertex) interpolated perspective-correctly over the triangle; only
/// the attributes listed in `varyings` are interpolated.
///
/// Renderer::render() checks every draw before it draws any: counts that do not fit together
/// (an attribute buffer too short for the vertices, an attribute stride below attribute_count,
/// a position stride below the position's size, a varying past attribute_count, more than
/// kMaxVaryings varyings, fewer than the shader reads, varyings without a shader, a viewport or
/// scissor out of DrawState's bounds) throw
/// Error{kInvalidDraw}, an index past the last vertex Error{kIndexOutOfRange}.
/// Triangles with a NaN or infinite coordinate after the transform are culled and counted in
/// FrameStats::triangles_nonfinite; they never affect other triangles.
struct Draw {
  Space space = Space::kClip;            ///< the space of `positions`, or of `transform`'s results
  StridedSpan<glm::vec4> positions;      ///< xyzw in `space`; empty if positions_xyz is used
  StridedSpan<glm::vec3> positions_xyz;  ///< used instead of `positions` when non-empty
  glm::mat4 transform{1.0f};             ///< applied to positions_xyz only
  IndexSpan indices;                     ///< size a multiple of 3; every index < vertex count

  ColorSource color_source = ColorSource::kConstant;  ///< which of the two fields below is read
  Rgba8 color{255, 255, 255, 255};                    ///< for kConstant
  std::span<const Rgba8> colors;  ///< one per triangle (kPerTriangle) or per vertex (kPerVertex)

  /// Per-vertex float attributes, interleaved: attribute a of vertex v is
  /// attributes[v * attribute_stride + a] (attribute_count for a stride of 0). At least
  /// (vertex count - 1) × stride + attribute_count floats.
  std::span<const float> attributes;
  std::uint32_t attribute_count = 0;  ///< floats per vertex that are attributes
  /// Floats from one vertex's attributes to the next's: 0 (= attribute_count) or at least
  /// attribute_count, e.g. sizeof(Vertex) / 4 for attributes inside an interleaved Vertex.
  std::uint32_t attribute_stride = 0;
  /// The shader's inputs: varying k is attribute varyings[k]. At most kMaxVaryings, each below
  /// attribute_count, at least shader.varyings_read() of them; empty without a shader.
  std::span<const std::uint32_t> varyings;
  /// The fragment shader; empty (the default) colours the draw from color_source, with the
  /// renderer's specialised kernels.
  Shader shader;

  DrawState state;  ///< depth test and write, culling, fill rule, blending
};

/// Floats from one vertex's attributes to the next's in `draw`.
inline std::size_t attribute_row(const Draw& draw) {
  return draw.attribute_stride ? draw.attribute_stride : draw.attribute_count;
}

}  // namespace mosaic
