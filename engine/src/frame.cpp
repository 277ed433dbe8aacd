// frame.cpp — the frame orchestrator: the only place that knows the order of the stages.
//
// validate → front end (transform, clip, cull, snap, setup) → binning → tile rasterization
// (coverage, hierarchical z, depth, shading) → resolve. Isa::kReference sends the whole frame to
// the exact scalar oracle instead.
#include <algorithm>
#include <string>
#include <thread>

#include "front/front_end.hpp"
#include "mosaic/errors.hpp"
#include "mosaic/renderer.hpp"
#include "reference/reference.hpp"

namespace mosaic {

void validate(const Frame& frame, const RenderTarget& /*target*/) {
  for (std::size_t d = 0; d < frame.draws.size(); ++d) {
    const Draw& draw = frame.draws[d];
    const std::string where = "draw " + std::to_string(d) + ": ";
    const bool xyz = !draw.positions_xyz.empty();
    const std::size_t vertices = xyz ? draw.positions_xyz.size() : draw.positions.size();
    if (xyz && !draw.positions.empty())
      throw Error(Errc::kInvalidDraw, where + "give positions or positions_xyz, not both");
    if (vertices > 0xffffffffu)
      throw Error(Errc::kInvalidDraw, where + "more than 2^32-1 vertices");
    if (!draw.indices.empty()) {
      if (draw.indices.size() % 3 != 0)
        throw Error(Errc::kInvalidDraw, where + "index count " +
                                            std::to_string(draw.indices.size()) +
                                            " is not a multiple of 3");
      for (std::size_t i = 0; i < draw.indices.size(); ++i) {
        if (draw.indices[i] >= vertices)
          throw Error(Errc::kIndexOutOfRange,
                      where + "index " + std::to_string(draw.indices[i]) + " at position " +
                          std::to_string(i) + " is out of range (" + std::to_string(vertices) +
                          " vertices)");
      }
    } else if (vertices % 3 != 0) {
      throw Error(Errc::kInvalidDraw, where + "vertex count " + std::to_string(vertices) +
                                          " is not a multiple of 3 and there is no index buffer");
    }
    const std::size_t tris = front::triangle_count(draw);
    if (draw.color_source == ColorSource::kPerTriangle && draw.colors.size() != tris)
      throw Error(Errc::kInvalidDraw, where + std::to_string(draw.colors.size()) +
                                          " colours for " + std::to_string(tris) + " triangles");
    if (draw.color_source == ColorSource::kPerVertex && draw.colors.size() != vertices)
      throw Error(Errc::kInvalidDraw, where + std::to_string(draw.colors.size()) +
                                          " colours for " + std::to_string(vertices) +
                                          " vertices");
  }
}

std::vector<Isa> available_isas() { return {Isa::kReference}; }

struct Renderer::Impl {
  RendererOptions options;
  Isa isa = Isa::kReference;
  int threads = 1;
};

Renderer::Renderer(RendererOptions options) : impl_(std::make_unique<Impl>()) {
  if (options.threads < 0)
    throw Error(Errc::kInvalidArgument, "thread count must be >= 0");
  impl_->options = options;
  const std::vector<Isa> isas = available_isas();
  if (options.isa == Isa::kAuto) {
    impl_->isa = isas.back();
  } else if (std::find(isas.begin(), isas.end(), options.isa) != isas.end()) {
    impl_->isa = options.isa;
  } else {
    throw Error(Errc::kUnsupportedIsa,
                std::string("instruction set ") + to_string(options.isa) +
                    " is not available on this CPU or build");
  }
  impl_->threads = options.threads > 0
                       ? options.threads
                       : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Isa Renderer::isa() const noexcept { return impl_->isa; }
int Renderer::threads() const noexcept { return impl_->threads; }

FrameStats Renderer::render(const Frame& frame, RenderTarget& target) {
  validate(frame, target);
  return reference::render(frame, target);
}

}  // namespace mosaic
