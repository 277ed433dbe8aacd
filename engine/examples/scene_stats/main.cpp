// scene_stats — renders one of mosaic's built-in scenes and prints what the frame cost.
//
// Takes: [scene] [--size W H] [--samples N] [--frames N] [--threads N] [--out image.png].
// Gives: for each built-in scene asked for (default: "default"), the counters of FrameStats and
// the mean stage times over the frames, on stdout; with --out, the last frame as an image.
// Uses only the public API (mosaic.hpp).
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mosaic/mosaic.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace {

/// Frames rendered by default: the first one warms caches and threads, the rest are averaged.
constexpr int kDefaultFrames = 5;
/// Upper bound of --frames: a cheap guard against a typo that would run for hours.
constexpr int kMaxFrames = 100000;

/// Parses an integer in [lo, hi]; false for anything else.
bool parse_int(const char* text, int lo, int hi, int& out) {
  const std::string_view s(text);
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || v < lo || v > hi) return false;
  out = v;
  return true;
}

int usage() {
  std::fprintf(stderr,
               "usage: scene_stats [scene] [--size W H] [--samples 1|4|8|16] [--frames N] "
               "[--threads N] [--out image.png]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string name = "default", out;
  int width = 1920, height = 1080, samples = 1, frames = kDefaultFrames, threads = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    const bool has1 = i + 1 < argc, has2 = i + 2 < argc;
    if (a == "--size" && has2) {
      if (!parse_int(argv[i + 1], 1, mosaic::kMaxTargetSize, width) ||
          !parse_int(argv[i + 2], 1, mosaic::kMaxTargetSize, height))
        return usage();
      i += 2;
    } else if (a == "--samples" && has1) {
      if (!parse_int(argv[++i], 1, 16, samples)) return usage();
    } else if (a == "--frames" && has1) {
      if (!parse_int(argv[++i], 1, kMaxFrames, frames)) return usage();
    } else if (a == "--threads" && has1) {
      if (!parse_int(argv[++i], 0, mosaic::kMaxThreads, threads)) return usage();
    } else if (a == "--out" && has1) {
      out = argv[++i];
    } else if (!a.empty() && a[0] != '-') {
      name = a;
    } else {
      return usage();
    }
  }

  try {
    mosaic::Scene scene = mosaic::builtin_scene(name, width, height);
    const std::vector<mosaic::Draw> draws = scene.draws();
    mosaic::Frame frame;
    frame.draws = draws;

    mosaic::RenderTarget target(width, height, samples);
    target.set_clear(scene.clear_color, scene.clear_depth);
    mosaic::RendererOptions options;
    options.threads = threads;
    mosaic::Renderer renderer(options);

    mosaic::FrameStats last, sum;
    for (int f = 0; f < frames; ++f) {
      last = renderer.render(frame, target);
      sum.ms_setup += last.ms_setup;
      sum.ms_binning += last.ms_binning;
      sum.ms_raster += last.ms_raster;
      sum.ms_resolve += last.ms_resolve;
      sum.ms_total += last.ms_total;
    }
    if (!out.empty()) mosaic::write_image(target, out);

    const double n = frames;
    std::printf("scene %s: %dx%d, %dx, %s, %d threads, %d frames\n", scene.name.c_str(), width,
                height, samples, mosaic::to_string(last.isa), last.threads, frames);
    const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
    std::printf(
        "  triangles in %llu, drawn %llu, clipped %llu, culled: face %llu, degenerate %llu, "
        "outside %llu, non-finite %llu, no sample %llu\n",
        u(last.triangles_in), u(last.triangles_drawn), u(last.triangles_clipped),
        u(last.triangles_culled_face), u(last.triangles_degenerate), u(last.triangles_outside),
        u(last.triangles_nonfinite), u(last.triangles_no_sample));
    std::printf("  (triangle, tile) pairs %llu, hi-z blocks rejected %llu, accepted %llu\n",
                u(last.triangles_binned), u(last.blocks_hiz_rejected), u(last.blocks_hiz_accepted));
    std::printf("  samples tested %llu, written %llu\n", u(last.samples_tested),
                u(last.samples_written));
    std::printf(
        "  mean ms: setup %.3f, binning %.3f, raster %.3f, resolve (thread time) %.3f, "
        "frame %.3f (%.1f frames/s)\n",
        sum.ms_setup / n, sum.ms_binning / n, sum.ms_raster / n, sum.ms_resolve / n,
        sum.ms_total / n, sum.ms_total > 0 ? 1000.0 * n / sum.ms_total : 0.0);
    std::printf("  image hash %016llx\n", u(target.image_hash()));
    if (!out.empty()) std::printf("  wrote %s\n", out.c_str());
    return 0;
  } catch (const mosaic::Error& e) {
    std::fprintf(stderr, "scene_stats: %s\n", e.what());
    return 1;
  }
}
