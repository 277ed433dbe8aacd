// bench/bench_features.cpp — what each feature of a draw costs, and occlusion culling (issue 7).
//
// Takes: nothing (linked into mosaic-bench, registered at start-up; run them with
// --benchmark_filter='^(features|occlusion)/'). Gives: wall-clock times (manual time, one
// Renderer::render or one batch of queries per iteration) of these cases, all on the built-in
// random-small scene (100k triangles of 10–50 px², random depths) at 1920×1080 on ONE thread with
// the best instruction set unless the name says otherwise:
//   features/<variant>/<S>x     whole frames, each variant changing one thing from color+depth
//                               (flat colour, `less` test with writes):
//                               depth-only (color_write off: no colour kept, shaded or resolved),
//                               depth-off (no test, no writes: no depth kept), interpolated
//                               (per-vertex colour), depth-only+hiz (keeping the hierarchical z);
//                               S = 1 and 4 samples
//   features/shader/<colour>/<S>x the cost of a shader: the same flat colour from the built-in
//                               constant-colour kernel (builtin), from flat_color_shader
//                               (shader: generic kernel, one batch call per 16 pixels), and with
//                               source-over blending on top (shader+blend)
//   features/varyings/<N>/1x    a shader summing N = 0, 4 or 8 varyings (random attributes):
//                               what perspective-correct interpolation costs per varying
//   features/depth-only/1x/<isa> the depth-only pass on every SIMD path: the comparison with
//                               Intel's Masked Occlusion Culling (100k triangles of 10–50 px²,
//                               depth-only, 1920×1080, one thread: 3.3–4.4 ms with AVX-512)
//   features/draws/<how>/16x    random-small at 4096×2160 16x as one draw, or as one draw per
//                               triangle (100k draws): the cost of a draw
//   occlusion/rects/<where>     100k rectangle queries (8–64 px, random depth) against the
//                               hierarchical z of the depth-only pass (random-small), or of a
//                               full-screen wall in front of every query (wall: all hidden, so
//                               every block of every query is visited)
//   occlusion/triangles/<where> 10k queries of 12 screen-space triangles (a box's faces)
//   occlusion/boxes/<where>     100k world-space boxes in one boxes_visible() call, through a
//                               perspective camera
// Counters: the FrameStats stage times per frame; for queries, queries/s, triangles/s and the
// fraction reported hidden.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "scenes/rng.hpp"

