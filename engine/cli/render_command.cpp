// cli/render_command.cpp — `mosaic render`: renders a scene, reports the time and writes the image.
//
// Takes: a SCENE (built-in name, .tris or .obj) and render options. Gives: a PNG/PPM file, one
// human line on stderr, and with --stats one JSON object of FrameStats on stdout.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "mosaic/mosaic.hpp"

namespace mosaic::cli {

namespace {

// Above this, a time is printed with one decimal; below it with two, so that sub-10 ms frames
// keep two significant digits.
constexpr double kTwoDecimalsBelowMs = 10.0;
// Most frames --repeat renders: far more than a median needs (100,000 one-millisecond frames
// take minutes), and the statistics kept per run for the medians stay near 20 MB.
constexpr int kMaxRepeat = 100'000;
// A long --repeat prints a progress line this often, so that it is never silent for hours.
constexpr std::chrono::seconds kProgressInterval{10};
// The value of --out that means "write no image" (as --no-out does).
constexpr const char* kNoOutput = "-";

// How --depth-test maps onto DrawState: the test, and whether depth is written.
struct DepthChoice {
  DepthTest test = DepthTest::kLess;
  bool write = true;
  bool reversed = false;  // greater / greater-equal: the depth buffer clears to 0
};

const std::map<std::string, DepthChoice>& depth_choices() {
  static const std::map<std::string, DepthChoice> choices = {
      {"less", {DepthTest::kLess, true, false}},
      {"less-equal", {DepthTest::kLessEqual, true, false}},
      {"greater", {DepthTest::kGreater, true, true}},
      {"greater-equal", {DepthTest::kGreaterEqual, true, true}},
      {"always", {DepthTest::kAlways, true, false}},
      {"off", {DepthTest::kAlways, false, false}},
  };
  return choices;
}

const std::map<std::string, FillRule>& fill_rules() {
  static const std::map<std::string, FillRule> rules = {{"d3d", FillRule::kD3D},
                                                        {"gl", FillRule::kOpenGL}};
  return rules;
}

const std::map<std::string, CullMode>& cull_modes() {
  static const std::map<std::string, CullMode> modes = {
      {"none", CullMode::kNone}, {"back", CullMode::kBack}, {"front", CullMode::kFront}};
  return modes;
}

const std::map<std::string, Shading>& shadings() {
  static const std::map<std::string, Shading> shadings = {{"flat", Shading::kFlat},
                                                          {"normals", Shading::kNormals},
                                                          {"lambert", Shading::kLambert},
                                                          {"uv", Shading::kUv}};
  return shadings;
}

std::string shading_name(Shading shading) {
  for (const auto& [name, value] : shadings())
    if (value == shading) return name;
  return "flat";
}

const std::map<std::string, Isa>& isa_names() {
  static const std::map<std::string, Isa> isas = {{"auto", Isa::kAuto},
                                                  {"reference", Isa::kReference},
                                                  {"sse4.1", Isa::kSse41},
                                                  {"avx2", Isa::kAvx2},
                                                  {"avx512", Isa::kAvx512}};
  return isas;
}

template <class T>
std::vector<std::string> keys_of(const std::map<std::string, T>& map) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : map) keys.push_back(key);
  return keys;
}

struct RenderOptions {
  SceneRequest scene;
  std::string size;
  std::uint64_t seed = 1;
  int msaa = 4;
  bool ssaa = false;
  int threads = 0;
  std::string fill_rule;
  std::string depth_test;
  std::string cull;
  bool painter = false;
  bool depth_only = false;
  bool nearest_first = false;
  std::string shade;
  bool reserve = false;
  int repeat = 1;
  std::string out;
  bool no_out = false;
  bool stats = false;
  bool reference = false;
  std::string isa = "auto";
  int tile_size = 0;

  // Which options were given (CLI11 keeps the counts on the Option objects).
  CLI::Option* size_opt = nullptr;
  CLI::Option* seed_opt = nullptr;
};

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 == 1 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

