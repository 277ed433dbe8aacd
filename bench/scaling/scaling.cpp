// mosaic-scaling — how a frame would scale past two cores, modelled from measured costs.
//
// Takes: built-in scene names (and `corner`, a dense mesh in one corner over a light
// background, made here), any .tris files, sample counts, core counts. Gives: markdown tables on
// stdout and, with --json, every cost and result:
//   - the work of each frame: front-end chunks and their costs, tiles, the tile work and its
//     critical path (the largest tile), and the core count from which that one tile bounds the
//     tile stage (largest >= total / P);
//   - a list-scheduling model (list_schedule.hpp) of the frame on P cores, with the tiles in the
//     renderer's order (busiest first by triangle count) and in LPT order (longest measured
//     first) as the bound of a better order, beside the real 1- and 2-thread frame times.
// Costs come from FrameStats::tile_costs / chunk_costs, recorded on one thread (free of
// contention for caches and cores), each the median over several frames. The real frames are
// timed with costs off, 1 and 2 threads alternating, whole frames around Renderer::render().
// The model checks its own invariants and exits with 1 if one fails (the ctest relies on it).
//
// `mosaic-scaling --compare a.json b.json ...` reads runs made with different tile sizes
// (bench/scaling/compare-tile-sizes.sh) and prints which tile size gives the best modelled time
// on --compare-cores cores per scene, with the real 1- and 2-thread times beside it.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "list_schedule.hpp"
#include "mosaic/mosaic.hpp"

