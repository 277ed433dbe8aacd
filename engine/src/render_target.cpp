#include "mosaic/render_target.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include "mosaic/errors.hpp"
#include "raster/sample_patterns.hpp"

namespace mosaic {

RenderTarget::RenderTarget(int width, int height, int samples, TargetOptions options)
    : width_(width), height_(height), samples_(samples), options_(options) {
  if (width < 1 || width > kMaxTargetSize || height < 1 || height > kMaxTargetSize) {
    throw Error(Errc::kInvalidTargetSize, "render target size " + std::to_string(width) + "x" +
                                              std::to_string(height) + " is outside 1..16384");
  }
  if (raster::sample_pattern(samples).empty()) {
    throw Error(Errc::kUnsupportedSampleCount,
                "unsupported sample count " + std::to_string(samples) + " (use 1, 4, 8 or 16)");
  }
  color_.assign(static_cast<std::size_t>(width) * height, clear_color_);
  const std::size_t n = color_.size() * static_cast<std::size_t>(samples);
  if (options_.keep_sample_depth) sample_depth_.assign(n, clear_depth_);
  if (options_.keep_sample_color) sample_color_.assign(n, clear_color_);
}

RenderTarget::RenderTarget(int width, int height, int samples, ColorView color, DepthView depth,
                           TargetOptions options)
    : RenderTarget(width, height, samples, options) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (color.pixels == nullptr) throw Error(Errc::kInvalidArgument, "ColorView::pixels is null");
  if (color.stride_bytes < static_cast<std::size_t>(width) * sizeof(Rgba8))
    throw Error(Errc::kInvalidArgument, "ColorView::stride_bytes " +
                                            std::to_string(color.stride_bytes) +
                                            " is shorter than a row of " + size);
  if (color.format != PixelFormat::kRgba8 && color.format != PixelFormat::kBgra8)
    throw Error(Errc::kInvalidArgument, "ColorView::format is not kRgba8 or kBgra8");
  if (depth.values != nullptr) {
    const std::size_t row = static_cast<std::size_t>(width) * samples * sizeof(float);
    if (depth.stride_bytes < row)
      throw Error(Errc::kInvalidArgument, "DepthView::stride_bytes " +
                                              std::to_string(depth.stride_bytes) +
                                              " is shorter than a row of " + size + " with " +
                                              std::to_string(samples) + " samples");
    if (depth.stride_bytes % sizeof(float) != 0 ||
        reinterpret_cast<std::uintptr_t>(depth.values) % alignof(float) != 0)
      throw Error(Errc::kInvalidArgument,
                  "DepthView::values and stride_bytes must be multiples of 4 bytes");
  }
  color_view_ = color;
  depth_view_ = depth;
  options_.keep_sample_depth = false;  // the view is the kept depth
  sample_depth_.clear();
  sample_depth_.shrink_to_fit();
  color_.clear();
  color_.shrink_to_fit();
  color_fill_known_ = false;  // the caller's memory holds whatever it held
}

Rgba8 RenderTarget::pixel(int x, int y) const {
  if (!over_caller_memory()) return color_[static_cast<std::size_t>(y) * width_ + x];
  Rgba8 c;
  std::memcpy(&c,
              static_cast<const std::uint8_t*>(color_view_.pixels) +
                  static_cast<std::size_t>(y) * color_view_.stride_bytes +
                  static_cast<std::size_t>(x) * sizeof(Rgba8),
              sizeof(Rgba8));
  if (color_view_.format == PixelFormat::kBgra8) std::swap(c.r, c.b);
  return c;
}

RenderTarget::ImageSurface RenderTarget::image_surface() noexcept {
  color_fill_known_ = false;
  if (over_caller_memory())
    return {static_cast<std::uint8_t*>(color_view_.pixels), color_view_.stride_bytes,
            color_view_.format == PixelFormat::kBgra8};
  return {reinterpret_cast<std::uint8_t*>(color_.data()),
          static_cast<std::size_t>(width_) * sizeof(Rgba8), false};
}

