// mosaic-peers — mosaic side by side with Mesa's llvmpipe, in one process, on the same scenes.
//
// Takes: built-in scene names (exported to .tris and read back, so that both renderers draw the
// very same file), any .tris or OBJ files (OBJ exported the same way), sample counts, thread
// counts. Gives: a markdown table of median frame times (each frame clear → resolved image,
// llvmpipe and mosaic alternating A B A B), their ratio, and how much the two images differ; a
// second table of covered-sample counts (OpenGL fill rule, depth test off: GL_SAMPLES_PASSED
// against samples_written); and, with --json, all of it with every frame time.
//
// Images may differ by 1 per channel: colour rounding, and at 4x the resolve (llvmpipe rounds
// a mean ending in .5 to even, mosaic up). "unexplained" counts pixels more than 1 apart none of
// whose samples is a depth near-tie (two triangles within float32 evaluation error of each
// other in exact depth). It must be 0, as must every difference beyond rounding with the depth
// test off, and every covered-sample count must be equal: otherwise the command exits with 1.
//
// llvmpipe reads LP_NUM_THREADS when its EGL display is initialised, so the thread count is the
// outer loop: one llvmpipe context (and one mosaic::Renderer) per thread count, in turn.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "llvmpipe/llvmpipe_peer.hpp"
#include "mosaic/mosaic.hpp"
#include "raster/sample_patterns.hpp"

namespace {

namespace fs = std::filesystem;
using mosaic::Rgba8;
using mosaic::peers::LlvmpipeContext;
using mosaic::peers::LlvmpipeScene;

// Untimed frames first: llvmpipe compiles its shaders and fragment pipeline at the first draws,
// and mosaic's worker threads and per-frame memory settle.
constexpr int kDefaultWarmup = 3;
// The issue asks for the median of at least ten timed frames.
constexpr int kMinFrames = 10;

struct SceneEntry {
  std::string name;
  fs::path file;
  mosaic::Scene scene;
};

struct ImageDiff {
  std::size_t pixels = 0;       ///< pixels where any channel differs
  int max_channel = 0;          ///< largest absolute difference of one channel
  std::size_t unexplained = 0;  ///< 1x: pixels > 1 apart with no depth near-tie at the centre
};

// Colour rounding (llvmpipe interpolates and converts in its own order) moves a channel by 1.
constexpr int kRoundingDifference = 1;
// Two depths closer than this many float ulps of the largest term a renderer adds while it
// evaluates either depth plane are a tie: both renderers evaluate planes in float32 (mosaic from
// the first vertex, llvmpipe from its own origin), so either may order them either way.
constexpr double kTieUlps = 4.0;
constexpr double kFloatEpsilon = 0x1.0p-24;  // half an ulp of 1: float32 rounding, relative
// Vertex positions are snapped to 1/256 px, round to nearest (GL_SUBPIXEL_BITS = 8 on llvmpipe).
constexpr double kSubpixelOne = 256.0;

// One triangle of the scene with its exact depth plane, for the near-tie check.
struct ExactTriangle {
  glm::dvec3 v[3];            ///< snapped position (pixels) and depth, clockwise on screen
  std::int64_t fx[3], fy[3];  ///< the same positions in 1/256 px
  double ddx = 0, ddy = 0;    ///< depth per pixel

  // Whether a sample (in 1/256 px) is covered, with OpenGL's rule as llvmpipe applies it in
  // y-down window space: a sample exactly on a left or bottom edge is inside, on a top or right
  // edge outside (DESIGN.md; tests/test_llvmpipe_peer.cpp checks it on llvmpipe alone). So a
  // sample on an edge two triangles share belongs to one of them, and is no tie.
  bool covers(std::int64_t sx, std::int64_t sy) const {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t dx = fx[(k + 1) % 3] - fx[k], dy = fy[(k + 1) % 3] - fy[k];
      const std::int64_t e = (sy - fy[k]) * dx - (sx - fx[k]) * dy;  // > 0 inside (clockwise)
      const bool kept = dy < 0 || (dy == 0 && dx < 0);               // left or bottom edge
      if (e < 0 || (e == 0 && !kept)) return false;
    }
    return true;
  }
};

