// raster/sample_patterns.hpp — the standard D3D / Vulkan sample positions.
//
// Offsets are in 1/16 px from the pixel centre, y down (the tables of the Vulkan specification's
// "standard sample locations"). In 16.8 units a sample of pixel (px, py) lies at
// (px * 256 + 128 + dx * 16, py * 256 + 128 + dy * 16).
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace mosaic::raster {

struct SampleOffset {
  std::int8_t dx, dy;  ///< 1/16 px from the pixel centre
};

/// Units of SampleOffset in one 16.8 unit: 256 / 16.
inline constexpr std::int32_t kSampleOffsetScale = 16;

inline constexpr std::array<SampleOffset, 1> kPattern1{{{0, 0}}};
inline constexpr std::array<SampleOffset, 4> kPattern4{{{-2, -6}, {6, -2}, {-6, 2}, {2, 6}}};
inline constexpr std::array<SampleOffset, 8> kPattern8{
    {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}}};
inline constexpr std::array<SampleOffset, 16> kPattern16{{{1, 1},
                                                          {-1, -3},
                                                          {-3, 2},
                                                          {4, -1},
                                                          {-5, -2},
                                                          {2, 5},
                                                          {5, 3},
                                                          {3, -5},
                                                          {-2, 6},
                                                          {0, -7},
                                                          {-4, -6},
                                                          {-6, 4},
                                                          {-8, 0},
                                                          {7, -4},
                                                          {6, 7},
                                                          {-7, -8}}};

/// The pattern for a sample count of 1, 4, 8 or 16 (anything else: empty span).
constexpr std::span<const SampleOffset> sample_pattern(int samples) {
  switch (samples) {
    case 1:
      return kPattern1;
    case 4:
      return kPattern4;
    case 8:
      return kPattern8;
    case 16:
      return kPattern16;
    default:
      return {};
  }
}

/// A sample's position in 16.8 units.
constexpr std::int64_t sample_x_fixed(int px, SampleOffset o) {
  return std::int64_t{px} * 256 + 128 + o.dx * kSampleOffsetScale;
}
constexpr std::int64_t sample_y_fixed(int py, SampleOffset o) {
  return std::int64_t{py} * 256 + 128 + o.dy * kSampleOffsetScale;
}
/// The same position in pixels, exact in float for any coordinate below 2^19.
constexpr float sample_x_px(int px, SampleOffset o) {
  return static_cast<float>(px) + 0.5f + static_cast<float>(o.dx) * (1.0f / 16.0f);
}
constexpr float sample_y_px(int py, SampleOffset o) {
  return static_cast<float>(py) + 0.5f + static_cast<float>(o.dy) * (1.0f / 16.0f);
}

}  // namespace mosaic::raster
