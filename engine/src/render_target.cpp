#include "mosaic/render_target.hpp"

#include <cmath>
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
}

void RenderTarget::set_clear(Rgba8 color, float depth) {
  if (!std::isfinite(depth)) throw Error(Errc::kInvalidArgument, "clear depth must be finite");
  clear_color_ = color;
  clear_depth_ = depth;
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
  for (const Rgba8& c : color_) {
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
