// mosaic/occlusion.hpp — occlusion queries against a frame's hierarchical z.
//
// Takes: the hierarchical z a Renderer kept from a frame (Frame::keep_hierarchical_z), usually a
// depth-only occluder pass, and screen rectangles or triangle lists. Gives: visible / hidden,
// conservatively — a query reported hidden is hidden (no sample of it would pass the depth test
// against the frame's depth); one reported visible may still be hidden.
#pragma once

#include <span>
#include <vector>

#include "mosaic/draw.hpp"
#include "mosaic/types.hpp"

namespace mosaic {

/// A rectangle of the screen in pixels, y down: [x0, x1) × [y0, y1).
struct ScreenRect {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
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

  /// Whether any sample of the draw's triangles could pass its depth test
  /// (draw.state.depth_test, kLess by default) against the frame's depth. The draw is read as
  /// Renderer::render() reads it (space, transform, indices, clipping, culling); its colour and
  /// its other state are ignored. Each triangle is tested in the blocks its edges do not reject,
  /// with a bound of its depth over each block. Throws as Renderer::render() would for a
  /// malformed draw (Error{kInvalidDraw}, Error{kIndexOutOfRange}).
  bool draw_visible(const Draw& draw) const;

  /// Engine internals: sizes the bounds for a width × height frame and gives them to be
  /// written. Not for applications.
  void reset(int width, int height);
  float* zmin_storage() noexcept { return zmin_.data(); }  ///< engine internals
  float* zmax_storage() noexcept { return zmax_.data(); }  ///< engine internals
  void clear() noexcept;                                   ///< engine internals: make empty

 private:
  int width_ = 0, height_ = 0;
  std::vector<float> zmin_, zmax_;
};

}  // namespace mosaic