std::vector<ExactTriangle> exact_triangles(const mosaic::Scene& scene) {
  std::vector<ExactTriangle> out;
  for (const mosaic::Mesh& m : scene.meshes) {
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
      ExactTriangle e;
      for (std::size_t k = 0; k < 3; ++k) {
        e.v[k] = glm::dvec3(m.positions[m.indices.empty() ? 3 * t + k : m.indices[3 * t + k]]);
        // Both renderers snap to 1/256 px before anything else: so must coverage here, or a
        // sample a hair from an edge lands on the other side of it.
        e.fx[k] = static_cast<std::int64_t>(std::floor(e.v[k].x * kSubpixelOne + 0.5));
        e.fy[k] = static_cast<std::int64_t>(std::floor(e.v[k].y * kSubpixelOne + 0.5));
        e.v[k].x = static_cast<double>(e.fx[k]) / kSubpixelOne;
        e.v[k].y = static_cast<double>(e.fy[k]) / kSubpixelOne;
      }
      const std::int64_t area2 =
          (e.fx[1] - e.fx[0]) * (e.fy[2] - e.fy[0]) - (e.fx[2] - e.fx[0]) * (e.fy[1] - e.fy[0]);
      if (area2 == 0) continue;
      if (area2 < 0) {  // make it clockwise on screen (y down): inside is e > 0 on every edge
        std::swap(e.v[1], e.v[2]);
        std::swap(e.fx[1], e.fx[2]);
        std::swap(e.fy[1], e.fy[2]);
      }
      const glm::dvec3 a = e.v[1] - e.v[0], b = e.v[2] - e.v[0];
      const double area = a.x * b.y - b.x * a.y;
      e.ddx = (a.z * b.y - b.z * a.y) / area;
      e.ddy = (b.z * a.x - a.z * b.x) / area;
      out.push_back(e);
    }
  }
  return out;
}

