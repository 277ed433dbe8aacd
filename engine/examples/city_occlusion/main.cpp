// city_occlusion — the occlusion workflow of a game engine on a generated city: render the
// occluders' depth at a low resolution, test every object's box against it, and draw only the
// objects that may be visible.
//
// Takes: [--blocks N] [--objects N] [--occluder-size W H] [--size W H] [--samples 1|4|8|16]
//        [--threads N] [--repeat N] [--out city.png]
// Gives, on stdout: the city's size; the occluder pass's time (depth-only, 1 sample, with the
// hierarchical z kept); the box queries' time, rate and hidden share; the final frame's time
// with every object and with the visible ones only; and how many pixels of the two final
// images differ. Times are medians of --repeat runs. With --out, the visible-only image.
//
// The queries are conservative against the occluder pass's own samples: at the occluder pass's
// size, 1 sample, the two final images are identical (tests/test_occlusion.cpp checks it). A
// final frame of a higher resolution has samples between the occluder pass's, so an object
// seen there only through a gap narrower than the occluder pass's pixels can be culled: the
// differing pixels measure that. Uses only the public API (mosaic.hpp) and city.hpp.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <mosaic/mosaic.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "city.hpp"

namespace {

using Clock = std::chrono::steady_clock;

/// The defaults: 32 × 32 blocks (4,096 buildings, 40,960 occluder triangles) and 8,000 objects;
/// the occluder pass at 640 × 360, a typical size for it; the final frame at 1080p, 4x MSAA.
constexpr int kDefaultBlocks = 32, kDefaultObjects = 8000;
constexpr int kDefaultOccluderW = 640, kDefaultOccluderH = 360;
constexpr int kDefaultW = 1920, kDefaultH = 1080, kDefaultSamples = 4;
constexpr int kDefaultRepeat = 11;
/// Bounds of the options: a city of up to 256 × 256 blocks, a million objects.
constexpr int kMaxBlocks = 256, kMaxObjects = 1000000, kMaxRepeat = 1000;
/// Sky and ground of the final frame.
constexpr mosaic::Rgba8 kSky{150, 185, 225, 255}, kGround{70, 72, 76, 255};

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
               "usage: city_occlusion [--blocks N] [--objects N] [--occluder-size W H] "
               "[--size W H] [--samples 1|4|8|16] [--threads N] [--repeat N] [--out city.png]\n");
  return 2;
}

/// Median wall time of `repeat` calls of `f`, in milliseconds.
template <class F>
double median_ms(int repeat, F&& f) {
  std::vector<double> ms;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = Clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

/// A world-space indexed draw through the city's view-projection.
mosaic::Draw world_draw(const std::vector<glm::vec3>& pos, const std::vector<std::uint32_t>& idx,
                        const std::vector<mosaic::Rgba8>& colors, const glm::mat4& view_proj) {
  mosaic::Draw d;
  d.positions_xyz = pos;
  d.indices = idx;
  d.transform = view_proj;
  d.color_source = mosaic::ColorSource::kPerTriangle;
  d.colors = colors;
  d.state.cull = mosaic::CullMode::kBack;
  return d;
}

struct Options {
  int blocks = kDefaultBlocks, objects = kDefaultObjects;
  int occluder_w = kDefaultOccluderW, occluder_h = kDefaultOccluderH;
  int width = kDefaultW, height = kDefaultH, samples = kDefaultSamples;
  int threads = 0, repeat = kDefaultRepeat;
  std::string out;
};

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    const bool has1 = i + 1 < argc, has2 = i + 2 < argc;
    if (a == "--blocks" && has1) {
      if (!parse_int(argv[++i], 1, kMaxBlocks, o.blocks)) return false;
    } else if (a == "--objects" && has1) {
      if (!parse_int(argv[++i], 0, kMaxObjects, o.objects)) return false;
    } else if (a == "--occluder-size" && has2) {
      if (!parse_int(argv[i + 1], 1, mosaic::kMaxTargetSize, o.occluder_w) ||
          !parse_int(argv[i + 2], 1, mosaic::kMaxTargetSize, o.occluder_h))
        return false;
      i += 2;
    } else if (a == "--size" && has2) {
      if (!parse_int(argv[i + 1], 1, mosaic::kMaxTargetSize, o.width) ||
          !parse_int(argv[i + 2], 1, mosaic::kMaxTargetSize, o.height))
        return false;
      i += 2;
    } else if (a == "--samples" && has1) {
      if (!parse_int(argv[++i], 1, 16, o.samples)) return false;
    } else if (a == "--threads" && has1) {
      if (!parse_int(argv[++i], 0, mosaic::kMaxThreads, o.threads)) return false;
    } else if (a == "--repeat" && has1) {
      if (!parse_int(argv[++i], 1, kMaxRepeat, o.repeat)) return false;
    } else if (a == "--out" && has1) {
      o.out = argv[++i];
    } else {
      return false;
    }
  }
  return true;
}

