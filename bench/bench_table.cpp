// bench/bench_table.cpp — mosaic-bench-table: the README tables from a mosaic-bench JSON file.
//
// Takes: the path of a Google Benchmark JSON file written by mosaic-bench (--benchmark_out=...
// --benchmark_out_format=json), with repetitions (medians are used) or without. Gives, on
// stdout, markdown: (1) scenes × {1x, 4x} × {1, 2 threads} with median ms, Mtri/s, Gsamples/s,
// samples per TSC cycle per thread and the distance to issue 3's targets at 4x on 2 threads;
// (2) each instruction set's speed-up over the reference; (3) where a 4x frame's time goes, from
// the FrameStats counters and the isolated stage cases; (4) what each draw feature costs, with
// the depth-only pass against Masked Occlusion Culling; (5) occlusion query throughput. A
// missing case prints as "—". A file that
// cannot be read or is not such JSON gives a one-line error and exit status 1.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "mosaic/errors.hpp"
#include "mosaic/scene.hpp"

namespace {

using nlohmann::json;

/// Issue 3's targets for mosaic at 4x MSAA on 2 threads, in ms (10× and 20× llvmpipe).
struct Target {
  const char* scene;
  double ms;
};
constexpr Target kTargets[] = {{"random-small", 8.0}, {"random-large", 16.0}, {"slivers", 9.0}};

/// The order of the ISA columns: mosaic's Isa enum order; any other name follows.
const char* const kIsaOrder[] = {"reference", "sse4.1", "avx2", "avx512"};

/// One case: its median wall time and median counters.
struct Case {
  double ms = 0;
  double cpu_ms = 0;  ///< CPU time of the thread that called render(), for the CPU / wall column
  std::map<std::string, double> counters;
  std::optional<double> counter(const std::string& k) const {
    const auto it = counters.find(k);
    if (it == counters.end()) return std::nullopt;
    return it->second;
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double to_ms(double t, const std::string& unit) {
  if (unit == "ns") return t * 1e-6;
  if (unit == "us") return t * 1e-3;
  if (unit == "s") return t * 1e3;
  return t;  // "ms"
}

/// Keys of a benchmark entry that are not counters.
bool is_field(const std::string& k) {
  static const char* const kFields[] = {"name",
                                        "family_index",
                                        "per_family_instance_index",
                                        "run_name",
                                        "run_type",
                                        "repetitions",
                                        "repetition_index",
                                        "threads",
                                        "iterations",
                                        "real_time",
                                        "cpu_time",
                                        "time_unit",
                                        "aggregate_name",
                                        "aggregate_unit",
                                        "error_occurred",
                                        "error_message",
                                        "label"};
  return std::find(std::begin(kFields), std::end(kFields), k) != std::end(kFields);
}

/// A run name without what Google Benchmark appends to it: "/min_time:0.200", "/iterations:1",
/// "/manual_time" (frame/star/4x/t2/min_time:0.200/manual_time gives frame/star/4x/t2).
std::string case_name(const std::string& run_name) {
  std::string out;
  std::size_t b = 0;
  while (b <= run_name.size()) {
    std::size_t e = run_name.find('/', b);
    if (e == std::string::npos) e = run_name.size();
    const std::string seg = run_name.substr(b, e - b);
    if (seg.find(':') == std::string::npos && seg != "manual_time" && seg != "real_time")
      out += (out.empty() ? "" : "/") + seg;
    b = e + 1;
  }
  return out;
}

/// The file's cases by case_name(), in the file's order, plus its context.
struct Results {
  std::vector<std::string> order;
  std::map<std::string, Case> cases;
  json context;
  int repetitions = 1;
};

Results load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw mosaic::Error(mosaic::Errc::kIo, "cannot read " + path);
  // Google Benchmark writes a bare NaN (not JSON) for the cv of a counter whose mean is 0, e.g.
  // the reference's ms_binning; such values become null, which this program never reads.
  std::stringstream text;
  text << in.rdbuf();
  static const std::regex kNonFinite(R"((:\s*)-?(NaN|nan|inf|Infinity)(\s*[,}\n]))");
  json doc;
  try {
    doc = json::parse(std::regex_replace(text.str(), kNonFinite, "$1null$3"));
  } catch (const json::exception& e) {
    throw mosaic::Error(mosaic::Errc::kParse, path + ": not JSON (" + e.what() + ")");
  }
  if (!doc.is_object() || !doc.contains("benchmarks") || !doc["benchmarks"].is_array())
    throw mosaic::Error(mosaic::Errc::kParse, path + ": no \"benchmarks\" array");

  Results r;
  if (doc.contains("context")) r.context = doc["context"];
  std::map<std::string, Case> medians;
  std::map<std::string, std::vector<Case>> runs;  // single runs, when there is no median
  try {
    for (const json& b : doc["benchmarks"]) {
      if (b.value("error_occurred", false)) continue;
      const std::string name = case_name(b.value("run_name", b.value("name", std::string())));
      const std::string type = b.value("run_type", std::string("iteration"));
      if (type == "aggregate" && b.value("aggregate_name", std::string()) != "median") continue;
      Case c;
      c.ms = to_ms(b.at("real_time").get<double>(), b.value("time_unit", std::string("ns")));
      c.cpu_ms = to_ms(b.value("cpu_time", 0.0), b.value("time_unit", std::string("ns")));
      for (const auto& [k, v] : b.items())
        if (!is_field(k) && v.is_number()) c.counters[k] = v.get<double>();
      r.repetitions = std::max(r.repetitions, b.value("repetitions", 1));
      if (std::find(r.order.begin(), r.order.end(), name) == r.order.end()) r.order.push_back(name);
      if (type == "aggregate")
        medians[name] = c;
      else
        runs[name].push_back(c);
    }
  } catch (const json::exception& e) {
    throw mosaic::Error(mosaic::Errc::kParse,
                        path + ": unexpected benchmark entry (" + e.what() + ")");
  }
  for (const std::string& name : r.order) {
    if (medians.count(name)) {
      r.cases[name] = medians[name];
      continue;
    }
    const std::vector<Case>& v = runs[name];
    Case c;
    std::vector<double> ms;
    for (const Case& x : v) ms.push_back(x.ms);
    c.ms = median(ms);
    std::vector<double> cpu;
    for (const Case& x : v) cpu.push_back(x.cpu_ms);
    c.cpu_ms = median(cpu);
    for (const auto& [k, unused] : v.front().counters) {
      std::vector<double> xs;
      for (const Case& x : v)
        if (x.counters.count(k)) xs.push_back(x.counters.at(k));
      c.counters[k] = median(xs);
    }
    r.cases[name] = c;
  }
  return r;
}

std::string fmt(double v, const char* f) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}
std::string fmt(std::optional<double> v, const char* f) { return v ? fmt(*v, f) : "—"; }

/// Path segment i of a case name ("frame/star/4x/t2" → 1 gives "star").
std::string segment(const std::string& name, int i) {
  std::size_t b = 0;
  for (int k = 0; k < i; ++k) {
    b = name.find('/', b);
    if (b == std::string::npos) return {};
    ++b;
  }
  return name.substr(b, name.find('/', b) - b);
}

/// Scenes named under `prefix`: the built-in ones in mosaic::builtin_scene_names() order (the
/// file's order is random when repetitions are interleaved), then any other in the file's order.
std::vector<std::string> scenes_of(const Results& r, const std::string& prefix) {
  std::vector<std::string> out;
  for (const std::string& n : r.order) {
    if (segment(n, 0) != prefix) continue;
    const std::string s = segment(n, 1);
    if (std::find(out.begin(), out.end(), s) == out.end()) out.push_back(s);
  }
  const std::vector<std::string> known = mosaic::builtin_scene_names();
  std::stable_sort(out.begin(), out.end(), [&](const std::string& a, const std::string& b) {
    return std::find(known.begin(), known.end(), a) < std::find(known.begin(), known.end(), b);
  });
  return out;
}

const Case* find(const Results& r, const std::string& name) {
  const auto it = r.cases.find(name);
  return it == r.cases.end() ? nullptr : &it->second;
}

void frames_table(const Results& r) {
  std::cout
      << "| scene | MSAA | threads | ms (median) | Mtri/s | Gsamples/s | "
         "samples / TSC cycle / thread | target (4x, 2 threads) | ms / target | CPU / wall |\n"
         "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& s : scenes_of(r, "frame")) {
    for (const char* S : {"1x", "4x"}) {
      for (const char* T : {"t1", "t2"}) {
        const Case* c = find(r, "frame/" + s + "/" + S + "/" + T);
        if (!c) continue;
        const auto tris = c->counter("tris"), samples = c->counter("samples");
        std::optional<double> mtri, gsamples;
        if (tris && c->ms > 0) mtri = *tris / (c->ms * 1e3);
        if (samples && c->ms > 0) gsamples = *samples / (c->ms * 1e6);
        std::string target = "—", distance = "—";
        for (const Target& t : kTargets) {
          if (s == t.scene && std::string(S) == "4x" && std::string(T) == "t2") {
            target = "≤ " + fmt(t.ms, "%.0f") + " ms";
            const double ratio = c->ms / t.ms;
            distance = fmt(ratio, "%.2f×") + (ratio <= 1 ? " (met)" : " (over)");
          }
        }
        std::cout << "| " << s << " | " << S << " | " << std::string(T).substr(1) << " | "
                  << fmt(c->ms, "%.2f") << " | " << fmt(mtri, "%.3g") << " | "
                  << fmt(gsamples, "%.3g") << " | "
                  << fmt(c->counter("samples/tsc_cycle/thread"), "%.3f") << " | " << target << " | "
                  << distance << " | " << fmt(c->cpu_ms / c->ms * 100, "%.0f %%") << " |\n";
      }
    }
  }
}

