// frame_checks.hpp — the checks Renderer::render() makes on every draw before drawing any.
//
// Takes: one Draw and its index in the frame. Gives: nothing, or a thrown Error{kInvalidDraw} /
// Error{kIndexOutOfRange} naming the draw. Shared by validate() and the occlusion queries.
#pragma once

#include <cstddef>

#include "mosaic/draw.hpp"

namespace mosaic::detail {

/// Throws as validate() does for draw number `index` of a frame.
void validate_draw(const Draw& draw, std::size_t index);

}  // namespace mosaic::detail
