// reference/reference.hpp — the exact scalar reference rasterizer: the oracle.
//
// Takes: a validated Frame and a RenderTarget. Gives: the resolved image (and the per-sample
// buffers the target asks for) and FrameStats. It visits every sample of every triangle's
// bounding box with exact int64 edge functions and the shared float depth and colour planes,
// one sample at a time, in submission order. It is slow on purpose: plainly correct first.
#pragma once

#include <vector>

#include "front/setup.hpp"
#include "mosaic/render_target.hpp"
#include "mosaic/renderer.hpp"

namespace mosaic::reference {

/// Full per-sample state of a frame, index ((y * width + x) * samples + s).
struct SampleBuffers {
  std::vector<Rgba8> color;
  std::vector<float> depth;
};

/// Renders `frame` into `target` exactly. `samples_out`, when given, receives the samples.
FrameStats render(const Frame& frame, RenderTarget& target, SampleBuffers* samples_out = nullptr);

/// Runs the front end over every draw in order, single-threaded; the painter's sort is applied
/// when frame.painter is set. Shared by the reference and the tests. Varying planes of shader
/// draws go to `planes` when given. `samples`: the target's sample count, whose pattern culls
/// triangles whose box holds no sample position (0: none culled).
std::vector<front::TriangleSetup> setup_frame(const Frame& frame, int width, int height,
                                              int samples, FrameStats& stats,
                                              front::PlaneArray* planes = nullptr);

}  // namespace mosaic::reference