/// The mesh scenes lit per pixel (lit/) against the same meshes flat (frame/).
void lit_table(const Results& r) {
  std::cout
      << "| mesh scene | MSAA | threads | flat ms | lit ms | lit / flat | flat setup | "
         "lit setup | flat raster | lit raster |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& s : scenes_of(r, "lit")) {
    for (const char* S : {"1x", "4x"}) {
      for (const char* T : {"t1", "t2"}) {
        const std::string key = s + "/" + S + "/" + T;
        const Case* lit = find(r, "lit/" + key);
        const Case* flat = find(r, "frame/" + key);
        if (!lit || !flat) continue;
        std::optional<double> ratio;
        if (flat->ms > 0) ratio = lit->ms / flat->ms;
        std::cout << "| " << s << " | " << S << " | " << std::string(T).substr(1) << " | "
                  << fmt(flat->ms, "%.2f") << " | " << fmt(lit->ms, "%.2f") << " | "
                  << fmt(ratio, "%.2f×") << " | " << fmt(flat->counter("ms_setup"), "%.2f") << " | "
                  << fmt(lit->counter("ms_setup"), "%.2f") << " | "
                  << fmt(flat->counter("ms_raster"), "%.2f") << " | "
                  << fmt(lit->counter("ms_raster"), "%.2f") << " |\n";
      }
    }
  }
}

