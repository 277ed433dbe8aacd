// mosaic-llvmpipe — renders one .tris scene with llvmpipe alone.
//
// Takes: a .tris file, a sample count, a thread count. Gives: GL_RENDERER, the median frame time
// (clear + draw + glFinish, + resolve + glFinish), GL_SAMPLES_PASSED with the depth test off,
// and optionally the resolved image. mosaic-peers runs the same peer beside mosaic.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "llvmpipe/llvmpipe_peer.hpp"
#include "mosaic/mosaic.hpp"

namespace {

// Frames drawn and thrown away first: llvmpipe compiles its shaders and state at the first draw.
constexpr int kDefaultWarmup = 3;
// The issue asks for the median of at least ten timed frames.
constexpr int kDefaultFrames = 10;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Render a .tris scene with Mesa llvmpipe (EGL surfaceless, OpenGL 4.5 core)"};
  std::string input, output;
  int samples = 1, threads = 1, frames = kDefaultFrames, warmup = kDefaultWarmup;
  app.add_option("scene", input, ".tris file")->required()->check(CLI::ExistingFile);
  app.add_option("-s,--samples", samples, "samples per pixel (1 or 4)")
      ->check(CLI::IsMember({1, 4}));
  app.add_option("-t,--threads", threads, "LP_NUM_THREADS")->check(CLI::Range(1, 256));
  app.add_option("-n,--frames", frames, "timed frames (median reported)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--warmup", warmup, "untimed frames first")->check(CLI::Range(0, 100000));
  app.add_option("-o,--output", output, "write the resolved image (.png or .ppm)");
  CLI11_PARSE(app, argc, argv);

  try {
    mosaic::Scene scene = mosaic::load_tris(input);
    mosaic::peers::LlvmpipeContext context(threads);
    std::printf("GL_RENDERER: %s\nGL_VERSION: %s\nLP_NUM_THREADS: %d (rasterizer threads: %d)\n",
                context.renderer().c_str(), context.version().c_str(), context.threads(),
                context.rasterizer_threads());
    std::vector<double> ms;
    {
      mosaic::peers::LlvmpipeScene gl(context, scene, samples);
      for (int i = 0; i < warmup; ++i) gl.render_frame();
      for (int i = 0; i < frames; ++i) ms.push_back(gl.render_frame());
      std::printf("%s: %dx%d, %zu triangles, %d samples: median %.3f ms over %d frames\n",
                  input.c_str(), scene.width, scene.height, scene.triangle_count(), samples,
                  mosaic::peers::median(ms), frames);
      if (!output.empty()) {
        mosaic::RenderTarget target(scene.width, scene.height, 1);
        const std::vector<mosaic::Rgba8> image = gl.read_image();
        target.color_storage().assign(image.begin(), image.end());
        mosaic::write_image(target, output);
      }
    }
    scene.for_each_state([](mosaic::DrawState& s) {
      s.depth_test = mosaic::DepthTest::kAlways;
      s.depth_write = false;
    });
    mosaic::peers::LlvmpipeScene counting(context, scene, samples);
    std::printf("GL_SAMPLES_PASSED with the depth test off: %llu\n",
                static_cast<unsigned long long>(counting.samples_passed()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mosaic-llvmpipe: %s\n", e.what());
    return 1;
  }
  return 0;
}