// For the pixels that differ by more than rounding: does one of their samples lie where two
// triangles (or a triangle and the clear depth) are within float evaluation error of each other
// in exact depth? Those are depth ties in all but name, and either renderer may resolve them
// either way; any other difference is unexplained. Triangles are visited once, each over the
// differing pixels of the rows its bounding box spans.
std::size_t count_unexplained(const mosaic::Scene& scene, int samples,
                              const std::vector<std::size_t>& pixels) {
  if (pixels.empty()) return 0;
  const auto pattern = mosaic::raster::sample_pattern(samples);
  const auto n_samples = pattern.size();
  const std::vector<ExactTriangle> tris = exact_triangles(scene);
  struct Nearest {
    double z[2] = {INFINITY, INFINITY};
    double reach[2] = {0, 0};
  };
  // The clear depth is what the first triangle at a sample is compared with.
  Nearest cleared;
  cleared.z[0] = scene.clear_depth;
  std::vector<Nearest> nearest(pixels.size() * n_samples, cleared);
  const auto w = static_cast<std::size_t>(scene.width);
  for (const ExactTriangle& t : tris) {
    const double y0 = std::min({t.v[0].y, t.v[1].y, t.v[2].y});
    const double y1 = std::max({t.v[0].y, t.v[1].y, t.v[2].y});
    const double x0 = std::min({t.v[0].x, t.v[1].x, t.v[2].x});
    const double x1 = std::max({t.v[0].x, t.v[1].x, t.v[2].x});
    if (y1 < -1 || y0 >= scene.height || x1 < -1 || x0 >= scene.width) continue;
    const auto first_row = static_cast<std::size_t>(std::max(0.0, std::floor(y0) - 1));
    const auto lo = std::lower_bound(pixels.begin(), pixels.end(), first_row * w);
    for (auto it = lo; it != pixels.end() && static_cast<double>(*it / w) <= y1 + 1; ++it) {
      for (std::size_t s = 0; s < n_samples; ++s) {
        const int px = static_cast<int>(*it % w), py = static_cast<int>(*it / w);
        const double cx = mosaic::raster::sample_x_px(px, pattern[s]);
        const double cy = mosaic::raster::sample_y_px(py, pattern[s]);
        if (cx < x0 || cx > x1 || cy < y0 || cy > y1) continue;
        if (!t.covers(mosaic::raster::sample_x_fixed(px, pattern[s]),
                      mosaic::raster::sample_y_fixed(py, pattern[s])))
          continue;
        const double z = t.v[0].z + t.ddx * (cx - t.v[0].x) + t.ddy * (cy - t.v[0].y);
        // The largest term either renderer may add: from a vertex, or from the window origin.
        double reach = std::abs(t.ddx) * cx + std::abs(t.ddy) * cy;
        for (const glm::dvec3& v : t.v)
          reach = std::max(reach, std::abs(t.ddx * (cx - v.x)) + std::abs(t.ddy * (cy - v.y)));
        Nearest& n = nearest[static_cast<std::size_t>(it - pixels.begin()) * n_samples + s];
        if (z < n.z[0]) {
          n.z[1] = n.z[0];
          n.reach[1] = n.reach[0];
          n.z[0] = z;
          n.reach[0] = reach;
        } else if (z < n.z[1]) {
          n.z[1] = z;
          n.reach[1] = reach;
        }
      }
    }
  }
  std::size_t unexplained = 0;
  for (std::size_t p = 0; p < pixels.size(); ++p) {
    bool tie = false;
    for (std::size_t s = 0; s < n_samples; ++s) {
      const Nearest& n = nearest[p * n_samples + s];
      const double tolerance = kTieUlps * kFloatEpsilon * (2.0 + n.reach[0] + n.reach[1]);
      tie = tie || n.z[1] - n.z[0] <= tolerance;
    }
    if (!tie) ++unexplained;
  }
  return unexplained;
}

// `tie_check`: the scene drawn with the depth test, whose near-ties explain differences; without
// it (depth test off: draw order decides every sample) nothing beyond rounding is explained.
ImageDiff compare_images(const std::vector<Rgba8>& a, std::span<const Rgba8> b, int samples,
                         const mosaic::Scene* tie_check = nullptr) {
  ImageDiff d;
  std::vector<std::size_t> beyond_rounding;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const int diffs[4] = {std::abs(a[i].r - b[i].r), std::abs(a[i].g - b[i].g),
                          std::abs(a[i].b - b[i].b), std::abs(a[i].a - b[i].a)};
    const int m = *std::max_element(diffs, diffs + 4);
    if (m > 0) ++d.pixels;
    if (m > kRoundingDifference) beyond_rounding.push_back(i);
    d.max_channel = std::max(d.max_channel, m);
  }
  d.unexplained =
      tie_check ? count_unexplained(*tie_check, samples, beyond_rounding) : beyond_rounding.size();
  return d;
}

mosaic::Scene with_fill_rule(mosaic::Scene s, mosaic::FillRule rule) {
  s.for_each_state([&](mosaic::DrawState& st) { st.fill_rule = rule; });
  return s;
}

// The scene as the coverage count needs it: OpenGL's fill rule, no depth test, no depth writes.
mosaic::Scene for_counting(mosaic::Scene s) {
  s.for_each_state([](mosaic::DrawState& st) {
    st.fill_rule = mosaic::FillRule::kOpenGL;
    st.depth_test = mosaic::DepthTest::kAlways;
    st.depth_write = false;
  });
  return s;
}

mosaic::RenderTarget make_target(const mosaic::Scene& s, int samples) {
  mosaic::RenderTarget t(s.width, s.height, samples);
  t.set_clear(s.clear_color, s.clear_depth);
  return t;
}