void isa_table(const Results& r) {
  std::vector<std::string> isas;
  for (const std::string& n : r.order)
    if (segment(n, 0) == "isa") {
      const std::string i = segment(n, 3);
      if (std::find(isas.begin(), isas.end(), i) == isas.end()) isas.push_back(i);
    }
  std::stable_sort(isas.begin(), isas.end(), [](const std::string& a, const std::string& b) {
    auto rank = [](const std::string& x) {
      return std::find(std::begin(kIsaOrder), std::end(kIsaOrder), x) - std::begin(kIsaOrder);
    };
    return rank(a) < rank(b);
  });
  std::cout << "| scene (4x, 1 thread) |";
  for (const std::string& i : isas)
    std::cout << " " << i << (i == "reference" ? " ms |" : " ms (speed-up) |");
  std::cout << "\n|---|";
  for (std::size_t k = 0; k < isas.size(); ++k) std::cout << "---|";
  std::cout << "\n";
  for (const std::string& s : scenes_of(r, "isa")) {
    const Case* ref = find(r, "isa/" + s + "/4x/reference");
    std::cout << "| " << s << " |";
    for (const std::string& i : isas) {
      const Case* c = find(r, "isa/" + s + "/4x/" + i);
      if (!c) {
        std::cout << " — |";
        continue;
      }
      std::cout << " " << fmt(c->ms, "%.2f");
      if (ref && c != ref && c->ms > 0) std::cout << " (" << fmt(ref->ms / c->ms, "%.1f×") << ")";
      std::cout << " |";
    }
    std::cout << "\n";
  }
}

