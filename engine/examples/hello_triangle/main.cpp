// hello_triangle — the smallest mosaic program: one triangle, rendered and written to an image.
//
// Takes: an optional output path ending in .png or .ppm (default hello_triangle.png). Gives:
// a 256×256 image, 4 samples per pixel, of a triangle with red, green and blue corners on a
// dark background, and one line of stats on stdout. Uses only the public API (mosaic.hpp).
#include <array>
#include <cstdio>
#include <filesystem>
#include <mosaic/mosaic.hpp>
#include <span>

namespace {

/// Image edge in pixels: small enough to look at, large enough to see the blend.
constexpr int kSize = 256;
/// Samples per pixel: 4x MSAA smooths the three edges.
constexpr int kSamples = 4;
/// Background, dark so that the three primaries stand out.
constexpr mosaic::Rgba8 kBackground{24, 24, 32, 255};

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path out = argc > 1 ? argv[1] : "hello_triangle.png";
  try {
    // Clip space (x, y in [-1, 1] are on screen, y up; depth z/w in [0, 1]). With w = 1 there
    // is no perspective: the corners land at 10% and 90% of the image.
    const std::array<glm::vec4, 3> positions{{
        {-0.8f, -0.8f, 0.5f, 1.0f},  // bottom left
        {0.8f, -0.8f, 0.5f, 1.0f},   // bottom right
        {0.0f, 0.8f, 0.5f, 1.0f},    // top
    }};
    const std::array<mosaic::Rgba8, 3> colors{
        {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}}};

    mosaic::Draw draw;
    draw.positions = positions;
    draw.color_source = mosaic::ColorSource::kPerVertex;  // interpolated across the triangle
    draw.colors = colors;

    mosaic::Frame frame;
    frame.draws = std::span<const mosaic::Draw>(&draw, 1);

    mosaic::RenderTarget target(kSize, kSize, kSamples);
    target.set_clear(kBackground);
    mosaic::Renderer renderer;  // every hardware thread, the best SIMD path of this CPU
    const mosaic::FrameStats stats = renderer.render(frame, target);
    mosaic::write_image(target, out);

    std::printf("hello_triangle: wrote %s (%dx%d, %dx), %llu triangle drawn, %s, %.3f ms\n",
                out.string().c_str(), kSize, kSize, kSamples,
                static_cast<unsigned long long>(stats.triangles_drawn),
                mosaic::to_string(stats.isa), stats.ms_total);
    return 0;
  } catch (const mosaic::Error& e) {
    std::fprintf(stderr, "hello_triangle: %s\n", e.what());
    return 1;
  }
}
