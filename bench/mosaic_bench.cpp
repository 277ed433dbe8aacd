// bench/mosaic_bench.cpp — the Google Benchmark suite of mosaic (issue 3, "Performance").
//
// Takes: Google Benchmark's flags, and --mosaic_smoke (every case runs one iteration: the ctest
// smoke run). Gives: wall-clock times (manual time, one Renderer::render or one stage per
// iteration) of these cases, every built-in scene at 1920×1080 (the stage cases all but the
// dense-mesh knot scenes):
//   frame/<scene>/<S>x/t<T>          whole frames, clear to resolved image, S = 1 and 4 samples,
//                                    T = 1 and 2 threads; per-stage times from FrameStats
//   lit/<mesh scene>/<S>x/t<T>       the knot scenes' frames lit per pixel (Shading::kLambert:
//                                    their normals as varyings through lambert_shader)
//   stage/setup/<scene>/t<T>         the front end alone (transform, clip, cull, snap, set up)
//   stage/binning/<scene>/t<T>       binning alone, over the front end's output
//   stage/raster/<scene>/4x/t<T>     the tile kernels alone over ready bins (each tile: clear,
//                                    triangles, in-tile resolve; the kernel cannot be split)
//   stage/resolve/<S>x/t<T>          the tile kernels over empty bins: each tile writes the clear
//                                    values (resolve/clear_tile.hpp)
//   isa/<scene>/4x/<isa>             one thread, each instruction set of available_isas(),
//                                    the scalar reference included, for the speed-up table
// Counters (plain per-frame values, so repetitions aggregate them as they are): Mtri/s of
// submitted triangles, Gsamples/s of FrameStats::samples_tested (covered samples that reached the
// depth test: hierarchical-z rejected blocks are not counted), samples per TSC cycle per thread,
// and the FrameStats stage times. bench/run-benchmarks.sh runs it and prints the README tables.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

#include "bin/binner.hpp"
#include "front/front_end.hpp"
#include "isa_dispatch.hpp"
#include "mosaic/mosaic.hpp"
#include "raster/tile.hpp"

namespace {

using Clock = std::chrono::steady_clock;

/// The benchmark resolution.
constexpr int kWidth = 1920, kHeight = 1080;
/// Seed of the random built-in scenes: the CLI's default, so `mosaic render` draws the same.
constexpr std::uint64_t kSceneSeed = 1;
/// Sample counts and thread counts the issue asks for.
constexpr int kSampleCounts[] = {1, 4};
constexpr int kThreadCounts[] = {1, 2};
/// The sample count of the isolated raster stage and of the ISA comparison: the issue's
/// targets are at 4x, and 1x frames are covered by frame/ already.
constexpr int kStageSamples = 4;
/// Scenes whose reference frame at 4x stays well under a second on this machine (default
/// ~90 ms, random-small ~350 ms, star ~90 ms, fan ~60 ms); slivers takes ~4.6 s and
/// random-large longer, so they are left out of the speed-up table.
const char* const kIsaScenes[] = {"default", "random-small", "star", "fan"};
/// The dense-mesh scenes (65k to 2 M triangles, 10–300 ms a frame): each repetition times a
/// fixed kMeshFrameIterations frames instead of searching for kFrameMinTime (which ran 2–5 frames
/// after a probe), and they have no isolated stage cases (their frames' FrameStats split the
/// stages).
const char* const kMeshScenes[] = {"knot", "knot-100px", "knot-30px", "knot-65k", "knot-2m"};
constexpr int kMeshFrameIterations = 2;

/// Minimum time per repetition: long enough that a 3 ms frame is timed ~60 times, short enough
/// that the whole suite with 5 repetitions stays within about 5 minutes on 2 cores. Frames
/// longer than this run once per repetition.
constexpr double kFrameMinTime = 0.2;
/// Isolated stages are cheaper and repeat the frames' work, so they get less.
constexpr double kStageMinTime = 0.1;
/// The ISA cases include the reference (60–350 ms a frame): one or two frames per repetition.
constexpr double kIsaMinTime = 0.3;
/// How long the TSC is calibrated against steady_clock: 1 µs of clock granularity over this is
/// well under 0.1 %.
constexpr auto kTscCalibration = std::chrono::milliseconds(200);

bool g_smoke = false;  ///< --mosaic_smoke: one iteration per case, for the ctest smoke run

std::uint64_t tsc() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return 0;  // no TSC: the per-cycle counter reads 0
#endif
}