template <class Field>
double median_of(const std::vector<FrameStats>& runs, Field field) {
  std::vector<double> values;
  values.reserve(runs.size());
  for (const FrameStats& s : runs) values.push_back(s.*field);
  return median(std::move(values));
}

std::string format_ms(double ms) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(ms < kTwoDecimalsBelowMs ? 2 : 1);
  out << ms;
  return out.str();
}

std::string hex64(std::uint64_t value) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

int run_render(const RenderOptions& o) {
  // Everything the command line can get wrong is checked before any file is read.
  std::optional<std::string> out_path;
  if (!o.no_out && o.out != kNoOutput) {
    out_path = o.out.empty() ? scene_display_name(o.scene.arg) + ".png" : o.out;
    const std::string ext = lower_extension(*out_path);
    if (ext != ".png" && ext != ".ppm")
      throw UsageError("--out: '" + *out_path + "' must end in .png or .ppm (or use --no-out)");
  }
  SceneRequest request = o.scene;
  if (o.size_opt->count() > 0) request.size = parse_size(o.size);
  if (o.seed_opt->count() > 0) request.seed = o.seed;

  Scene scene = load_scene(request);
  const std::string name = scene_display_name(o.scene.arg);

  float clear_depth = scene.clear_depth;
  if (!o.depth_test.empty()) {
    const DepthChoice choice = depth_choices().at(o.depth_test);
    scene.for_each_state([&](DrawState& s) {
      s.depth_test = choice.test;
      s.depth_write = choice.write;
    });
    if (choice.reversed) clear_depth = 0.0f;
  }
  if (!o.fill_rule.empty()) {
    const FillRule rule = fill_rules().at(o.fill_rule);
    scene.for_each_state([&](DrawState& s) { s.fill_rule = rule; });
  }
  if (!o.cull.empty()) {
    const CullMode cull = cull_modes().at(o.cull);
    scene.for_each_state([&](DrawState& s) { s.cull = cull; });
  }
  if (o.depth_only) scene.for_each_state([](DrawState& s) { s.color_write = false; });
  const Shading shading = o.shade.empty() ? scene.default_shading : shadings().at(o.shade);
  if (shading == Shading::kUv && !scene.has_uvs())
    throw Error(Errc::kInvalidArgument,
                "--shade uv: scene '" + name + "' has no texture coordinates");
  if ((shading == Shading::kNormals || shading == Shading::kLambert) && !scene.has_normals())
    throw Error(Errc::kInvalidArgument,
                "--shade " + o.shade + ": scene '" + name + "' has no vertex normals");

  RenderTarget target(scene.width, scene.height, o.msaa);
  target.set_clear(scene.clear_color, clear_depth);
  RendererOptions renderer_options;
  renderer_options.threads = o.threads;
  renderer_options.isa = o.reference ? Isa::kReference : isa_names().at(o.isa);
  renderer_options.tile_size = o.tile_size;
  Renderer renderer(renderer_options);

  const std::vector<Draw> draws = scene.draws(shading);
  Frame frame;
  frame.draws = draws;
  frame.ssaa = o.ssaa;
  frame.painter = o.painter;
  frame.occluders_nearest_first = o.nearest_first;

  double ms_reserve = 0;
  if (o.reserve) {
    const auto r0 = std::chrono::steady_clock::now();
    std::uint64_t indexed_vertices = 0;  // what the vertex stage projects
    for (const Mesh& m : scene.meshes)
      if (!m.indices.empty()) indexed_vertices += m.positions.size();
    renderer.reserve({target.width(), target.height(), target.samples(), scene.triangle_count(),
                      indexed_vertices});
    ms_reserve =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
  }
  std::vector<FrameStats> runs;
  runs.reserve(static_cast<std::size_t>(o.repeat));
  const auto start = std::chrono::steady_clock::now();
  auto next_progress = start + kProgressInterval;
  for (int i = 0; i < o.repeat; ++i) {
    runs.push_back(renderer.render(frame, target));
    if (const auto now = std::chrono::steady_clock::now(); now >= next_progress) {
      std::cerr << "render: " << i + 1 << " of " << o.repeat << " frames ("
                << static_cast<long>(std::chrono::duration<double>(now - start).count()) << " s)"
                << std::endl;
      next_progress = now + kProgressInterval;
    }
  }
  // Counters are exact and identical in every repeat; the last run stands for them all.
  const FrameStats& last = runs.back();
  const double ms_median = median_of(runs, &FrameStats::ms_total);

  if (out_path) write_image(target, *out_path);

  std::string line =
      printable(name) + " " + std::to_string(target.width()) + "x" +
      std::to_string(target.height()) + " " + std::to_string(target.samples()) + "x" +
      (o.ssaa ? " ssaa" : "") + (o.painter ? " painter" : "") +
      (o.depth_only ? " depth-only" : "") + (o.nearest_first ? " nearest-first" : "") +
      (shading == Shading::kFlat ? "" : " " + shading_name(shading)) + ": " + format_ms(ms_median) +
      " ms median of " + std::to_string(o.repeat) + " (" + to_string(last.isa) + ", " +
      std::to_string(last.threads) + (last.threads == 1 ? " thread)" : " threads)");
  if (out_path) line += " -> " + printable(*out_path);
  std::cerr << line << '\n';

  if (o.stats) {
    nlohmann::ordered_json j;
    j["scene"] = name;
    j["width"] = target.width();
    j["height"] = target.height();
    j["samples"] = target.samples();
    j["ssaa"] = o.ssaa;
    j["painter"] = o.painter;
    j["depth_only"] = o.depth_only;
    j["nearest_first"] = o.nearest_first;
    j["shade"] = shading_name(shading);
    j["repeat"] = o.repeat;
    j["triangles_in"] = last.triangles_in;
    j["triangles_nonfinite"] = last.triangles_nonfinite;
    j["triangles_culled_face"] = last.triangles_culled_face;
    j["triangles_degenerate"] = last.triangles_degenerate;
    j["triangles_outside"] = last.triangles_outside;
    j["triangles_clipped"] = last.triangles_clipped;
    j["triangles_no_sample"] = last.triangles_no_sample;
    j["triangles_drawn"] = last.triangles_drawn;
    j["triangles_binned"] = last.triangles_binned;
    j["blocks_hiz_rejected"] = last.blocks_hiz_rejected;
    j["blocks_hiz_accepted"] = last.blocks_hiz_accepted;
    j["samples_tested"] = last.samples_tested;
    j["samples_written"] = last.samples_written;
    j["bytes_vertices"] = last.memory.vertices;
    j["bytes_setups"] = last.memory.setups;
    j["bytes_planes"] = last.memory.planes;
    j["bytes_bins"] = last.memory.bins;
    j["ms_median"] = ms_median;
    j["ms_first"] = runs.front().ms_total;  // the first frame of a new Renderer and target
    j["reserve"] = o.reserve;
    j["ms_reserve"] = ms_reserve;
    j["ms_setup"] = median_of(runs, &FrameStats::ms_setup);
    j["ms_binning"] = median_of(runs, &FrameStats::ms_binning);
    j["ms_raster"] = median_of(runs, &FrameStats::ms_raster);
    j["ms_resolve"] = median_of(runs, &FrameStats::ms_resolve);
    j["isa"] = to_string(last.isa);
    j["threads"] = last.threads;
    j["tile_size"] = last.tile_size;
    j["image_hash"] = hex64(target.image_hash());
    j["output"] = out_path ? nlohmann::ordered_json(*out_path) : nlohmann::ordered_json(nullptr);
    // Invalid UTF-8 in the scene's name (a file name) is written as U+FFFD, not thrown.
    std::cout << j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << std::endl;
  }
  return kExitOk;
}

}  // namespace