RenderTarget::DepthSurface RenderTarget::depth_surface() {
  const std::size_t row = static_cast<std::size_t>(width_) * samples_;
  if (depth_view_.values != nullptr)
    return {depth_view_.values, depth_view_.stride_bytes / sizeof(float)};
  if (!options_.keep_sample_depth) return {};
  sample_depth_.resize(row * static_cast<std::size_t>(height_));
  return {sample_depth_.data(), row};
}

void RenderTarget::set_clear(Rgba8 color, float depth) {
  if (!std::isfinite(depth)) throw Error(Errc::kInvalidArgument, "clear depth must be finite");
  clear_color_ = color;
  clear_depth_ = depth;
}

void RenderTarget::fill_image(Rgba8 c) {
  const ImageSurface s = image_surface();
  if (s.bgra) std::swap(c.r, c.b);
  for (int y = 0; y < height_; ++y) {
    std::uint8_t* row = s.base + static_cast<std::size_t>(y) * s.stride_bytes;
    for (int x = 0; x < width_; ++x)
      std::memcpy(row + std::size_t(x) * sizeof(Rgba8), &c, sizeof c);
  }
}

void RenderTarget::store_image(std::span<const Rgba8> rgba) {
  const ImageSurface s = image_surface();
  for (int y = 0; y < height_; ++y) {
    std::uint8_t* row = s.base + static_cast<std::size_t>(y) * s.stride_bytes;
    for (int x = 0; x < width_; ++x) {
      Rgba8 c = rgba[static_cast<std::size_t>(y) * width_ + x];
      if (s.bgra) std::swap(c.r, c.b);
      std::memcpy(row + std::size_t(x) * sizeof(Rgba8), &c, sizeof c);
    }
  }
}

void RenderTarget::store_sample_depth(std::span<const float> depth) {
  const DepthSurface s = depth_surface();
  if (!s.base) return;
  const std::size_t row = static_cast<std::size_t>(width_) * samples_;
  for (int y = 0; y < height_; ++y)
    std::memcpy(s.base + std::size_t(y) * s.stride_floats, depth.data() + std::size_t(y) * row,
                row * sizeof(float));
}

std::vector<float> RenderTarget::read_sample_depth() const {
  const std::size_t row = static_cast<std::size_t>(width_) * samples_;
  if (!depth_view_.values) return sample_depth_;
  std::vector<float> out(row * static_cast<std::size_t>(height_));
  for (int y = 0; y < height_; ++y)
    std::memcpy(out.data() + std::size_t(y) * row,
                depth_view_.values + std::size_t(y) * (depth_view_.stride_bytes / sizeof(float)),
                row * sizeof(float));
  return out;
}

std::uint64_t RenderTarget::image_hash() const noexcept {
  // FNV-1a, 64-bit: small, stable across platforms, and plenty for golden images.
  std::uint64_t h = 14695981039346656037ull;
  auto mix = [&h](std::uint8_t byte) {
    h ^= byte;
    h *= 1099511628211ull;
  };
  for (int shift = 0; shift < 32; shift += 8) mix(static_cast<std::uint8_t>(width_ >> shift));
  for (int shift = 0; shift < 32; shift += 8) mix(static_cast<std::uint8_t>(height_ >> shift));
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Rgba8 c = pixel(x, y);
      mix(c.r);
      mix(c.g);
      mix(c.b);
      mix(c.a);
    }
  return h;
}

const char* to_string(Isa isa) noexcept {
  switch (isa) {
    case Isa::kAuto:
      return "auto";
    case Isa::kReference:
      return "reference";
    case Isa::kSse41:
      return "sse4.1";
    case Isa::kAvx2:
      return "avx2";
    case Isa::kAvx512:
      return "avx512";
  }
  return "?";
}

}  // namespace mosaic