/// TSC ticks per second, measured against steady_clock. The TSC ticks at the nominal
/// frequency (constant_tsc), not at the turbo clock the cores actually run at.
double calibrate_tsc() {
  const auto t0 = Clock::now();
  const std::uint64_t c0 = tsc();
  std::this_thread::sleep_for(kTscCalibration);
  const std::uint64_t c1 = tsc();
  const auto t1 = Clock::now();
  return static_cast<double>(c1 - c0) / std::chrono::duration<double>(t1 - t0).count();
}

/// A built-in scene at the benchmark size with every draw forced to flat colour and a `less`
/// depth test with depth writes, as the issue specifies. Only "default" differs from that as
/// built (its cube, octahedron and crossing triangles have per-vertex colour): each of its
/// triangles takes the colour of its first vertex instead. Scenes are built once and shared.
const mosaic::Scene& bench_scene(const std::string& name) {
  static std::map<std::string, std::unique_ptr<mosaic::Scene>> cache;
  auto& slot = cache[name];
  if (slot) return *slot;
  mosaic::Scene s = mosaic::builtin_scene(name, kWidth, kHeight, kSceneSeed);
  for (mosaic::Mesh& m : s.meshes) {
    m.state.depth_test = mosaic::DepthTest::kLess;
    m.state.depth_write = true;
    if (m.color_source == mosaic::ColorSource::kPerVertex) {
      std::vector<mosaic::Rgba8> flat(m.triangle_count());
      for (std::size_t t = 0; t < flat.size(); ++t)
        flat[t] = m.colors[m.indices.empty() ? 3 * t : m.indices[3 * t]];
      m.colors = std::move(flat);
      m.color_source = mosaic::ColorSource::kPerTriangle;
    }
  }
  slot = std::make_unique<mosaic::Scene>(std::move(s));
  return *slot;
}

/// Sums over the timed iterations of a case.
struct Totals {
  double seconds = 0;
  std::uint64_t cycles = 0, iterations = 0, triangles = 0, samples = 0;
  double ms_setup = 0, ms_binning = 0, ms_raster = 0, ms_resolve = 0;

  void add(double s, std::uint64_t c) {
    seconds += s;
    cycles += c;
    ++iterations;
  }
};

/// Times one call of `body` as this iteration's manual time, and counts it into `tot`.
template <class F>
void timed(benchmark::State& state, Totals& tot, F&& body) {
  const auto t0 = Clock::now();
  const std::uint64_t c0 = tsc();
  body();
  const std::uint64_t c1 = tsc();
  const auto t1 = Clock::now();
  const double s = std::chrono::duration<double>(t1 - t0).count();
  state.SetIterationTime(s);
  tot.add(s, c1 - c0);
}

/// Throughput counters: per-frame work divided by the measured time; samples per TSC cycle are
/// divided by the thread count, so that one fully used core at that rate reads the same at any T.
void set_throughput(benchmark::State& state, const Totals& tot, int threads, bool with_samples) {
  if (tot.iterations == 0 || tot.seconds <= 0) return;
  const double n = static_cast<double>(tot.iterations);
  state.counters["tris"] = static_cast<double>(tot.triangles) / n;
  state.counters["Mtri/s"] = static_cast<double>(tot.triangles) / tot.seconds * 1e-6;
  if (!with_samples) return;  // setup and binning test no samples
  state.counters["samples"] = static_cast<double>(tot.samples) / n;
  state.counters["Gsamples/s"] = static_cast<double>(tot.samples) / tot.seconds * 1e-9;
  state.counters["samples/tsc_cycle/thread"] =
      tot.cycles == 0
          ? 0.0
          : static_cast<double>(tot.samples) / static_cast<double>(tot.cycles) / threads;
}