void stages_table(const Results& r) {
  std::cout << "| scene (4x) | threads | frame ms | setup | binning | raster + resolve | "
               "resolve (sum over threads) | isolated setup | isolated binning | "
               "isolated raster + resolve |\n"
               "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& s : scenes_of(r, "frame")) {
    for (const char* T : {"t1", "t2"}) {
      const Case* f = find(r, "frame/" + s + "/4x/" + T);
      if (!f) continue;
      auto ms = [&](const std::string& name) -> std::optional<double> {
        const Case* c = find(r, name);
        if (!c) return std::nullopt;
        return c->ms;
      };
      std::cout << "| " << s << " | " << std::string(T).substr(1) << " | " << fmt(f->ms, "%.3f")
                << " | " << fmt(f->counter("ms_setup"), "%.3f") << " | "
                << fmt(f->counter("ms_binning"), "%.3f") << " | "
                << fmt(f->counter("ms_raster"), "%.3f") << " | "
                << fmt(f->counter("ms_resolve"), "%.3f") << " | "
                << fmt(ms("stage/setup/" + s + "/" + T), "%.3f") << " | "
                << fmt(ms("stage/binning/" + s + "/" + T), "%.3f") << " | "
                << fmt(ms("stage/raster/" + s + "/4x/" + T), "%.3f") << " |\n";
    }
  }
  std::cout << "\nTiles with empty bins (every tile through the kernel, which writes the clear "
               "values without clearing and resolving samples): ";
  std::string sep;
  for (const char* S : {"1x", "4x"})
    for (const char* T : {"t1", "t2"}) {
      const Case* c = find(r, std::string("stage/resolve/") + S + "/" + T);
      if (!c) continue;
      std::cout << sep << S << " " << std::string(T).substr(1) << " thread"
                << (std::string(T) == "t1" ? "" : "s") << ": " << fmt(c->ms, "%.3f") << " ms";
      sep = "; ";
    }
  std::cout << ".\n";
}

/// Intel's Masked Occlusion Culling on this machine (issue 7): 100k triangles of 10–50 px²,
/// depth-only, 1920×1080, one thread, AVX-512, conservative coverage: 3.3 to 4.4 ms.
constexpr double kMocMsLow = 3.3, kMocMsHigh = 4.4;
/// Issue 7's aim for mosaic's exact depth-only 1x pass on the same scene: within 1.5× of MOC.
constexpr double kMocAimRatio = 1.5;

void features_table(const Results& r) {
  // (case name under features/, what it changes from color+depth)
  const std::pair<const char*, const char*> kVariants[] = {
      {"color+depth", "color+depth: flat colour, `less` test with writes (the baseline)"},
      {"depth-only", "depth-only: colour write off (occluder pass)"},
      {"depth-only+hiz", "depth-only, keeping the hierarchical z for queries"},
      {"depth-off", "depth test off: no depth kept"},
      {"interpolated", "per-vertex colour, interpolated"},
      {"shader/builtin", "constant colour through the shader cases' own draw"},
      {"shader/shader", "flat_color_shader: a fragment shader, no varyings"},
      {"shader/shader+blend", "flat_color_shader with source-over blending"},
      {"varyings/0", "a shader reading 0 varyings"},
      {"varyings/4", "a shader reading 4 varyings"},
      {"varyings/8", "a shader reading 8 varyings"}};
  std::cout << "| variant (random-small, 1 thread) | samples | frame ms | vs color+depth | setup | "
               "binning | raster + resolve |\n|---|---|---|---|---|---|---|\n";
  for (const char* S : {"1x", "4x"}) {
    const Case* base = find(r, std::string("features/color+depth/") + S);
    for (const auto& [v, label] : kVariants) {
      const Case* c = find(r, std::string("features/") + v + "/" + S);
      if (!c) continue;
      std::optional<double> ratio;
      if (base && base->ms > 0) ratio = c->ms / base->ms;
      std::cout << "| " << label << " | " << S << " | " << fmt(c->ms, "%.2f") << " | "
                << fmt(ratio, "%.2f×") << " | " << fmt(c->counter("ms_setup"), "%.2f") << " | "
                << fmt(c->counter("ms_binning"), "%.2f") << " | "
                << fmt(c->counter("ms_raster"), "%.2f") << " |\n";
    }
  }
  std::cout << "\nThe depth-only 1x pass on every instruction set against Masked Occlusion "
               "Culling (MOC: "
            << fmt(kMocMsLow, "%.1f") << "–" << fmt(kMocMsHigh, "%.1f")
            << " ms on the same scene, AVX-512, one thread; aim: within "
            << fmt(kMocAimRatio, "%.1f×") << "):\n\n"
            << "| instruction set | frame ms | raster ms | frame / MOC |\n|---|---|---|---|\n";
  for (const char* isa : kIsaOrder) {
    const Case* c = find(r, std::string("features/depth-only/1x/") + isa);
    if (!c) continue;
    std::cout << "| " << isa << " | " << fmt(c->ms, "%.2f") << " | "
              << fmt(c->counter("ms_raster"), "%.2f") << " | " << fmt(c->ms / kMocMsHigh, "%.1f")
              << "–" << fmt(c->ms / kMocMsLow, "%.1f×") << " |\n";
  }
}