Command add_render_command(CLI::App& parent) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* app = parent.add_subcommand(
      "render", "Render a scene, print its time on stderr and write the image");
  app->add_option("SCENE", o->scene.arg,
                  "A built-in scene (see `mosaic scenes`), or a .tris or .obj file")
      ->capture_default_str();
  app->add_option("--msaa", o->msaa, "Samples per pixel")
      ->type_name("N")
      ->transform(integer_in(1, 16))
      ->check(CLI::IsMember({1, 4, 8, 16}))
      ->capture_default_str();
  app->add_flag("--ssaa", o->ssaa, "Shade every sample (supersampling) instead of every pixel");
  app->add_option("--threads", o->threads, "Worker threads; 0 = every hardware thread")
      ->type_name("N")
      ->transform(thread_count(0))
      ->capture_default_str();
  app->add_option("--fill-rule", o->fill_rule,
                  "Edge rule for every draw: d3d (top-left) or gl (bottom-left)")
      ->check(CLI::IsMember(keys_of(fill_rules())));
  app->add_option("--depth-test", o->depth_test,
                  "Depth test for every draw. off = no test, no depth writes, input order; "
                  "greater and greater-equal clear depth to 0 (reversed Z)")
      ->check(CLI::IsMember(keys_of(depth_choices())));
  app->add_option("--cull", o->cull, "Face culling for every draw")
      ->check(CLI::IsMember(keys_of(cull_modes())));
  app->add_flag("--depth-only", o->depth_only,
                "Depth only: no draw writes colour (an occluder pass; the image is the clear "
                "colour)");
  app->add_flag("--nearest-first", o->nearest_first,
                "Draw the occluders (depth-only draws that write depth) nearest first in each "
                "tile (Frame::occluders_nearest_first): the same depth, fewer samples tested");
  app->add_option("--shade", o->shade,
                  "How meshes are coloured: flat (their colours), normals (vertex normals as "
                  "colours), lambert (the normals lit per pixel) or uv (texture coordinates as "
                  "colours, for an OBJ file whose faces name them). Default: lambert for an OBJ "
                  "file without vertex colours, flat otherwise")
      ->check(CLI::IsMember(keys_of(shadings())));
  app->add_flag("--reserve", o->reserve,
                "Size the renderer's memory for the frame before the first one "
                "(Renderer::reserve), so that the first frame costs what the later ones do");
  app->add_flag("--painter", o->painter,
                "Painter's algorithm: no depth test, triangles sorted back to front");
  app->add_option("--repeat", o->repeat, "Render the frame N times and report the median")
      ->type_name("N")
      ->transform(integer_in(1, kMaxRepeat))
      ->capture_default_str();
  CLI::Option* out =
      app->add_option("--out", o->out,
                      "Image to write, .png or .ppm (default: <scene>.png in the current "
                      "directory; '-' writes none). Written whole, then renamed into place: a "
                      "symlink at FILE is replaced by the image, never written through")
          ->type_name("FILE");
  app->add_flag("--no-out", o->no_out, "Write no image")->excludes(out);
  app->add_flag("--stats", o->stats, "Print one JSON object of frame statistics on stdout");
  CLI::Option* isa = app->add_option("--isa", o->isa, "Instruction set of the tile kernels")
                         ->check(CLI::IsMember(keys_of(isa_names())))
                         ->capture_default_str();
  app->add_option("--tile-size", o->tile_size,
                  "Tile edge in pixels of the fast path: 8, 16, 32, 64 or 128; 0 = chosen by the "
                  "sample count (128 up to 4x, 64 beyond)")
      ->type_name("N")
      ->check(CLI::IsMember({0, 8, 16, 32, 64, 128}))
      ->capture_default_str();
  app->add_flag("--reference", o->reference,
                "Use the exact scalar reference rasterizer (= --isa reference)")
      ->excludes(isa);
  o->size_opt = app->add_option("--size", o->size,
                                "Target size WxH for built-in and OBJ scenes (default 1920x1080; "
                                ".tris files set their own)")
                    ->type_name("WxH")
                    ->check(size_validator());
  o->seed_opt = app->add_option("--seed", o->seed, "Random seed of built-in scenes (default 1)")
                    ->type_name("UINT")
                    ->transform(unsigned_integer());
  return Command{app, [o] { return run_render(*o); }};
}

}  // namespace mosaic::cli