/// Whole frames through the public API.
void bench_frame(benchmark::State& state, const std::string& scene_name, int samples, int threads,
                 mosaic::Isa isa, mosaic::Shading shading = mosaic::Shading::kFlat) {
  const mosaic::Scene& scene = bench_scene(scene_name);
  mosaic::RendererOptions options;
  options.threads = threads;
  options.isa = isa;
  mosaic::Renderer renderer(options);
  mosaic::RenderTarget target(scene.width, scene.height, samples);
  target.set_clear(scene.clear_color, scene.clear_depth);
  const std::vector<mosaic::Draw> draws = scene.draws(shading);
  mosaic::Frame frame;
  frame.draws = draws;
  // Warm-up frame: the renderer's per-frame memory reaches its steady size, caches are warm.
  renderer.render(frame, target);

  Totals tot;
  for (auto _ : state) {
    mosaic::FrameStats st;
    timed(state, tot, [&] { st = renderer.render(frame, target); });
    tot.triangles += st.triangles_in;
    tot.samples += st.samples_tested;
    tot.ms_setup += st.ms_setup;
    tot.ms_binning += st.ms_binning;
    tot.ms_raster += st.ms_raster;
    tot.ms_resolve += st.ms_resolve;
  }
  set_throughput(state, tot, renderer.threads(), true);
  if (tot.iterations > 0) {
    const double n = static_cast<double>(tot.iterations);
    state.counters["ms_setup"] = tot.ms_setup / n;
    state.counters["ms_binning"] = tot.ms_binning / n;
    state.counters["ms_raster"] = tot.ms_raster / n;    // includes the in-tile resolve
    state.counters["ms_resolve"] = tot.ms_resolve / n;  // summed over the worker threads
  }
  state.counters["threads"] = renderer.threads();
}

/// The stages below frame.cpp's Renderer, driven as frame.cpp drives them (same chunking, same
/// tile order and partitioner) so that their times can be read next to the FrameStats ones.
struct StageRig {
  const mosaic::Scene& scene;
  std::vector<mosaic::Draw> draws;
  std::vector<mosaic::DrawState> states;
  mosaic::bin::ChunkPlan plan;
  std::vector<mosaic::bin::Chunk> chunks;
  mosaic::bin::TileGrid grid;
  std::span<const mosaic::raster::SampleOffset> pattern;  ///< setup culls by it
  std::unique_ptr<tbb::global_control> parallelism;       // outlives the arena
  tbb::task_arena arena;
  mosaic::raster::TileKernel kernel = nullptr;
  mosaic::front::FrontEnd front_end = nullptr;  ///< the SIMD front end of the kernel's ISA
  tbb::enumerable_thread_specific<mosaic::raster::TileScratch> scratch;
  tbb::enumerable_thread_specific<std::vector<mosaic::raster::BinRun>> runs;

  /// `samples`: the sample count the tiles will be rasterized with, which picks the tile size.
  StageRig(const mosaic::Scene& s, int samples, int threads)
      : scene(s),
        draws(s.draws()),
        grid(s.width, s.height, mosaic::default_tile_size(samples)),
        pattern(mosaic::raster::sample_pattern(samples)),
        parallelism(threads > tbb::info::default_concurrency()
                        ? std::make_unique<tbb::global_control>(
                              tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads))
                        : nullptr),
        arena(threads),
        kernel(mosaic::dispatch::tile_kernel(mosaic::available_isas().back())),
        front_end(mosaic::dispatch::front_end(mosaic::available_isas().back())) {
    for (const mosaic::Draw& d : draws) states.push_back(d.state);
    std::vector<std::uint32_t> draw_triangles;
    for (const mosaic::Draw& d : draws) draw_triangles.push_back(mosaic::front::triangle_count(d));
    plan.build(draw_triangles, mosaic::bin::kChunkTriangles);
    chunks.resize(plan.chunks());
  }

  void setup() {
    arena.execute([&] {
      tbb::parallel_for(std::size_t{0}, chunks.size(), [&](std::size_t i) {
        mosaic::front::FrontStats fs;
        mosaic::bin::set_up_chunk(chunks[i], plan.pieces(i), draws, front_end, scene.width,
                                  scene.height, static_cast<int>(pattern.size()), fs);
      });
    });
  }

  void binning() {
    arena.execute([&] {
      tbb::parallel_for(std::size_t{0}, chunks.size(),
                        [&](std::size_t i) { mosaic::bin::bin_chunk(chunks[i], grid); });
    });
  }

  /// Every tile through the kernel, busiest first; with `empty`, no tile gets any triangle.
  mosaic::raster::TileStats raster(mosaic::RenderTarget& target, bool empty) {
    mosaic::bin::TileChunks tile_chunks;
    tile_chunks.build(chunks, grid.count());
    std::vector<std::pair<std::uint64_t, int>> order;
    for (int t = 0; t < grid.count(); ++t)
      order.push_back({empty ? 0 : tile_chunks.triangles(chunks, t), t});
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    mosaic::raster::TileFrame tf;
    tf.states = states;
    tf.samples = target.samples();
    tf.tile_size = grid.size;
    tf.clear_color = target.clear_color();
    tf.clear_depth = target.clear_depth();
    tf.width = target.width();
    tf.height = target.height();
    const mosaic::RenderTarget::ImageSurface image = target.image_surface();
    tf.image = image.base;
    tf.image_stride = image.stride_bytes;
    tbb::enumerable_thread_specific<mosaic::raster::TileStats> stats;
    arena.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, order.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& r) {
            mosaic::raster::TileScratch& sc = scratch.local();
            std::vector<mosaic::raster::BinRun>& bin = runs.local();
            mosaic::raster::TileStats& ts = stats.local();
            for (std::size_t k = r.begin(); k != r.end(); ++k) {
              const int t = order[k].second;
              bin.clear();
              if (!empty) {
                for (const mosaic::bin::TileChunks::Entry& e : tile_chunks.of(t))
                  mosaic::bin::append_runs(chunks[e.chunk], e.bin, bin);
              }
              kernel(tf, grid.rect(t), bin, sc, ts);
            }
          },
          tbb::simple_partitioner());
    });
    mosaic::raster::TileStats total;
    for (const auto& s : stats) total += s;
    return total;
  }
};