namespace {

using Rng = mosaic::SplitMix64;

using Clock = std::chrono::steady_clock;

/// The benchmark resolution and scene (the anchor's triangle count and sizes).
constexpr int kWidth = 1920, kHeight = 1080;
constexpr const char* kScene = "random-small";
constexpr std::uint64_t kSceneSeed = 1;  ///< the CLI's default seed, as in mosaic_bench.cpp
/// Frames of 10–60 ms: a few dozen per repetition.
constexpr double kMinTime = 0.3;
/// Query batches: enough queries that a batch takes milliseconds, not microseconds.
constexpr int kRectQueries = 100'000;
constexpr int kTriangleQueries = 10'000;
constexpr int kTrianglesPerBox = 12;
/// Query sizes in pixels: from about one block to a few tiles' worth of blocks.
constexpr double kQueryMinPx = 8, kQueryMaxPx = 64;

enum class Variant { kColorDepth, kDepthOnly, kDepthOff, kInterpolated, kDepthOnlyHiz };

const char* name(Variant v) {
  switch (v) {
    case Variant::kColorDepth:
      return "color+depth";
    case Variant::kDepthOnly:
      return "depth-only";
    case Variant::kDepthOff:
      return "depth-off";
    case Variant::kInterpolated:
      return "interpolated";
    case Variant::kDepthOnlyHiz:
      return "depth-only+hiz";
  }
  return "?";
}

/// random-small with every draw set to `v` (built once per variant).
const mosaic::Scene& scene(Variant v) {
  static std::map<Variant, std::unique_ptr<mosaic::Scene>> cache;
  auto& slot = cache[v];
  if (slot) return *slot;
  mosaic::Scene s = mosaic::builtin_scene(kScene, kWidth, kHeight, kSceneSeed);
  for (mosaic::Mesh& m : s.meshes) {
    m.state.depth_test = mosaic::DepthTest::kLess;
    m.state.depth_write = true;
    if (v == Variant::kDepthOnly || v == Variant::kDepthOnlyHiz) m.state.color_write = false;
    if (v == Variant::kDepthOff) {
      m.state.depth_test = mosaic::DepthTest::kAlways;
      m.state.depth_write = false;
    }
    if (v == Variant::kInterpolated && m.color_source == mosaic::ColorSource::kPerTriangle) {
      // Three different colours per triangle: its own and two rotations of its channels.
      std::vector<mosaic::Rgba8> per_vertex;
      for (const mosaic::Rgba8& c : m.colors) {
        per_vertex.push_back(c);
        per_vertex.push_back({c.g, c.b, c.r, c.a});
        per_vertex.push_back({c.b, c.r, c.g, c.a});
      }
      m.colors = std::move(per_vertex);
      m.color_source = mosaic::ColorSource::kPerVertex;
    }
  }
  slot = std::make_unique<mosaic::Scene>(std::move(s));
  return *slot;
}

/// How the shader cases colour random-small (features/shader and features/varyings).
enum class Shading { kNone, kBuiltinFlat, kFlatShader, kFlatShaderBlend, kVaryings };

/// Attributes per vertex of the varyings cases: the most any case reads.
constexpr std::uint32_t kBenchAttributes = 8;

/// A shader that sums N varyings into its colour (so that none is optimised away).
template <int N>
mosaic::Shader sum_shader() {
  return mosaic::make_shader(
      [](const mosaic::Fragment& f) {
        float sum = 0.0f;
        for (int k = 0; k < N; ++k) sum += f.varying(k);
        return glm::vec4(0.5f + 0.1f * sum, 0.25f, 0.75f, 1.0f);
      },
      N);
}

/// The draws of random-small coloured as `shading` asks (N varyings for kVaryings). The
/// attribute buffers live as long as the program.
std::vector<mosaic::Draw> shaded_draws(const mosaic::Scene& sc, Shading shading, int varyings) {
  static std::map<const mosaic::Mesh*, std::vector<float>> attributes;
  static const std::uint32_t kAll[kBenchAttributes] = {0, 1, 2, 3, 4, 5, 6, 7};
  std::vector<mosaic::Draw> draws = sc.draws();
  if (shading == Shading::kNone) return draws;
  const glm::vec4 flat(0.8f, 0.4f, 0.2f, 0.6f);
  for (std::size_t i = 0; i < draws.size(); ++i) {
    mosaic::Draw& d = draws[i];
    d.color_source = mosaic::ColorSource::kConstant;
    d.color = {204, 102, 51, 153};  // the same colour as `flat`, in 8 bits
    if (shading == Shading::kBuiltinFlat) continue;
    if (shading != Shading::kVaryings) {
      d.shader = mosaic::flat_color_shader(flat);
      if (shading == Shading::kFlatShaderBlend) d.state.blend = mosaic::BlendMode::kSourceOver;
      continue;
    }
    std::vector<float>& a = attributes[&sc.meshes[i]];
    if (a.empty()) {
      Rng rng{11};
      a.resize(sc.meshes[i].positions.size() * kBenchAttributes);
      for (float& x : a) x = static_cast<float>(rng.uniform(0, 1));
    }
    d.attributes = a;
    d.attribute_count = kBenchAttributes;
    d.varyings = std::span<const std::uint32_t>(kAll, static_cast<std::size_t>(varyings));
    d.shader = varyings == 0 ? sum_shader<0>() : varyings == 4 ? sum_shader<4>() : sum_shader<8>();
  }
  return draws;
}

void bench_frame(benchmark::State& state, Variant v, int samples, mosaic::Isa isa,
                 Shading shading = Shading::kNone, int varyings = 0) {
  const mosaic::Scene& sc = scene(v);
  mosaic::Renderer renderer({1, isa});
  mosaic::RenderTarget target(sc.width, sc.height, samples);
  target.set_clear(sc.clear_color, sc.clear_depth);
  const std::vector<mosaic::Draw> draws = shaded_draws(sc, shading, varyings);
  mosaic::Frame frame;
  frame.draws = draws;
  frame.keep_hierarchical_z = v == Variant::kDepthOnlyHiz;
  renderer.render(frame, target);  // warm-up: memory at its steady size, caches warm
  double setup = 0, binning = 0, raster = 0, n = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const mosaic::FrameStats st = renderer.render(frame, target);
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
    setup += st.ms_setup;
    binning += st.ms_binning;
    raster += st.ms_raster;
    n += 1;
  }
  if (n > 0) {
    state.counters["ms_setup"] = setup / n;
    state.counters["ms_binning"] = binning / n;
    state.counters["ms_raster"] = raster / n;  // tiles: clear, triangles, resolve
  }
  state.SetLabel(mosaic::to_string(renderer.isa()));
}