int run(const Options& o) {
  // One camera for both passes: its clip space is mapped to each pass's own target, so the
  // occluder pass sees the final frame's view at its own resolution.
  const float aspect = static_cast<float>(o.width) / static_cast<float>(o.height);
  const city::City c = city::make_city(o.blocks, o.objects, aspect);
  std::printf("city: %d buildings (%zu occluder triangles), %zu objects\n", c.buildings,
              c.indices.size() / 3, c.objects.size());

  mosaic::RendererOptions ro;
  ro.threads = o.threads;
  mosaic::Renderer renderer(ro);

  // 1. The occluder pass: depth only, one sample, the hierarchical z kept for the queries.
  mosaic::Draw occluders = world_draw(c.positions, c.indices, c.colors, c.view_proj);
  occluders.state.color_write = false;
  mosaic::Frame occluder_frame;
  occluder_frame.draws = std::span<const mosaic::Draw>(&occluders, 1);
  occluder_frame.keep_hierarchical_z = true;
  mosaic::RenderTarget occluder_target(o.occluder_w, o.occluder_h, 1);
  mosaic::FrameStats occluder_stats;
  const double occluder_ms = median_ms(
      o.repeat, [&] { occluder_stats = renderer.render(occluder_frame, occluder_target); });
  std::printf("occluder pass %dx%d depth-only: %.3f ms (%llu triangles drawn, %d threads)\n",
              o.occluder_w, o.occluder_h, occluder_ms,
              static_cast<unsigned long long>(occluder_stats.triangles_drawn),
              occluder_stats.threads);

  // 2. The queries: every object's world-space box, in one batch.
  const mosaic::HierarchicalZ& hiz = renderer.hierarchical_z();
  std::vector<std::uint8_t> visible(c.objects.size());
  const double query_ms =
      median_ms(o.repeat, [&] { hiz.boxes_visible(c.objects, c.view_proj, visible); });
  const auto shown = static_cast<std::size_t>(std::count(visible.begin(), visible.end(), 1));
  const std::size_t hidden = c.objects.size() - shown;
  const double share = c.objects.empty() ? 0.0 : 100.0 * double(hidden) / double(c.objects.size());
  std::printf("queries: %zu boxes in %.3f ms (%.1f M boxes/s): %zu hidden (%.1f %%)\n",
              c.objects.size(), query_ms,
              query_ms > 0 ? double(c.objects.size()) / query_ms / 1000.0 : 0.0, hidden, share);

  // 3. The final frame: ground, buildings and objects, with every object and with the visible
  //    ones only. (The hierarchical z of step 1 stays in the renderer until its next frame.)
  const std::vector<glm::vec3> ground_pos{
      {-1e4f, 0, -1e4f}, {1e4f, 0, -1e4f}, {1e4f, 0, 1e4f}, {-1e4f, 0, 1e4f}};
  const std::vector<std::uint32_t> ground_idx{0, 3, 2, 0, 2, 1};
  const std::vector<mosaic::Rgba8> ground_col{kGround, kGround};
  std::vector<glm::vec3> all_pos, vis_pos;
  std::vector<std::uint32_t> all_idx, vis_idx;
  std::vector<mosaic::Rgba8> all_col, vis_col;
  city::object_mesh(c, {}, all_pos, all_idx, all_col);
  city::object_mesh(c, visible, vis_pos, vis_idx, vis_col);
  mosaic::RenderTarget target(o.width, o.height, o.samples);
  target.set_clear(kSky);
  auto final_frame = [&](const std::vector<glm::vec3>& pos, const std::vector<std::uint32_t>& idx,
                         const std::vector<mosaic::Rgba8>& col, std::vector<mosaic::Rgba8>& image) {
    const std::vector<mosaic::Draw> draws{
        world_draw(ground_pos, ground_idx, ground_col, c.view_proj),
        world_draw(c.positions, c.indices, c.colors, c.view_proj),
        world_draw(pos, idx, col, c.view_proj)};
    mosaic::Frame f;
    f.draws = draws;
    const double ms = median_ms(o.repeat, [&] { renderer.render(f, target); });
    image.assign(target.color().begin(), target.color().end());
    return ms;
  };
  std::vector<mosaic::Rgba8> all_image, vis_image;
  const double all_ms = final_frame(all_pos, all_idx, all_col, all_image);
  const double vis_ms = final_frame(vis_pos, vis_idx, vis_col, vis_image);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < all_image.size(); ++i) differ += all_image[i] == vis_image[i] ? 0 : 1;
  std::printf("final frame %dx%d %dx: every object %.3f ms, visible only %.3f ms\n", o.width,
              o.height, o.samples, all_ms, vis_ms);
  std::printf("pixels that differ: %zu of %zu\n", differ, all_image.size());
  if (!o.out.empty()) {
    mosaic::write_image(target, o.out);
    std::printf("wrote %s\n", o.out.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) return usage();
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "city_occlusion: %s\n", e.what());
    return 1;
  }
}