void bench_setup(benchmark::State& state, const std::string& scene_name, int threads) {
  StageRig rig(bench_scene(scene_name), kStageSamples, threads);
  rig.setup();  // warm-up: the chunks' vectors reach their size
  Totals tot;
  for (auto _ : state) {
    timed(state, tot, [&] { rig.setup(); });
    tot.triangles += rig.scene.triangle_count();
  }
  set_throughput(state, tot, threads, false);
}

void bench_binning(benchmark::State& state, const std::string& scene_name, int threads) {
  StageRig rig(bench_scene(scene_name), kStageSamples, threads);
  rig.setup();
  rig.binning();
  Totals tot;
  for (auto _ : state) {
    timed(state, tot, [&] { rig.binning(); });
    tot.triangles += rig.scene.triangle_count();
  }
  set_throughput(state, tot, threads, false);
}

void bench_raster(benchmark::State& state, const std::string& scene_name, int samples,
                  int threads) {
  StageRig rig(bench_scene(scene_name), samples, threads);
  mosaic::RenderTarget target(rig.scene.width, rig.scene.height, samples);
  target.set_clear(rig.scene.clear_color, rig.scene.clear_depth);
  rig.setup();
  rig.binning();
  rig.raster(target, false);
  Totals tot;
  double resolve_ms = 0;
  for (auto _ : state) {
    mosaic::raster::TileStats ts;
    timed(state, tot, [&] { ts = rig.raster(target, false); });
    tot.triangles += rig.scene.triangle_count();
    tot.samples += ts.samples_tested;
    resolve_ms += static_cast<double>(ts.resolve_ns) * 1e-6;
  }
  set_throughput(state, tot, threads, true);
  if (tot.iterations > 0)
    state.counters["ms_resolve"] = resolve_ms / static_cast<double>(tot.iterations);
}

void bench_resolve(benchmark::State& state, int samples, int threads) {
  // Any scene will do: only its size and clear values are used.
  StageRig rig(bench_scene("star"), samples, threads);
  mosaic::RenderTarget target(rig.scene.width, rig.scene.height, samples);
  target.set_clear(rig.scene.clear_color, rig.scene.clear_depth);
  rig.raster(target, true);
  Totals tot;
  double resolve_ms = 0;
  for (auto _ : state) {
    mosaic::raster::TileStats ts;
    timed(state, tot, [&] { ts = rig.raster(target, true); });
    resolve_ms += static_cast<double>(ts.resolve_ns) * 1e-6;
  }
  if (tot.iterations > 0) {
    state.counters["ms_resolve"] = resolve_ms / static_cast<double>(tot.iterations);
    state.counters["Gpixels/s"] = static_cast<double>(rig.scene.width) * rig.scene.height *
                                  static_cast<double>(tot.iterations) / tot.seconds * 1e-9;
  }
}