/// The hierarchical z the queries run against: the depth-only random-small pass, or a
/// full-screen wall at depth 0.25 (the queries lie at 0.3–1: all hidden).
const mosaic::HierarchicalZ& occluders(bool wall) {
  static std::map<bool, std::unique_ptr<mosaic::HierarchicalZ>> cache;
  auto& slot = cache[wall];
  if (slot) return *slot;
  mosaic::Scene sc = scene(Variant::kDepthOnly);
  std::vector<glm::vec4> quad;
  if (wall) {
    const float w = kWidth, h = kHeight, z = 0.25f;
    quad = {{0, 0, z, 1}, {w, 0, z, 1}, {w, h, z, 1}, {0, 0, z, 1}, {w, h, z, 1}, {0, h, z, 1}};
  }
  std::vector<mosaic::Draw> draws = sc.draws();
  if (wall) {
    mosaic::Draw d;
    d.space = mosaic::Space::kScreen;
    d.positions = quad;
    d.state.color_write = false;
    draws = {d};
  }
  mosaic::Frame frame;
  frame.draws = draws;
  frame.keep_hierarchical_z = true;
  mosaic::Renderer renderer({1});
  mosaic::RenderTarget target(kWidth, kHeight);
  renderer.render(frame, target);
  slot = std::make_unique<mosaic::HierarchicalZ>(renderer.hierarchical_z());
  return *slot;
}

void bench_rects(benchmark::State& state, bool wall) {
  const mosaic::HierarchicalZ& hiz = occluders(wall);
  Rng rng{3};
  std::vector<mosaic::ScreenRect> rects(kRectQueries);
  std::vector<float> depth(kRectQueries);
  for (int i = 0; i < kRectQueries; ++i) {
    const double x = rng.uniform(0, kWidth), y = rng.uniform(0, kHeight);
    rects[i] = {static_cast<float>(x), static_cast<float>(y),
                static_cast<float>(x + rng.uniform(kQueryMinPx, kQueryMaxPx)),
                static_cast<float>(y + rng.uniform(kQueryMinPx, kQueryMaxPx))};
    depth[i] = static_cast<float>(rng.uniform(0.3, 1.0));
  }
  std::int64_t hidden = 0, queries = 0;
  double seconds = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    std::int64_t h = 0;
    for (int i = 0; i < kRectQueries; ++i) h += !hiz.rect_visible(rects[i], depth[i]);
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    state.SetIterationTime(s);
    benchmark::DoNotOptimize(h);
    hidden += h;
    queries += kRectQueries;
    seconds += s;
  }
  if (seconds > 0) {
    state.counters["Mrects/s"] = static_cast<double>(queries) / seconds * 1e-6;
    state.counters["hidden"] = static_cast<double>(hidden) / static_cast<double>(queries);
  }
}

