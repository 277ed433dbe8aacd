// mosaic/occlusion.hpp — occlusion queries against a frame's hierarchical z.
//
// Takes: the hierarchical z a Renderer kept from a frame (Frame::keep_hierarchical_z), usually a
// depth-only occluder pass, and screen rectangles or triangle lists. Gives: visible / hidden,
// conservatively — a query reported hidden is hidden (no sample of it would pass the depth test
// against the frame's depth); one reported visible may still be hidden.
//
// The workflow (engine/examples/city_occlusion): render the occluders depth-only
// (DrawState::color_write off) into a small target of one sample with keep_hierarchical_z, for
// example 640×360; test every object's world-space box with boxes_visible() and the same
// view-projection; draw only the objects it reports visible. "Hidden" holds for the occluder
// pass's samples: a final frame of higher resolution can show an object through a gap narrower
// than one of the occluder pass's pixels.
#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "mosaic/draw.hpp"
#include "mosaic/types.hpp"

namespace mosaic {

/// A rectangle of the screen in pixels, y down: [x0, x1) × [y0, y1).
struct ScreenRect {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// An axis-aligned box with corners `min` and `max`, in the space a query's matrix maps to clip
/// space (usually world space, with the occluder pass's view-projection).
struct Box {
  glm::vec3 min{0.0f}, max{0.0f};
};

/// What a box query found besides its answer (HierarchicalZ::boxes_visible()).
struct BoxBounds {
  /// The box's screen rectangle (its projected corners' bounds, widened by a pixel) and its
  /// nearest depth in the sense of the test: the rectangle and depth the box was tested with. A
  /// box with a corner on or behind the near plane, or not finite, gets the whole screen and the
  /// nearest depth there is (0, or 1 for the greater tests); one wholly behind it, nothing.
  ScreenRect rect;
  float nearest = 0;
};

/// Depth bounds of every 8×8-pixel block of a frame: the smallest and the largest depth any of
/// the block's samples (inside the image) held at the end of the frame. The bounds are exact, so
/// two frames with the same depth buffer have the same hierarchical z on every path.
///
/// Queries are answered block by block: a query is hidden when, in every block it may touch, no
/// depth it may have there can pass the depth test against any depth the block holds. An empty
/// HierarchicalZ (no frame kept one) answers every query "visible".
class HierarchicalZ {
 public:
  /// Block edge in pixels.
  static constexpr int kBlockSize = 8;

  int width() const noexcept { return width_; }    ///< the frame's width in pixels
  int height() const noexcept { return height_; }  ///< the frame's height in pixels
  int blocks_x() const noexcept { return (width_ + kBlockSize - 1) / kBlockSize; }
  int blocks_y() const noexcept { return (height_ + kBlockSize - 1) / kBlockSize; }
  bool empty() const noexcept { return zmin_.empty(); }  ///< true until a frame kept one
  /// Per block, row-major (blocks_x() per row): the smallest / largest stored depth.
  std::span<const float> zmin() const noexcept { return zmin_; }
  std::span<const float> zmax() const noexcept { return zmax_; }

  /// Whether anything drawn in `rect` at depths no nearer than `nearest` could pass `test`
  /// (the occluder pass's test: with kLess, a sample at depth z passes where z < stored).
  /// `nearest` is the query's nearest depth in the sense of the test: its smallest depth for
  /// kLess / kLessEqual, its largest for kGreater / kGreaterEqual (reversed Z). A rectangle
  /// entirely off the screen, or empty, is hidden; a NaN in the input answers visible.
  bool rect_visible(const ScreenRect& rect, float nearest, DepthTest test = DepthTest::kLess) const;

  /// rect_visible() of many rectangles: `visible[i]` is 1 when rects[i] at depth nearest[i] may
  /// be visible, 0 when it is hidden. Throws Error{kInvalidArgument} if the spans' sizes differ.
  void rects_visible(std::span<const ScreenRect> rects, std::span<const float> nearest,
                     std::span<std::uint8_t> visible, DepthTest test = DepthTest::kLess) const;

  /// Whether anything inside each box could pass `test` against the frame's depth: `visible[i]`
  /// is 1 when boxes[i] may be visible, 0 when it is hidden. `view_proj` maps the boxes' space to
  /// the occluder pass's clip space (D3D depth: 0 <= z <= w), and the viewport is the frame's, as
  /// Renderer::render() maps clip space. Each box is projected by its eight corners in double; a
  /// box with a corner on or behind the near plane (w <= 0 or z < 0) is visible unless all of
  /// them are behind it (z < 0: clipped away, hidden), and one with a non-finite corner is
  /// visible. Otherwise its screen rectangle, widened by a pixel, and its nearest corner depth,
  /// moved one float step nearer, go to rect_visible(). Conservative: never 0 when a sample of a
  /// triangle inside the box would pass. `bounds`, if not empty, gets what each box was tested
  /// with. Throws Error{kInvalidArgument} if the spans' sizes differ.
  void boxes_visible(std::span<const Box> boxes, const glm::mat4& view_proj,
                     std::span<std::uint8_t> visible, DepthTest test = DepthTest::kLess,
                     std::span<BoxBounds> bounds = {}) const;

  /// Whether any sample of the draw's triangles could pass its depth test
  /// (draw.state.depth_test, kLess by default) against the frame's depth. The draw is read as
  /// Renderer::render() reads it (space, transform, indices, clipping, culling); its colour and
  /// its other state are ignored. Each triangle is tested in the blocks its edges do not reject,
  /// with a bound of its depth over each block. Throws as Renderer::render() would for a
  /// malformed draw (Error{kInvalidDraw}, Error{kIndexOutOfRange}).
  bool draw_visible(const Draw& draw) const;

  /// Blocks per edge of a coarse cell: rect_visible() skips every block of a 32×32-pixel cell
  /// whose bounds already hide the query, and looks at the blocks only where they do not.
  static constexpr int kCoarseBlocks = 4;

  /// Engine internals: sizes the bounds for a width × height frame and gives them to be
  /// written; build_coarse() then derives the coarse cells from them. Not for applications.
  void reset(int width, int height);
  void build_coarse();                                     ///< engine internals
  float* zmin_storage() noexcept { return zmin_.data(); }  ///< engine internals
  float* zmax_storage() noexcept { return zmax_.data(); }  ///< engine internals
  void clear() noexcept;                                   ///< engine internals: make empty

 private:
  int width_ = 0, height_ = 0;
  std::vector<float> zmin_, zmax_;
  std::vector<float> coarse_min_, coarse_max_;  ///< per coarse cell: the bounds of its blocks
};

}  // namespace mosaic