/// Common settings: wall-clock time as measured around each call, in milliseconds. `iterations`
/// > 0 fixes the frames per repetition instead of min_time.
benchmark::internal::Benchmark* configure(benchmark::internal::Benchmark* b, double min_time,
                                          int iterations = 0) {
  b->UseManualTime()->Unit(benchmark::kMillisecond);
  if (g_smoke) return b->Iterations(1);
  if (iterations > 0) return b->Iterations(iterations);
  return b->MinTime(min_time);
}

bool is_mesh_scene(const std::string& name) {
  return std::find(std::begin(kMeshScenes), std::end(kMeshScenes), name) != std::end(kMeshScenes);
}

// Built by appending: GCC 12 gives a false -Wrestrict error (-O3) on "t" + std::to_string(n).
std::string threads_tag(int threads) {
  std::string tag = "t";
  tag += std::to_string(threads);
  return tag;
}
std::string samples_tag(int samples) { return std::to_string(samples) + "x"; }

void register_all() {
  using mosaic::Isa;
  const std::vector<std::string> scenes = mosaic::builtin_scene_names();
  for (const std::string& s : scenes)
    for (int S : kSampleCounts)
      for (int T : kThreadCounts)
        configure(benchmark::RegisterBenchmark(
                      ("frame/" + s + "/" + samples_tag(S) + "/" + threads_tag(T)).c_str(),
                      [=](benchmark::State& st) { bench_frame(st, s, S, T, Isa::kAuto); }),
                  kFrameMinTime, is_mesh_scene(s) ? kMeshFrameIterations : 0);
  // The mesh scenes lit per pixel (their normals through lambert_shader), beside frame/'s flat
  // draws of the same meshes.
  for (const char* s : kMeshScenes)
    for (int S : kSampleCounts)
      for (int T : kThreadCounts)
        configure(
            benchmark::RegisterBenchmark(
                (std::string("lit/") + s + "/" + samples_tag(S) + "/" + threads_tag(T)).c_str(),
                [=](benchmark::State& st) {
                  bench_frame(st, s, S, T, Isa::kAuto, mosaic::Shading::kLambert);
                }),
            kFrameMinTime, kMeshFrameIterations);
  for (const std::string& s : scenes) {
    if (is_mesh_scene(s)) continue;
    for (int T : kThreadCounts) {
      configure(benchmark::RegisterBenchmark(("stage/setup/" + s + "/" + threads_tag(T)).c_str(),
                                             [=](benchmark::State& st) { bench_setup(st, s, T); }),
                kStageMinTime);
      configure(
          benchmark::RegisterBenchmark(("stage/binning/" + s + "/" + threads_tag(T)).c_str(),
                                       [=](benchmark::State& st) { bench_binning(st, s, T); }),
          kStageMinTime);
      configure(benchmark::RegisterBenchmark(
                    ("stage/raster/" + s + "/" + samples_tag(kStageSamples) + "/" + threads_tag(T))
                        .c_str(),
                    [=](benchmark::State& st) { bench_raster(st, s, kStageSamples, T); }),
                kStageMinTime);
    }
  }
  for (int S : kSampleCounts)
    for (int T : kThreadCounts)
      configure(benchmark::RegisterBenchmark(
                    ("stage/resolve/" + samples_tag(S) + "/" + threads_tag(T)).c_str(),
                    [=](benchmark::State& st) { bench_resolve(st, S, T); }),
                kStageMinTime);
  for (const char* s : kIsaScenes)
    for (Isa isa : mosaic::available_isas())
      configure(benchmark::RegisterBenchmark(
                    (std::string("isa/") + s + "/" + samples_tag(kStageSamples) + "/" +
                     mosaic::to_string(isa))
                        .c_str(),
                    [=](benchmark::State& st) { bench_frame(st, s, kStageSamples, 1, isa); }),
                kIsaMinTime);
}

}  // namespace

int main(int argc, char** argv) {
  // Take out our own flag before Google Benchmark sees the rest.
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--mosaic_smoke") == 0)
      g_smoke = true;
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  benchmark::AddCustomContext("tsc_ghz", std::to_string(calibrate_tsc() * 1e-9));
  benchmark::AddCustomContext("mosaic_isa", mosaic::to_string(mosaic::available_isas().back()));
  benchmark::AddCustomContext("mosaic_size",
                              std::to_string(kWidth) + "x" + std::to_string(kHeight));
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
