// mosaic/render_target.hpp — where a frame lands.
//
// Takes: a size, a sample count and TargetOptions, or memory the caller owns (ColorView,
// DepthView). Gives: the resolved RGBA8 (or BGRA8) image of the last frame and, when asked for,
// the per-sample colour and float32 depth that the resolve read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mosaic/types.hpp"

namespace mosaic {

/// What a render target keeps besides the resolved image. Per-sample buffers cost memory
/// bandwidth at the end of every frame, so they are written only when asked for; the target
/// allocates them when it is made, so that its first frame costs what the later ones do.
struct TargetOptions {
  bool keep_sample_depth = false;  ///< write every sample's final depth to sample_depth()
  bool keep_sample_color = false;  ///< write every sample's colour to sample_color()
};

/// The channel order of colour memory, four bytes a pixel.
enum class PixelFormat : std::uint8_t {
  kRgba8,  ///< r, g, b, a (Rgba8's own order)
  kBgra8,  ///< b, g, r, a (most window surfaces and video frames)
};

/// Colour memory the caller owns, which the resolve writes straight into: pixel (x, y) is the
/// four bytes at `pixels + y * stride_bytes + 4 * x`, in `format`'s order. The memory must
/// outlive the target; nothing of it outside the width × height rectangle (the row padding
/// included) is ever written.
struct ColorView {
  void* pixels = nullptr;
  std::size_t stride_bytes = 0;  ///< from one row to the next: at least 4 * width
  PixelFormat format = PixelFormat::kRgba8;
};

/// Depth memory the caller owns, one float32 per sample: sample s of pixel (x, y) is the float
/// at byte offset `y * stride_bytes + 4 * (x * samples + s)` from `values`. Given to a target,
/// it takes the place of the kept sample depth (TargetOptions::keep_sample_depth): every frame
/// writes it whole, and a frame with Frame::depth_load = kLoad starts from what it holds. The
/// memory must outlive the target; nothing outside the rectangle is written.
struct DepthView {
  float* values = nullptr;
  std::size_t stride_bytes = 0;  ///< from one row to the next: at least 4 * width * samples
};

/// A width × height image with 1, 4, 8 or 16 samples per pixel.
///
/// Each Renderer::render() call is one frame: every sample is cleared to clear_color() and
/// clear_depth(), the draws are rasterized, and the samples are resolved with a box filter
/// (the rounded mean) into color().
class RenderTarget {
 public:
  /// Throws Error{kInvalidTargetSize} unless 1 <= width, height <= kMaxTargetSize, and
  /// Error{kUnsupportedSampleCount} unless samples is 1, 4, 8 or 16.
  RenderTarget(int width, int height, int samples = 1, TargetOptions options = {});
  /// A target over the caller's memory: the image goes to `color`, and the sample depth to
  /// `depth` if its `values` is set (then options.keep_sample_depth is implied). Throws as the
  /// constructor above, and Error{kInvalidArgument} for a null `color.pixels`, a stride too
  /// short for the width (and samples), a depth pointer or stride that is not float-aligned, or
  /// an unknown format.
  RenderTarget(int width, int height, int samples, ColorView color, DepthView depth = {},
               TargetOptions options = {});

  int width() const noexcept { return width_; }      ///< in pixels
  int height() const noexcept { return height_; }    ///< in pixels
  int samples() const noexcept { return samples_; }  ///< per pixel: 1, 4, 8 or 16
  /// The per-sample buffers this target keeps.
  const TargetOptions& options() const noexcept { return options_; }

  /// The colour and depth every sample starts each frame with (defaults: opaque black, 1).
  /// Throws Error{kInvalidArgument} for a depth that is not finite, changing nothing.
  void set_clear(Rgba8 color, float depth = 1.0f);
  Rgba8 clear_color() const noexcept { return clear_color_; }  ///< as set by set_clear()
  float clear_depth() const noexcept { return clear_depth_; }  ///< as set by set_clear()