void bench_triangles(benchmark::State& state, bool wall) {
  const mosaic::HierarchicalZ& hiz = occluders(wall);
  Rng rng{5};
  // Each query: the six faces of a box, seen slightly from one corner, as 12 screen triangles.
  std::vector<std::vector<glm::vec4>> boxes(kTriangleQueries);
  for (auto& b : boxes) {
    const double x = rng.uniform(0, kWidth), y = rng.uniform(0, kHeight);
    const double s = rng.uniform(kQueryMinPx, kQueryMaxPx), z = rng.uniform(0.3, 0.95);
    const double d = s * 0.3;  // the back face's offset on screen
    auto p = [&](double px, double py, double pz) {
      return glm::vec4(static_cast<float>(px), static_cast<float>(py), static_cast<float>(pz), 1);
    };
    const glm::vec4 c[8] = {p(x, y, z),
                            p(x + s, y, z),
                            p(x + s, y + s, z),
                            p(x, y + s, z),
                            p(x + d, y - d, z + .05),
                            p(x + s + d, y - d, z + .05),
                            p(x + s + d, y + s - d, z + .05),
                            p(x + d, y + s - d, z + .05)};
    const int faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 2, 6, 5}};
    for (const auto& f : faces)
      for (int k : {f[0], f[1], f[2], f[0], f[2], f[3]}) b.push_back(c[k]);
  }
  std::int64_t hidden = 0, queries = 0;
  double seconds = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    std::int64_t h = 0;
    for (const auto& b : boxes) {
      mosaic::Draw d;
      d.space = mosaic::Space::kScreen;
      d.positions = b;
      h += !hiz.draw_visible(d);
    }
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    state.SetIterationTime(s);
    benchmark::DoNotOptimize(h);
    hidden += h;
    queries += kTriangleQueries;
    seconds += s;
  }
  if (seconds > 0) {
    state.counters["Kqueries/s"] = static_cast<double>(queries) / seconds * 1e-3;
    state.counters["Mtri/s"] = static_cast<double>(queries) * kTrianglesPerBox / seconds * 1e-6;
    state.counters["hidden"] = static_cast<double>(hidden) / static_cast<double>(queries);
  }
}

/// World boxes for the batched box queries: 100k boxes of 0.1 to 1 unit through a camera 20 units
/// from the origin, 2 to 60 px wide on the screen, spread over the view and in depth.
constexpr int kBoxQueries = 100'000;

void bench_boxes(benchmark::State& state, bool wall) {
  const mosaic::HierarchicalZ& hiz = occluders(wall);
  const glm::mat4 vp =
      glm::perspectiveRH_ZO(glm::radians(60.0f), float(kWidth) / kHeight, 1.0f, 100.0f) *
      glm::lookAtRH(glm::vec3(0, 0, 20), glm::vec3(0), glm::vec3(0, 1, 0));
  Rng rng{7};
  std::vector<mosaic::Box> boxes(kBoxQueries);
  for (mosaic::Box& b : boxes) {
    const glm::vec3 c(rng.uniform(-15, 15), rng.uniform(-8, 8), rng.uniform(-30, 15));
    const float e = static_cast<float>(rng.uniform(0.05, 0.5));
    b = {c - e, c + e};
  }
  std::vector<std::uint8_t> visible(boxes.size());
  std::int64_t hidden = 0, queries = 0;
  double seconds = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    hiz.boxes_visible(boxes, vp, visible);
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    state.SetIterationTime(s);
    for (std::uint8_t v : visible) hidden += !v;
    queries += kBoxQueries;
    seconds += s;
  }
  if (seconds > 0) {
    state.counters["Mboxes/s"] = static_cast<double>(queries) / seconds * 1e-6;
    state.counters["hidden"] = static_cast<double>(hidden) / static_cast<double>(queries);
  }
}

/// The many-draws case: random-small's 100k triangles at 4096×2160 16x, as one draw or as one
/// draw per triangle. What a frame costs per draw must not grow with the tile count.
constexpr int kDrawsWidth = 4096, kDrawsHeight = 2160, kDrawsSamples = 16;

