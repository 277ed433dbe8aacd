// resolve/resolve.hpp — turning samples into pixels.
//
// Takes: per-sample colours, `samples` consecutive values per pixel. Gives: one RGBA8 pixel
// each, the box filter (the mean of the samples per channel) rounded to nearest, ties up.
#pragma once

#include <cstdint>
#include <span>

#include "mosaic/types.hpp"

namespace mosaic::resolve {

/// Resolves `out.size()` pixels of `samples` samples each.
void box_resolve(std::span<const Rgba8> in, int samples, std::span<Rgba8> out);

/// The box filter of one channel: round(sum / samples) with ties up, in integers.
constexpr std::uint8_t box_mean(std::uint32_t sum, std::uint32_t samples) {
  return static_cast<std::uint8_t>((sum + samples / 2) / samples);
}

}  // namespace mosaic::resolve