void write_pair(const fs::path& dir, const std::string& stem, const std::vector<Rgba8>& gl,
                const mosaic::RenderTarget& mosaic_target) {
  mosaic::RenderTarget gl_target(mosaic_target.width(), mosaic_target.height(), 1);
  gl_target.color_storage().assign(gl.begin(), gl.end());
  mosaic::write_image(gl_target, dir / (stem + "-llvmpipe.png"));
  mosaic::write_image(mosaic_target, dir / (stem + "-mosaic.png"));
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    if (comma > start) out.push_back(list.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Time mosaic against Mesa llvmpipe on the same scenes, compare images and coverage"};
  std::vector<std::string> files;
  std::string scene_list = "all", size = "1920x1080", json_path, out_dir, images_dir;
  std::string fill_rule = "gl", isa_name = "auto";
  std::vector<int> samples_list{1, 4}, threads_list{1, 2};
  int frames = kMinFrames, warmup = kDefaultWarmup;
  app.add_option("files", files,
                 ".tris or .obj files to add to the built-in scenes (an OBJ is framed at --size "
                 "and exported to .tris first)")
      ->check(CLI::ExistingFile);
  app.add_option("--scenes", scene_list,
                 "built-in scenes, comma-separated, 'all' or 'none' (default all)");
  app.add_option("--size", size, "size of the built-in scenes, WxH (default 1920x1080)");
  app.add_option("--samples", samples_list, "sample counts (default 1 4)")
      ->check(CLI::IsMember({1, 4}))
      ->delimiter(',');
  app.add_option("--threads", threads_list, "thread counts, both renderers (default 1 2)")
      ->check(CLI::Range(1, 256))
      ->delimiter(',');
  app.add_option("--frames", frames, "timed frames per renderer; the median is reported (>= 10)")
      ->check(CLI::Range(kMinFrames, 100000));
  app.add_option("--warmup", warmup, "untimed frames per renderer first (default 3)")
      ->check(CLI::Range(0, 100000));
  app.add_option(
         "--fill-rule", fill_rule,
         "mosaic's fill rule for the timed frames (default gl; d3d differs from llvmpipe on edges)")
      ->check(CLI::IsMember({"gl", "d3d"}));
  app.add_option("--isa", isa_name, "mosaic's instruction set (default auto)");
  app.add_option("--json", json_path, "write every result and frame time as JSON");
  app.add_option("--out", out_dir, "keep the exported .tris files here (default: a temp folder)");
  app.add_option("--images", images_dir, "write both renderers' images here as PNG");
  CLI11_PARSE(app, argc, argv);

  const fs::path tris_dir =
      out_dir.empty() ? fs::temp_directory_path() / ("mosaic-peers-" + std::to_string(getpid()))
                      : fs::path(out_dir);
  int status = 0;
  try {
    int width = 0, height = 0;
    if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2)
      throw mosaic::Error(mosaic::Errc::kInvalidArgument, "--size must be WxH, e.g. 1920x1080");
    mosaic::Isa isa = mosaic::Isa::kAuto;
    bool isa_known = isa_name == "auto";
    for (mosaic::Isa i : mosaic::available_isas()) {
      if (isa_name == mosaic::to_string(i)) {
        isa = i;
        isa_known = true;
      }
    }
    if (!isa_known)
      throw mosaic::Error(mosaic::Errc::kUnsupportedIsa, "--isa " + isa_name + " is not available");
    const mosaic::FillRule rule =
        fill_rule == "gl" ? mosaic::FillRule::kOpenGL : mosaic::FillRule::kD3D;

    // Built-in scenes and OBJ files go through .tris and back: both renderers then draw exactly
    // the file. Clip-space ones (default, the knots, OBJ) are written as the doubles mosaic's
    // front end computes, and the loader snaps them (ties to even, as llvmpipe), so both draw
    // the same snapped vertices; per-vertex colour is interpolated linearly in a .tris.
    std::vector<SceneEntry> scenes;
    std::vector<std::string> names = scene_list == "all"    ? mosaic::builtin_scene_names()
                                     : scene_list == "none" ? std::vector<std::string>{}
                                                            : split(scene_list);
    if (!names.empty()) fs::create_directories(tris_dir);
    for (const std::string& name : names) {
      const fs::path file = tris_dir / (name + ".tris");
      mosaic::save_tris(mosaic::builtin_scene(name, width, height), file);
      scenes.push_back({name, file, mosaic::load_tris(file)});
    }
    for (const std::string& f : files) {
      std::string ext = fs::path(f).extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      const std::string stem = fs::path(f).stem().string();
      if (ext != ".obj") {
        scenes.push_back({stem, f, mosaic::load_tris(f)});
        continue;
      }
      fs::create_directories(tris_dir);
      const fs::path file = tris_dir / (stem + ".tris");
      mosaic::save_tris(mosaic::load_obj(f, width, height), file);
      scenes.push_back({stem, file, mosaic::load_tris(file)});
    }
    if (scenes.empty()) throw mosaic::Error(mosaic::Errc::kInvalidArgument, "no scenes to run");
    if (!images_dir.empty()) fs::create_directories(images_dir);

    nlohmann::json json;
    json["frames"] = frames;
    json["warmup"] = warmup;
    json["fill_rule"] = fill_rule;
    json["results"] = nlohmann::json::array();
    json["coverage"] = nlohmann::json::array();
    std::string table =
        "| scene | samples | threads | llvmpipe ms | mosaic ms | llvmpipe/mosaic | differing "
        "pixels | max channel diff | unexplained "
        "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::string coverage =
        "| scene | samples | llvmpipe GL_SAMPLES_PASSED | mosaic samples_written | equal | "
        "differing pixels | max channel diff | more than 1 apart |\n"
        "|---|---:|---:|---:|---|---:|---:|---:|\n";
    using Clock = std::chrono::steady_clock;

    for (std::size_t ti = 0; ti < threads_list.size(); ++ti) {
      const int threads = threads_list[ti];
      LlvmpipeContext context(threads);
      mosaic::Renderer renderer(mosaic::RendererOptions{.threads = threads, .isa = isa});
      std::printf("threads %d: %s, %s; llvmpipe rasterizer threads %d; mosaic %s\n", threads,
                  context.renderer().c_str(), context.version().c_str(),
                  context.rasterizer_threads(), mosaic::to_string(renderer.isa()));
      std::fflush(stdout);
      json["llvmpipe"]["renderer"] = context.renderer();
      json["llvmpipe"]["version"] = context.version();
      json["mosaic"]["isa"] = mosaic::to_string(renderer.isa());

      for (const SceneEntry& entry : scenes) {
        const mosaic::Scene scene = with_fill_rule(entry.scene, rule);
        const std::vector<mosaic::Draw> draws = scene.draws();
        for (const int samples : samples_list) {
          LlvmpipeScene gl(context, scene, samples);
          mosaic::RenderTarget target = make_target(scene, samples);
          const mosaic::Frame frame{.draws = draws};
          auto mosaic_frame = [&] {
            const auto t0 = Clock::now();
            renderer.render(frame, target);
            return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
          };
          for (int i = 0; i < warmup; ++i) {
            gl.render_frame();
            mosaic_frame();
          }
          std::vector<double> gl_ms, mosaic_ms;
          for (int i = 0; i < frames; ++i) {  // A B A B: both see the same machine state
            gl_ms.push_back(gl.render_frame());
            mosaic_ms.push_back(mosaic_frame());
          }
          const std::vector<Rgba8> gl_image = gl.read_image();
          // Every pixel more than rounding apart must hold a sample on a depth near-tie; with
          // --fill-rule d3d, edges differ by design and only the timing counts.
          const ImageDiff d = compare_images(gl_image, target.color(), samples, &scene);
          if (d.unexplained != 0 && rule == mosaic::FillRule::kOpenGL) status = 1;
          const double gl_median = mosaic::peers::median(gl_ms);
          const double mosaic_median = mosaic::peers::median(mosaic_ms);
          char row[256];
          std::snprintf(row, sizeof row, "| %s | %d | %d | %.2f | %.2f | %.2f | %zu | %d | %zu |\n",
                        entry.name.c_str(), samples, threads, gl_median, mosaic_median,
                        gl_median / mosaic_median, d.pixels, d.max_channel, d.unexplained);
          table += row;
          std::printf("%s", row);
          std::fflush(stdout);
          json["results"].push_back({{"scene", entry.name},
                                     {"file", entry.file.string()},
                                     {"width", scene.width},
                                     {"height", scene.height},
                                     {"triangles", scene.triangle_count()},
                                     {"samples", samples},
                                     {"threads", threads},
                                     {"llvmpipe_rasterizer_threads", context.rasterizer_threads()},
                                     {"llvmpipe_ms", gl_median},
                                     {"mosaic_ms", mosaic_median},
                                     {"ratio_llvmpipe_over_mosaic", gl_median / mosaic_median},
                                     {"llvmpipe_frames_ms", gl_ms},
                                     {"mosaic_frames_ms", mosaic_ms},
                                     {"differing_pixels", d.pixels},
                                     {"max_channel_difference", d.max_channel}});
          json["results"].back()["unexplained_pixels"] = d.unexplained;
          if (ti == 0 && !images_dir.empty())
            write_pair(images_dir, entry.name + "-" + std::to_string(samples) + "x", gl_image,
                       target);
        }

        // Coverage does not depend on the thread count (both renderers promise it): once.
        if (ti != 0) continue;
        const mosaic::Scene counted = for_counting(entry.scene);
        const std::vector<mosaic::Draw> counted_draws = counted.draws();
        for (const int samples : samples_list) {
          LlvmpipeScene gl(context, counted, samples);
          const std::uint64_t passed = gl.samples_passed();
          mosaic::RenderTarget target = make_target(counted, samples);
          const mosaic::FrameStats stats =
              renderer.render(mosaic::Frame{.draws = counted_draws}, target);
          const ImageDiff d = compare_images(gl.read_image(), target.color(), samples);
          const bool equal = passed == stats.samples_written;
          // No depth test: draw order decides every sample, so no difference beyond colour
          // rounding is explained.
          if (!equal || d.unexplained != 0) status = 1;
          char row[256];
          std::snprintf(row, sizeof row, "| %s | %d | %llu | %llu | %s | %zu | %d | %zu |\n",
                        entry.name.c_str(), samples, static_cast<unsigned long long>(passed),
                        static_cast<unsigned long long>(stats.samples_written),
                        equal ? "yes" : "**NO**", d.pixels, d.max_channel, d.unexplained);
          coverage += row;
          json["coverage"].push_back({{"scene", entry.name},
                                      {"samples", samples},
                                      {"llvmpipe_samples_passed", passed},
                                      {"mosaic_samples_written", stats.samples_written},
                                      {"equal", equal},
                                      {"differing_pixels", d.pixels},
                                      {"max_channel_difference", d.max_channel},
                                      {"pixels_more_than_1_apart", d.unexplained}});
        }
      }
    }

    std::printf(
        "\nMedian of %d frames after %d warm-up frames, clear to resolved image, "
        "llvmpipe and mosaic alternating; mosaic fill rule %s.\n\n%s",
        frames, warmup, fill_rule.c_str(), table.c_str());
    std::printf(
        "\nCovered samples, OpenGL fill rule, depth test off (the images compared are "
        "those frames):\n\n%s",
        coverage.c_str());
    if (!json_path.empty()) {
      std::ofstream out(json_path);
      out << json.dump(2) << "\n";
      if (!out) throw mosaic::Error(mosaic::Errc::kIo, "cannot write " + json_path);
    }
    if (status != 0)
      std::fprintf(stderr,
                   "mosaic-peers: covered-sample counts or 1x images differ beyond rounding and "
                   "depth near-ties\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mosaic-peers: %s\n", e.what());
    status = 2;
  }
  if (out_dir.empty()) {
    std::error_code ec;
    fs::remove_all(tris_dir, ec);
  }
  return status;
}