  /// The resolved image, row-major, top row first: pixel (x, y) is color()[y * width() + x].
  /// After a depth-only frame (every draw's DrawState::color_write off, no sample colour kept)
  /// it holds the clear colour, as the box filter of untouched samples would; the renderer
  /// writes it once and skips the write while the image already holds that colour.
  /// Empty for a target over caller memory: read that memory, or pixel().
  std::span<const Rgba8> color() const noexcept { return color_; }
  /// The resolved pixel (x, y) in r, g, b, a order, whoever owns the memory; requires
  /// 0 <= x < width() and 0 <= y < height() (unchecked).
  Rgba8 pixel(int x, int y) const;
  /// Whether the image lives in memory the caller gave (a ColorView).
  bool over_caller_memory() const noexcept { return color_view_.pixels != nullptr; }

  /// Per-sample depth of the last frame, index ((y * width + x) * samples + s); empty unless
  /// TargetOptions::keep_sample_depth, and for a target whose depth is a DepthView (read that).
  std::span<const float> sample_depth() const noexcept { return sample_depth_; }
  /// Per-sample colour of the last frame, same indexing; empty unless keep_sample_color.
  std::span<const Rgba8> sample_color() const noexcept { return sample_color_; }

  /// FNV-1a hash of the resolved image (and its size), for golden tests and --stats.
  std::uint64_t image_hash() const noexcept;

  /// Mutable access for the renderers (engine internals); not for applications.
  std::vector<Rgba8>& color_storage() noexcept {
    color_fill_known_ = false;  // the caller may write anything
    return color_;
  }
  /// Engine internals: whether color() is known to hold nothing but `c`, and marking it so.
  bool color_filled_with(Rgba8 c) const noexcept { return color_fill_known_ && color_fill_ == c; }
  void mark_color_filled(Rgba8 c) noexcept {
    color_fill_known_ = true;
    color_fill_ = c;
  }
  std::vector<float>& sample_depth_storage() noexcept { return sample_depth_; }
  std::vector<Rgba8>& sample_color_storage() noexcept { return sample_color_; }
  /// Engine internals: where the resolved image goes, row by row, and where the kept sample
  /// depth goes (null base when it is not kept; the owned buffer is sized on first use).
  struct ImageSurface {
    std::uint8_t* base = nullptr;
    std::size_t stride_bytes = 0;
    bool bgra = false;
  };
  struct DepthSurface {
    float* base = nullptr;
    std::size_t stride_floats = 0;
  };
  ImageSurface image_surface() noexcept;  // the caller may write anything: fill unknown
  DepthSurface depth_surface();
  /// Engine internals: the whole image set to one colour, or to an r, g, b, a image of
  /// width × height; the kept sample depth set from, or read into, ((y * W + x) * S + s) order.
  void fill_image(Rgba8 c);
  void store_image(std::span<const Rgba8> rgba);
  void store_sample_depth(std::span<const float> depth);
  std::vector<float> read_sample_depth() const;
  /// Engine internals: whether no frame has been rendered into the target yet.
  bool fresh() const noexcept { return fresh_; }
  void mark_rendered() noexcept { fresh_ = false; }
  bool keeps_sample_depth() const noexcept {
    return options_.keep_sample_depth || depth_view_.values != nullptr;
  }

 private:
  int width_ = 0, height_ = 0, samples_ = 1;
  TargetOptions options_;
  Rgba8 clear_color_{0, 0, 0, 255};
  float clear_depth_ = 1.0f;
  std::vector<Rgba8> color_;  ///< empty over caller memory
  ColorView color_view_;
  DepthView depth_view_;
  std::vector<float> sample_depth_;
  std::vector<Rgba8> sample_color_;
  bool fresh_ = true;
  bool color_fill_known_ = true;  ///< the constructor fills color_ with color_fill_
  Rgba8 color_fill_{0, 0, 0, 255};
};

}  // namespace mosaic
