// frame_checks.hpp — the checks Renderer::render() makes on every draw before drawing any.
//
// Takes: one Draw and its index in the frame. Gives: nothing, or a thrown Error{kInvalidDraw} /
// Error{kIndexOutOfRange} naming the draw. Shared by validate(), Renderer::render() and the
// occlusion queries.
#pragma once

#include <cstddef>

#include "mosaic/draw.hpp"

namespace mosaic::detail {

/// Where a draw's index range is checked: here, or by the fast path's front end, which reads
/// every index anyway (front::FrontStats::index_out_of_range; Renderer::render() then throws).
enum class IndexCheck { kHere, kInFrontEnd };

/// Throws as validate() does for draw number `index` of a frame.
void validate_draw(const Draw& draw, std::size_t index, IndexCheck indices = IndexCheck::kHere);

}  // namespace mosaic::detail