void bench_draws(benchmark::State& state, bool per_triangle) {
  static const mosaic::Scene sc =
      mosaic::builtin_scene(kScene, kDrawsWidth, kDrawsHeight, kSceneSeed);
  std::vector<mosaic::Draw> draws = sc.draws();
  if (per_triangle) {
    std::vector<mosaic::Draw> split;
    for (const mosaic::Draw& d : draws)
      for (std::size_t t = 0; t < d.positions.size() / 3; ++t) {
        mosaic::Draw one = d;
        one.positions = d.positions.subspan(3 * t, 3);
        one.colors = d.colors.subspan(t, 1);
        split.push_back(one);
      }
    draws = std::move(split);
  }
  mosaic::Renderer renderer({1});
  mosaic::RenderTarget target(sc.width, sc.height, kDrawsSamples);
  mosaic::Frame frame;
  frame.draws = draws;
  renderer.render(frame, target);  // warm-up
  for (auto _ : state) {
    const auto t0 = Clock::now();
    renderer.render(frame, target);
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  state.counters["draws"] = static_cast<double>(draws.size());
}

benchmark::internal::Benchmark* configure(benchmark::internal::Benchmark* b) {
  return b->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(kMinTime);
}

/// Registers the cases when mosaic-bench starts (before its main() registers its own).
const bool registered = [] {
  for (Variant v : {Variant::kColorDepth, Variant::kDepthOnly, Variant::kDepthOff,
                    Variant::kInterpolated, Variant::kDepthOnlyHiz})
    for (int samples : {1, 4})
      configure(benchmark::RegisterBenchmark(
          (std::string("features/") + name(v) + "/" + std::to_string(samples) + "x").c_str(),
          [=](benchmark::State& st) { bench_frame(st, v, samples, mosaic::Isa::kAuto); }));
  const std::pair<const char*, Shading> shader_cases[] = {
      {"builtin", Shading::kBuiltinFlat},
      {"shader", Shading::kFlatShader},
      {"shader+blend", Shading::kFlatShaderBlend}};
  for (const auto& [label, shading] : shader_cases)
    for (int samples : {1, 4})
      configure(benchmark::RegisterBenchmark(
          (std::string("features/shader/") + label + "/" + std::to_string(samples) + "x").c_str(),
          [=](benchmark::State& st) {
            bench_frame(st, Variant::kColorDepth, samples, mosaic::Isa::kAuto, shading);
          }));
  for (int n : {0, 4, 8})
    configure(benchmark::RegisterBenchmark(
        ("features/varyings/" + std::to_string(n) + "/1x").c_str(), [=](benchmark::State& st) {
          bench_frame(st, Variant::kColorDepth, 1, mosaic::Isa::kAuto, Shading::kVaryings, n);
        }));
  for (mosaic::Isa isa : mosaic::available_isas()) {
    if (isa == mosaic::Isa::kReference) continue;
    configure(benchmark::RegisterBenchmark(
        (std::string("features/depth-only/1x/") + mosaic::to_string(isa)).c_str(),
        [=](benchmark::State& st) { bench_frame(st, Variant::kDepthOnly, 1, isa); }));
  }
  for (bool per_triangle : {false, true})
    configure(benchmark::RegisterBenchmark(
        per_triangle ? "features/draws/per-triangle/16x" : "features/draws/one/16x",
        [=](benchmark::State& st) { bench_draws(st, per_triangle); }));
  for (bool wall : {false, true}) {
    const std::string where = wall ? "wall" : kScene;
    configure(benchmark::RegisterBenchmark(("occlusion/rects/" + where).c_str(),
                                           [=](benchmark::State& st) { bench_rects(st, wall); }));
    configure(
        benchmark::RegisterBenchmark(("occlusion/triangles/" + where).c_str(),
                                     [=](benchmark::State& st) { bench_triangles(st, wall); }));
    configure(benchmark::RegisterBenchmark(("occlusion/boxes/" + where).c_str(),
                                           [=](benchmark::State& st) { bench_boxes(st, wall); }));
  }
  return true;
}();

}  // namespace
