// tests/tsan/seeded_race.cpp — a deliberate data race inside the tile stage, built in
// ThreadSanitizer builds only. Its test passes when TSan reports the race: proof that
// .ci/tsan.supp and the stage annotations (engine/src/parallel/stage_edges.hpp) hide no race that
// a mosaic task makes, although every task runs below uninstrumented oneTBB frames.
#include <cstdio>

#include "mosaic/mosaic.hpp"

namespace {

// Written by every tile's shader calls, on any worker thread, without synchronisation.
int racy_counter = 0;

}  // namespace

int main() {
  mosaic::Mesh m;
  m.space = mosaic::Space::kScreen;
  m.color_source = mosaic::ColorSource::kConstant;
  // Two triangles over the whole 1024x1024 target: 64 tiles for the two workers to share.
  m.positions = {{0, 0, 0.5f, 1}, {1024, 0, 0.5f, 1},    {1024, 1024, 0.5f, 1},
                 {0, 0, 0.5f, 1}, {1024, 1024, 0.5f, 1}, {0, 1024, 0.5f, 1}};
  mosaic::Draw d = m.draw();
  d.shader = mosaic::make_shader(
      [](const mosaic::Fragment&) {
        ++racy_counter;
        return glm::vec4(1, 0, 0, 1);
      },
      0);
  mosaic::Frame frame;
  frame.draws = std::span<const mosaic::Draw>(&d, 1);
  mosaic::RenderTarget target(1024, 1024, 4);
  mosaic::Renderer renderer(mosaic::RendererOptions{.threads = 2});
  for (int i = 0; i < 5; ++i) renderer.render(frame, target);
  std::printf("seeded_race: %d shader calls\n", racy_counter);
  return 0;
}