void occlusion_table(const Results& r) {
  std::cout << "| query | hierarchical z of | ms per batch | rate | reported hidden |\n"
               "|---|---|---|---|---|\n";
  for (const std::string kind : {"rects", "boxes", "triangles"}) {
    for (const char* where : {"random-small", "wall"}) {
      const Case* c = find(r, "occlusion/" + kind + "/" + where);
      if (!c) continue;
      std::string what, rate;
      if (kind == "rects") {
        what = "100k rectangles, 8–64 px (`rect_visible`)";
        rate = fmt(c->counter("Mrects/s"), "%.1f") + " M rectangles/s";
      } else if (kind == "boxes") {
        what = "100k world boxes in one `boxes_visible` call";
        rate = fmt(c->counter("Mboxes/s"), "%.1f") + " M boxes/s";
      } else {
        what = "10k boxes of 12 triangles (`draw_visible`)";
        rate = fmt(c->counter("Kqueries/s"), "%.0f") + " k boxes/s (" +
               fmt(c->counter("Mtri/s"), "%.1f") + " M triangles/s)";
      }
      std::cout << "| " << what << " | " << where << " | " << fmt(c->ms, "%.2f") << " | " << rate
                << " | " << fmt(c->counter("hidden").value_or(0) * 100, "%.0f %%") << " |\n";
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: mosaic-bench-table RESULTS.json\n";
    return 2;
  }
  try {
    const Results r = load(argv[1]);
    const std::string tsc = r.context.is_object() ? r.context.value("tsc_ghz", "?") : "?";
    const std::string isa = r.context.is_object() ? r.context.value("mosaic_isa", "?") : "?";
    // The load average when the run started: on a shared machine it says how far to trust it.
    std::string load = "?";
    if (r.context.is_object() && r.context.contains("load_avg") &&
        r.context["load_avg"].is_array() && !r.context["load_avg"].empty() &&
        r.context["load_avg"][0].is_number())
      load = fmt(r.context["load_avg"][0].get<double>(), "%.2f");
    const int cpus = r.context.is_object() ? r.context.value("num_cpus", 0) : 0;
    std::cout << "Medians of " << r.repetitions << " repetition" << (r.repetitions == 1 ? "" : "s")
              << "; 1920×1080, flat colour, depth test `less`; fast path " << isa << "; TSC "
              << fmt(std::stod(tsc == "?" ? "0" : tsc), "%.2f")
              << " GHz (TSC cycles tick at the nominal clock, not the turbo clock). "
                 "Load average at the start: "
              << load << " on " << cpus
              << " CPUs. "
                 "Gsamples/s counts FrameStats::samples_tested: covered samples that reached "
                 "the depth test (blocks rejected by hierarchical z are not counted). "
                 "CPU / wall: CPU time of the thread that called render() over wall time; well "
                 "under 100 % on 1 thread means the run waited for a core taken by other work "
                 "(on 2 threads it also shows the caller waiting for the other worker).\n\n";
    frames_table(r);
    std::cout << "\nThe mesh scenes lit per pixel (`lambert_shader` on their vertex normals, "
                 "`--shade lambert`) against the same meshes flat (ms, medians):\n\n";
    lit_table(r);
    std::cout << "\nSpeed-up of each instruction set over the scalar reference:\n\n";
    isa_table(r);
    std::cout << "\nWhere a 4x frame's time goes (ms; FrameStats medians, then the isolated "
                 "stage cases):\n\n";
    stages_table(r);
    std::cout << "\nWhat each feature of a draw costs (bench_features.cpp: random-small, 100k "
                 "triangles of 10–50 px², one thread; each variant changes one thing from flat "
                 "colour with a `less` depth test):\n\n";
    features_table(r);
    std::cout << "\nOcclusion queries against the hierarchical z of a depth-only pass (one "
                 "thread):\n\n";
    occlusion_table(r);
  } catch (const std::exception& e) {
    std::cerr << "mosaic-bench-table: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