namespace {

namespace fs = std::filesystem;
using mosaic::scaling::FrameModel;
using mosaic::scaling::StageModel;
using nlohmann::json;

// Untimed frames first: worker threads start, per-frame memory and caches settle.
constexpr int kDefaultWarmup = 2;
// Frames per median: enough for a stable median of costs on a shared machine, few enough that
// all scenes at two sample counts run in about a minute.
constexpr int kDefaultFrames = 7;
// The core counts the issue asks about (1 and 2 are the ones this machine can check).
const std::vector<int> kDefaultCores{1, 2, 4, 8, 16, 64};
// Relative tolerance of the invariant checks: the model only adds the costs, in other orders.
constexpr double kSumTolerance = 1e-9;
// CPU / wall of the 2-thread frames above which both cores count as free for them (a frame
// also has serial parts, so a free machine gives less than 2).
constexpr double kTwoCoresFree = 1.5;
// ---- the `corner` case: a dense mesh in one corner ----

// The dense patch: a square of this many pixels at the top-left corner (one 64 px tile).
constexpr int kCornerPatchPx = 64;
// Layers of the patch, drawn back to front so that every layer passes the depth test and writes:
// the corner holds most of the frame's work.
constexpr int kCornerLayers = 8;
// Quads per pixel edge in the patch: 1 px quads, two 0.5 px² triangles each (a far, detailed
// object: many triangles per pixel, each cheap alone).
constexpr int kCornerQuadsPerPx = 1;
// The background: a grid of quads of this edge over the whole screen, so that every tile has a
// little work.
constexpr int kBackgroundCellPx = 40;
// Depth of the background (behind the patch) and the depth range the patch layers span.
constexpr float kBackgroundDepth = 0.9f, kPatchFarDepth = 0.8f, kPatchNearDepth = 0.1f;

void add_quad(mosaic::Mesh& m, float x0, float y0, float x1, float y1, float z, mosaic::Rgba8 c) {
  const glm::vec4 a(x0, y0, z, 1), b(x1, y0, z, 1), d(x0, y1, z, 1), e(x1, y1, z, 1);
  m.positions.insert(m.positions.end(), {a, b, e, a, e, d});
  m.colors.insert(m.colors.end(), {c, c});
}

mosaic::Mesh screen_mesh() {
  mosaic::Mesh m;
  m.space = mosaic::Space::kScreen;
  m.color_source = mosaic::ColorSource::kPerTriangle;
  return m;
}

// A screen-space scene of width × height: the light background grid, then the dense patch.
mosaic::Scene corner_scene(int width, int height) {
  mosaic::Scene s;
  s.name = "corner";
  s.width = width;
  s.height = height;
  mosaic::Mesh background = screen_mesh();
  for (int y = 0; y < height; y += kBackgroundCellPx) {
    for (int x = 0; x < width; x += kBackgroundCellPx) {
      const auto shade = static_cast<std::uint8_t>(((x + y) / kBackgroundCellPx) % 2 ? 90 : 150);
      add_quad(background, static_cast<float>(x), static_cast<float>(y),
               static_cast<float>(std::min(width, x + kBackgroundCellPx)),
               static_cast<float>(std::min(height, y + kBackgroundCellPx)), kBackgroundDepth,
               {shade, shade, shade, 255});
    }
  }
  s.meshes.push_back(std::move(background));
  const int patch = std::min({kCornerPatchPx, width, height});
  const int quads = patch * kCornerQuadsPerPx;
  const float step = static_cast<float>(patch) / static_cast<float>(quads);
  for (int layer = 0; layer < kCornerLayers; ++layer) {
    mosaic::Mesh m = screen_mesh();
    const float t = static_cast<float>(layer) / static_cast<float>(kCornerLayers - 1);
    const float z = kPatchFarDepth + (kPatchNearDepth - kPatchFarDepth) * t;
    for (int j = 0; j < quads; ++j) {
      for (int i = 0; i < quads; ++i) {
        const auto r = static_cast<std::uint8_t>(255 * i / std::max(1, quads - 1));
        const auto g = static_cast<std::uint8_t>(255 * j / std::max(1, quads - 1));
        const auto b = static_cast<std::uint8_t>(255 * layer / (kCornerLayers - 1));
        add_quad(m, static_cast<float>(i) * step, static_cast<float>(j) * step,
                 static_cast<float>(i + 1) * step, static_cast<float>(j + 1) * step, z,
                 {r, g, b, 255});
      }
    }
    s.meshes.push_back(std::move(m));
  }
  return s;
}

// ---- measuring ----

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Measured {
  std::string scene;
  int samples = 1;
  std::uint64_t triangles = 0, triangles_binned = 0;
  int tile_size = 0;                         // FrameStats::tile_size the frames used
  std::vector<mosaic::TileCost> tiles;       // ms: median over the cost frames
  std::vector<mosaic::ChunkCost> chunks;     // ms_setup, ms_binning: medians
  std::vector<double> frames_1t, frames_2t;  // wall ms, costs off
  // CPU ms of the same frames: the calling thread alone at 1 thread (a one-slot arena runs
  // everything on it), the whole process at 2. On a machine shared with other work, wall time
  // above CPU time is time the frame waited for a core.
  std::vector<double> cpu_1t, cpu_2t;
};

// Milliseconds of CPU time on `clock` (CLOCK_THREAD_CPUTIME_ID or CLOCK_PROCESS_CPUTIME_ID).
double cpu_ms(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

struct Settings {
  int frames = kDefaultFrames, warmup = kDefaultWarmup;
  mosaic::Isa isa = mosaic::Isa::kAuto;
  int tile_size = 0;  // RendererOptions::tile_size: 0 lets the renderer choose
};

mosaic::RenderTarget make_target(const mosaic::Scene& s, int samples) {
  mosaic::RenderTarget t(s.width, s.height, samples);
  t.set_clear(s.clear_color, s.clear_depth);
  return t;
}

Measured measure(const mosaic::Scene& scene, int samples, const Settings& set) {
  using Clock = std::chrono::steady_clock;
  Measured m;
  m.scene = scene.name;
  m.samples = samples;
  m.triangles = scene.triangle_count();
  const std::vector<mosaic::Draw> draws = scene.draws();
  const mosaic::Frame frame{.draws = draws};
  mosaic::RenderTarget target = make_target(scene, samples);

  // Costs: one thread, costs on; the median of each tile and chunk over the frames.
  {
    mosaic::Renderer r(
        {.threads = 1, .isa = set.isa, .record_costs = true, .tile_size = set.tile_size});
    for (int i = 0; i < set.warmup; ++i) r.render(frame, target);
    std::vector<std::vector<double>> tile_ms, setup_ms, binning_ms;
    for (int f = 0; f < set.frames; ++f) {
      const mosaic::FrameStats st = r.render(frame, target);
      if (f == 0) {
        m.tiles = st.tile_costs;
        m.chunks = st.chunk_costs;
        m.triangles_binned = st.triangles_binned;
        m.tile_size = st.tile_size;
        tile_ms.resize(m.tiles.size());
        setup_ms.resize(m.chunks.size());
        binning_ms.resize(m.chunks.size());
      }
      if (st.tile_costs.size() != m.tiles.size() || st.chunk_costs.size() != m.chunks.size())
        throw mosaic::Error(mosaic::Errc::kInvalidArgument,
                            "the renderer returned a different number of costs between frames");
      for (std::size_t t = 0; t < m.tiles.size(); ++t) tile_ms[t].push_back(st.tile_costs[t].ms);
      for (std::size_t c = 0; c < m.chunks.size(); ++c) {
        setup_ms[c].push_back(st.chunk_costs[c].ms_setup);
        binning_ms[c].push_back(st.chunk_costs[c].ms_binning);
      }
    }
    for (std::size_t t = 0; t < m.tiles.size(); ++t) m.tiles[t].ms = median(tile_ms[t]);
    for (std::size_t c = 0; c < m.chunks.size(); ++c) {
      m.chunks[c].ms_setup = median(setup_ms[c]);
      m.chunks[c].ms_binning = median(binning_ms[c]);
    }
  }

  // Real frames: costs off, 1 and 2 threads alternating A B A B, each frame clear to resolve.
  mosaic::Renderer one({.threads = 1, .isa = set.isa, .tile_size = set.tile_size});
  mosaic::Renderer two({.threads = 2, .isa = set.isa, .tile_size = set.tile_size});
  auto timed = [&](mosaic::Renderer& r, clockid_t cpu_clock, std::vector<double>* wall,
                   std::vector<double>* cpu) {
    const double c0 = cpu_ms(cpu_clock);
    const auto t0 = Clock::now();
    r.render(frame, target);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (wall != nullptr) wall->push_back(ms);
    if (cpu != nullptr) cpu->push_back(cpu_ms(cpu_clock) - c0);
  };
  for (int i = 0; i < set.warmup; ++i) {
    timed(one, CLOCK_THREAD_CPUTIME_ID, nullptr, nullptr);
    timed(two, CLOCK_PROCESS_CPUTIME_ID, nullptr, nullptr);
  }
  for (int f = 0; f < set.frames; ++f) {
    timed(one, CLOCK_THREAD_CPUTIME_ID, &m.frames_1t, &m.cpu_1t);
    timed(two, CLOCK_PROCESS_CPUTIME_ID, &m.frames_2t, &m.cpu_2t);
  }
  return m;
}

// ---- modelling ----

struct Costs {
  std::vector<double> setup, binning, tiles;
  std::vector<std::uint32_t> tile_triangles;
};

Costs costs_of(const Measured& m) {
  Costs c;
  for (const mosaic::ChunkCost& k : m.chunks) {
    c.setup.push_back(k.ms_setup);
    c.binning.push_back(k.ms_binning);
  }
  for (const mosaic::TileCost& t : m.tiles) {
    c.tiles.push_back(t.ms);
    c.tile_triangles.push_back(t.triangles);
  }
  return c;
}

struct ModelRow {
  int cores = 1;
  FrameModel renderer_order, lpt_order;
};

// Fails loudly if the model breaks an invariant: one core is the sum of the costs, more cores
// never cost more time, no stage beats max(largest job, total / P).
void check_invariants(const std::string& what, const Costs& c, const std::vector<ModelRow>& rows) {
  auto fail = [&](const std::string& why) {
    throw mosaic::Error(mosaic::Errc::kInvalidArgument,
                        "model invariant broken for " + what + ": " + why);
  };
  double sum = 0;
  for (const auto* v : {&c.setup, &c.binning, &c.tiles})
    for (double x : *v) sum += std::max(0.0, x);
  const double tolerance = kSumTolerance * std::max(1.0, sum);
  for (int order = 0; order < 2; ++order) {
    double previous = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const FrameModel& f = order == 0 ? rows[i].renderer_order : rows[i].lpt_order;
      const std::string at = std::to_string(rows[i].cores) + " cores";
      if (std::abs(f.total() - sum) > tolerance) fail("total is not the sum of the costs");
      if (rows[i].cores == 1 && std::abs(f.ms() - sum) > tolerance)
        fail("1 core is not the sum of the costs");
      if (i > 0 && rows[i].cores > rows[i - 1].cores && f.ms() > previous + tolerance)
        fail("time rises from " + std::to_string(rows[i - 1].cores) + " to " + at);
      for (const StageModel* s : {&f.setup, &f.binning, &f.tiles})
        if (s->ms < s->lower_bound() - tolerance) fail("a stage beats its lower bound at " + at);
      previous = f.ms();
    }
  }
}

std::vector<ModelRow> model(const Costs& c, const std::vector<int>& cores) {
  const std::vector<double> busiest =
      mosaic::scaling::in_order(c.tiles, mosaic::scaling::busiest_first(c.tile_triangles));
  const std::vector<double> lpt =
      mosaic::scaling::in_order(c.tiles, mosaic::scaling::longest_first(c.tiles));
  std::vector<ModelRow> rows;
  for (int p : cores)
    rows.push_back({p, mosaic::scaling::model_frame(c.setup, c.binning, busiest, p),
                    mosaic::scaling::model_frame(c.setup, c.binning, lpt, p)});
  return rows;
}

// The smallest core count from which one job bounds a stage: largest >= total / P.
int bound_from(double total, double largest) {
  if (largest <= 0) return 0;
  return std::max(1, static_cast<int>(std::ceil(total / largest - kSumTolerance)));
}

json stage_json(const StageModel& s) {
  return {{"ms", s.ms},
          {"total_ms", s.total},
          {"largest_ms", s.largest},
          {"lower_bound_ms", s.lower_bound()},
          {"bound_by_largest", s.bound_by_largest()}};
}

json frame_json(const FrameModel& f) {
  return {{"ms", f.ms()},
          {"lower_bound_ms", f.lower_bound()},
          {"setup", stage_json(f.setup)},
          {"binning", stage_json(f.binning)},
          {"tiles", stage_json(f.tiles)}};
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// "12.3 (×4.1)": modelled ms and speed-up over the modelled 1-core frame.
std::string cell(double ms, double one_core) {
  return fmt("%.2f", ms) + " (×" + fmt("%.1f", ms > 0 ? one_core / ms : 0) + ")";
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

mosaic::Scene scene_by_name(const std::string& name, int width, int height) {
  if (name == "corner") return corner_scene(width, height);
  return mosaic::builtin_scene(name, width, height);
}

// ---- --compare: runs made with different tile sizes ----

int compare(const std::vector<std::string>& files, int cores) {
  struct Entry {
    int tile_size = 0;
    std::size_t tiles = 0;
    double model_ms = 0, lpt_ms = 0, model_1 = 0;  // modelled: P = cores, LPT, 1 core
    double cpu_1t = 0, wall_1t = 0, wall_2t = 0;   // real frames
  };
  // (scene, samples) in the order first seen → one entry per run that has it.
  std::vector<std::pair<std::string, int>> keys;
  std::map<std::pair<std::string, int>, std::vector<Entry>> entries;
  double load_min = 1e300, load_max = -1e300;  // load averages the runs started with
  for (const std::string& f : files) {
    std::ifstream in(f);
    if (!in) throw mosaic::Error(mosaic::Errc::kIo, "cannot read " + f);
    try {
      const json j = json::parse(in);
      const double load = j.value("load_average", -1.0);
      load_min = std::min(load_min, load);
      load_max = std::max(load_max, load);
      for (const json& c : j.at("cases")) {
        const auto key =
            std::make_pair(c.at("scene").get<std::string>(), c.at("samples").get<int>());
        Entry e;
        e.tile_size = c.at("tile_size").get<int>();
        e.tiles = c.at("tiles").size();
        e.cpu_1t = c.at("measured_1t_cpu_ms").get<double>();
        e.wall_1t = c.at("measured_1t_ms").get<double>();
        e.wall_2t = c.at("measured_2t_ms").get<double>();
        bool found = false;
        for (const json& r : c.at("model")) {
          if (r.at("cores").get<int>() == 1)
            e.model_1 = r.at("renderer_order").at("ms").get<double>();
          if (r.at("cores").get<int>() != cores) continue;
          e.model_ms = r.at("renderer_order").at("ms").get<double>();
          e.lpt_ms = r.at("lpt_order").at("ms").get<double>();
          found = true;
        }
        if (!found)
          throw mosaic::Error(mosaic::Errc::kInvalidArgument,
                              f + " has no model for " + std::to_string(cores) + " cores");
        if (!entries.count(key)) keys.push_back(key);
        entries[key].push_back(e);
      }
    } catch (const json::exception& e) {
      throw mosaic::Error(mosaic::Errc::kParse, f + ": " + e.what());
    }
  }
  const std::string p = std::to_string(cores);
  std::string table = "| scene | samples | tile size | tiles | model P=" + p + " ms | LPT P=" + p +
                      " ms | model P=1 ms | real 1T CPU ms | real 1T ms | real 2T ms | |\n"
                      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  std::string summary = "| scene | samples | best tile size | model P=" + p +
                        " ms | (renderer's size: ms) | real 1T CPU ms | real 1T ms | real 2T ms |\n"
                        "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& key : keys) {
    std::vector<Entry>& es = entries[key];
    std::stable_sort(es.begin(), es.end(),
                     [](const Entry& a, const Entry& b) { return a.tile_size < b.tile_size; });
    const auto best = std::min_element(es.begin(), es.end(), [](const Entry& a, const Entry& b) {
      return a.model_ms < b.model_ms;
    });
    // The size the renderer picks by itself for this sample count.
    const int default_size = mosaic::default_tile_size(key.second);
    std::string at_default = "-";
    char row[512];
    for (const Entry& e : es) {
      std::snprintf(row, sizeof row,
                    "| %s | %d | %d | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %s |\n",
                    key.first.c_str(), key.second, e.tile_size, e.tiles, e.model_ms, e.lpt_ms,
                    e.model_1, e.cpu_1t, e.wall_1t, e.wall_2t, &e == &*best ? "**best**" : "");
      table += row;
      if (e.tile_size == default_size) at_default = fmt("%.2f", e.model_ms);
    }
    std::snprintf(row, sizeof row, "| %s | %d | %d | %.2f | %s | %.2f | %.2f | %.2f |\n",
                  key.first.c_str(), key.second, best->tile_size, best->model_ms,
                  at_default.c_str(), best->cpu_1t, best->wall_1t, best->wall_2t);
    summary += row;
  }
  std::printf("%zu runs; load average at their start %.2f to %.2f.\n\n", files.size(), load_min,
              load_max);
  std::printf(
      "Modelled %d-core frame (tiles in the renderer's order) per tile size, with the real "
      "1- and 2-thread frames of the same build:\n\n%s",
      cores, table.c_str());
  std::printf("\nBest tile size for the modelled %d-core frame per scene:\n\n%s", cores,
              summary.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Model how mosaic's frames scale past two cores from measured per-tile and per-chunk costs"};
  std::vector<std::string> files, compare_files;
  std::string scene_list = "all", size = "1920x1080", json_path, isa_name = "auto";
  std::vector<int> samples_list{1, 4}, cores = kDefaultCores;
  Settings set;
  int compare_cores = 16;
  app.add_option("files", files, ".tris files to add to the scenes")->check(CLI::ExistingFile);
  app.add_option("--scenes", scene_list,
                 "scenes, comma-separated: built-in names or corner; 'all' (built-ins and corner) "
                 "or 'none'");
  app.add_option("--size", size, "size of the built-in scenes and corner, WxH (default 1920x1080)");
  app.add_option("--samples", samples_list, "sample counts (default 1 4)")
      ->check(CLI::IsMember({1, 4, 8, 16}))
      ->delimiter(',');
  app.add_option("--cores", cores, "core counts to model (default 1 2 4 8 16 64)")
      ->check(CLI::Range(1, 4096))
      ->delimiter(',');
  app.add_option("--frames", set.frames, "frames per median, costs and real frames (default 7)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--warmup", set.warmup, "untimed frames first (default 2)")
      ->check(CLI::Range(0, 100000));
  app.add_option("--isa", isa_name, "instruction set (default auto)");
  app.add_option("--tile-size", set.tile_size,
                 "tile edge in pixels, a power of two from 8 to 128 (default 0: the renderer's "
                 "choice per sample count)")
      ->check(CLI::IsMember({0, 8, 16, 32, 64, 128}));
  app.add_option("--json", json_path, "write every cost, measurement and modelled time as JSON");
  app.add_option("--compare", compare_files,
                 "instead of measuring: compare JSON files of runs with different tile sizes")
      ->check(CLI::ExistingFile);
  app.add_option("--compare-cores", compare_cores, "core count --compare ranks by (default 16)")
      ->check(CLI::Range(1, 4096));
  CLI11_PARSE(app, argc, argv);

  try {
    if (!compare_files.empty()) return compare(compare_files, compare_cores);

    int width = 0, height = 0;
    if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2)
      throw mosaic::Error(mosaic::Errc::kInvalidArgument, "--size must be WxH, e.g. 1920x1080");
    bool isa_known = isa_name == "auto";
    for (mosaic::Isa i : mosaic::available_isas()) {
      if (isa_name == mosaic::to_string(i) && i != mosaic::Isa::kReference) {
        set.isa = i;
        isa_known = true;
      }
    }
    if (!isa_known)
      throw mosaic::Error(mosaic::Errc::kUnsupportedIsa,
                          "--isa " + isa_name + " is not an available fast path");
    std::sort(cores.begin(), cores.end());
    cores.erase(std::unique(cores.begin(), cores.end()), cores.end());
    // 1 core: the base of every speed-up; 2: the count this machine can check the model at.
    for (int must : {2, 1})
      if (std::find(cores.begin(), cores.end(), must) == cores.end()) cores.push_back(must);
    std::sort(cores.begin(), cores.end());

    std::vector<mosaic::Scene> scenes;
    std::vector<std::string> names;
    if (scene_list == "all") {
      names = mosaic::builtin_scene_names();
      names.push_back("corner");
    } else if (scene_list != "none") {
      names = split(scene_list);
    }
    for (const std::string& n : names) scenes.push_back(scene_by_name(n, width, height));
    for (const std::string& f : files) scenes.push_back(mosaic::load_tris(f));
    if (scenes.empty()) throw mosaic::Error(mosaic::Errc::kInvalidArgument, "no scenes to run");

    const mosaic::Renderer probe({.threads = 1, .isa = set.isa});
    // The machine's load when the run starts: times from a starved run read differently.
    double load = 0;
    if (getloadavg(&load, 1) != 1) load = -1;
    json out;
    out["isa"] = mosaic::to_string(probe.isa());
    out["frames"] = set.frames;
    out["warmup"] = set.warmup;
    out["load_average"] = load;
    out["cores"] = cores;
    out["cases"] = json::array();
    std::string work =
        "| scene | samples | triangles | chunks | setup ms (largest chunk) | binning ms (largest "
        "chunk) | tiles | tile work ms | largest tile ms | at (x0,y0) px | triangles in it | "
        "largest / tile work | one tile bounds the tiles from |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|\n";
    std::string head = "| scene | samples";
    std::string rule = "|---|---:";
    for (int p : cores) {
      head += " | P=" + std::to_string(p);
      rule += "|---:";
    }
    head += " |\n";
    rule += "|\n";
    std::string renderer_table = head + rule, lpt_table = head + rule;
    std::string limits;
    std::vector<double> cores_used_2t;  // CPU / wall of each case's 2-thread frames
    std::string validation =
        "| scene | samples | model P=1 ms | real 1T CPU ms | real 1T ms | model P=2 ms | real 2T "
        "ms "
        "| real 2T CPU / wall | model ×2 | real ×2 |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";

    for (const mosaic::Scene& scene : scenes) {
      for (const int samples : samples_list) {
        const Measured m = measure(scene, samples, set);
        const Costs c = costs_of(m);
        const std::vector<ModelRow> rows = model(c, cores);
        const std::string what = scene.name + " " + std::to_string(samples) + "x";
        check_invariants(what, c, rows);

        const FrameModel& one = rows.front().renderer_order;
        const StageModel& tiles = one.tiles;
        // The largest tile in tile order (largest_job counts in the order the model started them).
        const auto hot_at = std::max_element(c.tiles.begin(), c.tiles.end());
        const mosaic::TileCost hot =
            m.tiles.empty() ? mosaic::TileCost{}
                            : m.tiles[static_cast<std::size_t>(hot_at - c.tiles.begin())];
        const int tile_bound = bound_from(tiles.total, tiles.largest);
        const int setup_bound = bound_from(one.setup.total, one.setup.largest);
        const double m1 = median(m.frames_1t), m2 = median(m.frames_2t);

        char row[512];
        std::snprintf(row, sizeof row,
                      "| %s | %d | %llu | %zu | %.2f (%.2f) | %.2f (%.2f) | %zu | %.2f | %.3f | "
                      "(%d,%d) | %u | %.1f%% | %s |\n",
                      scene.name.c_str(), samples, static_cast<unsigned long long>(m.triangles),
                      m.chunks.size(), one.setup.total, one.setup.largest, one.binning.total,
                      one.binning.largest, m.tiles.size(), tiles.total, tiles.largest, hot.x0,
                      hot.y0, hot.triangles,
                      tiles.total > 0 ? 100.0 * tiles.largest / tiles.total : 0.0,
                      tile_bound > 0 ? (std::to_string(tile_bound) + " cores").c_str() : "-");
        work += row;

        auto table_row = [&](bool lpt) {
          std::string r = "| " + scene.name + " | " + std::to_string(samples);
          const double base = (lpt ? rows.front().lpt_order : rows.front().renderer_order).ms();
          for (const ModelRow& mr : rows) {
            const FrameModel& f = lpt ? mr.lpt_order : mr.renderer_order;
            std::string x = cell(f.ms(), base);
            if (f.tiles.bound_by_largest() && mr.cores > 1) x = "**" + x + "**";
            r += " | " + x;
          }
          return r + " |\n";
        };
        renderer_table += table_row(false);
        lpt_table += table_row(true);

        // The model against the real frames at 1 and 2 threads.
        const double c1 = median(m.cpu_1t), c2 = median(m.cpu_2t);
        const double model2 = rows[1].renderer_order.ms();  // cores holds 1 and 2 first
        std::snprintf(row, sizeof row,
                      "| %s | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n",
                      scene.name.c_str(), samples, one.ms(), c1, m1, model2, m2,
                      m2 > 0 ? c2 / m2 : 0.0, model2 > 0 ? one.ms() / model2 : 0.0,
                      m2 > 0 ? m1 / m2 : 0.0);
        validation += row;
        cores_used_2t.push_back(m2 > 0 ? c2 / m2 : 0.0);

        // What limits it: one tile, the chunk count, or the stages that stay serial in time.
        std::string l = "- **" + what + "**: ";
        if (tile_bound > 0 && tile_bound <= cores.back())
          l += "the frame is limited by tile (" + std::to_string(hot.x0) + "," +
               std::to_string(hot.y0) + ") (" + std::to_string(hot.triangles) + " triangles, " +
               fmt("%.3f", tiles.largest) + " of " + fmt("%.2f", tiles.total) +
               " ms of tile work) from " + std::to_string(tile_bound) + " cores on; ";
        else
          l += "no single tile bounds the frame up to " + std::to_string(cores.back()) +
               " cores (the largest is " + fmt("%.1f", 100.0 * tiles.largest / tiles.total) +
               "% of the tile work); ";
        if (m.chunks.size() == 1)
          l += "the front end is one chunk (up to 2048 triangles), so it runs on one core";
        else
          l += "the front end has " + std::to_string(m.chunks.size()) +
               " chunks of up to 2048 triangles, and setup stops scaling at " +
               std::to_string(setup_bound) + " cores (its largest chunk)";
        const FrameModel& top = rows.back().renderer_order;
        l += "; at " + std::to_string(rows.back().cores) + " cores the model spends " +
             fmt("%.3f", top.setup.ms) + " ms in setup, " + fmt("%.3f", top.binning.ms) +
             " in binning and " + fmt("%.3f", top.tiles.ms) + " in tiles (×" +
             fmt("%.1f", top.ms() > 0 ? one.ms() / top.ms() : 0) + ").\n";
        limits += l;

        json jc;
        jc["scene"] = scene.name;
        jc["samples"] = samples;
        jc["tile_size"] = m.tile_size;
        jc["width"] = scene.width;
        jc["height"] = scene.height;
        jc["triangles"] = m.triangles;
        jc["triangles_binned"] = m.triangles_binned;
        jc["measured_1t_ms"] = m1;
        jc["measured_2t_ms"] = m2;
        jc["frames_1t_ms"] = m.frames_1t;
        jc["frames_2t_ms"] = m.frames_2t;
        jc["measured_1t_cpu_ms"] = c1;
        jc["measured_2t_cpu_ms"] = c2;
        jc["frames_1t_cpu_ms"] = m.cpu_1t;
        jc["frames_2t_cpu_ms"] = m.cpu_2t;
        jc["tile_bound_from_cores"] = tile_bound;
        jc["setup_bound_from_cores"] = setup_bound;
        jc["largest_tile"] = {
            {"x0", hot.x0}, {"y0", hot.y0}, {"triangles", hot.triangles}, {"ms", tiles.largest}};
        jc["chunks"] = json::array();
        for (const mosaic::ChunkCost& k : m.chunks)
          jc["chunks"].push_back(
              {{"triangles", k.triangles}, {"ms_setup", k.ms_setup}, {"ms_binning", k.ms_binning}});
        jc["tiles"] = json::array();
        for (const mosaic::TileCost& t : m.tiles)
          jc["tiles"].push_back({{"x0", t.x0},
                                 {"y0", t.y0},
                                 {"width", t.width},
                                 {"height", t.height},
                                 {"triangles", t.triangles},
                                 {"ms", t.ms}});
        jc["model"] = json::array();
        for (const ModelRow& mr : rows)
          jc["model"].push_back({{"cores", mr.cores},
                                 {"renderer_order", frame_json(mr.renderer_order)},
                                 {"lpt_order", frame_json(mr.lpt_order)}});
        out["cases"].push_back(jc);
        std::fprintf(stderr, "mosaic-scaling: %s done\n", what.c_str());
      }
    }
    out["tile_size_option"] = set.tile_size;

    std::printf(
        "mosaic-scaling: tile size %s, %s, %dx%d; load average %.2f at the start (%u hardware "
        "threads). Costs: median of %d frames on 1 thread (costs on) after %d warm-up; real "
        "frames: median of %d, 1 and 2 threads alternating, costs off.\n\n",
        set.tile_size ? (std::to_string(set.tile_size) + " px").c_str() : "chosen per sample count",
        mosaic::to_string(probe.isa()), width, height, load, std::thread::hardware_concurrency(),
        set.frames, set.warmup, set.frames);
    std::printf(
        "Work per frame (ms on 1 thread; a tile's cost is clear, rasterize, resolve):\n\n%s",
        work.c_str());
    std::printf(
        "\nThe model against the real frames (CPU ms: the thread's CPU time; wall above it is "
        "time spent waiting for a core on a shared machine; CPU / wall near 2 means both cores "
        "were free):\n\n%s",
        validation.c_str());
    if (const double used = median(cores_used_2t); used < kTwoCoresFree)
      std::printf(
          "\nThe 2-thread frames had %.2f cores on average (median CPU / wall): other work held "
          "the "
          "rest, so this run cannot check the model at P=2; run it on an idle machine.\n",
          used);
    std::printf(
        "\nModelled frame on P cores, tiles in the renderer's order (busiest first by triangle "
        "count): ms (× speed-up over the modelled 1 core); **bold** where one tile bounds the "
        "tile stage (largest tile >= tile work / P):\n\n%s",
        renderer_table.c_str());
    std::printf(
        "\nThe same with the tiles in LPT order (longest measured first), the bound of a better "
        "tile order:\n\n%s",
        lpt_table.c_str());
    std::printf("\nWhat limits scaling:\n\n%s", limits.c_str());
    if (!json_path.empty()) {
      std::ofstream f(json_path);
      f << out.dump(1) << "\n";
      if (!f) throw mosaic::Error(mosaic::Errc::kIo, "cannot write " + json_path);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mosaic-scaling: %s\n", e.what());
    return 1;
  }
  return 0;
}
