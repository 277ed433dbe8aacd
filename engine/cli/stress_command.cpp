// cli/stress_command.cpp — `mosaic stress`: random-mesh stress testing against invariants and
// the reference (engine/src/stress/stress.hpp).
//
// Takes: --seed, --minutes, --frames, --msaa, --threads, --out-dir. Gives: progress lines on
// stderr (frames, triangles, failures), one reduced .tris file per failing frame, and exit status
// 0 when every frame passed, 1 when any failed.
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "mosaic/errors.hpp"
#include "mosaic/renderer.hpp"
#include "stress/stress.hpp"

namespace mosaic::cli {

namespace {

// A week: any longer --minutes is a typo.
constexpr double kMaxMinutes = 7 * 24 * 60;

struct StressCliOptions {
  std::uint64_t seed = 1;
  double minutes = 1;
  std::uint64_t frames = 0;
  int msaa = 0;
  int threads = 2;
  std::string out_dir = ".";
};

int run_stress_command(const StressCliOptions& o) {
  // The folder for failing cases is made if it is missing, before the first frame runs.
  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec || !std::filesystem::is_directory(o.out_dir))
    throw mosaic::Error(mosaic::Errc::kIo,
                        "--out-dir: cannot make the folder '" + o.out_dir + "'" +
                            (ec ? ": " + ec.message() : ": a file of that name exists"));
  stress::RunOptions r;
  r.seed = o.seed;
  r.minutes = o.minutes;
  r.frames = o.frames;
  r.msaa = o.msaa;
  r.threads = o.threads;
  r.out_dir = o.out_dir;
  std::cerr << "stress: seed " << o.seed << ", " << o.minutes << " min"
            << (o.frames != 0 ? ", at most " + std::to_string(o.frames) + " frames" : "")
            << ", msaa " << (o.msaa == 0 ? std::string("random") : std::to_string(o.msaa)) << ", "
            << o.threads << " threads" << std::endl;
  const stress::RunSummary s = stress::run_stress(r, std::cerr);
  if (s.failures == 0) {
    std::cerr << "stress: passed: " << s.frames << " frames, " << s.triangles << " triangles"
              << std::endl;
    return kExitOk;
  }
  std::cerr << "stress: " << s.failures << " of " << s.frames << " frames failed" << std::endl;
  return kExitRuntimeError;
}

}  // namespace

Command add_stress_command(CLI::App& parent) {
  auto o = std::make_shared<StressCliOptions>();
  CLI::App* app = parent.add_subcommand(
      "stress",
      "Draw random closed meshes, grids, fans and triangle soups; check watertightness, "
      "bit-equality with the reference and thread-count independence; write a reduced .tris for "
      "every failure");
  app->add_option("--seed", o->seed, "Seed of the random cases")
      ->type_name("S")
      ->transform(unsigned_integer())
      ->capture_default_str();
  app->add_option("--minutes", o->minutes, "Time budget in minutes (fractions allowed)")
      ->type_name("M")
      ->check(CLI::Range(0.0, kMaxMinutes))
      ->capture_default_str();
  app->add_option("--frames", o->frames, "Stop after N frames as well (0: no limit)")
      ->type_name("N")
      ->transform(unsigned_integer())
      ->capture_default_str();
  app->add_option("--msaa", o->msaa, "Samples per pixel of every frame (default: random)")
      ->type_name("N")
      ->transform(integer_in(1, 16))
      ->check(CLI::IsMember({1, 4, 8, 16}));
  app->add_option("--threads", o->threads, "Worker threads of the fast path")
      ->type_name("N")
      ->transform(thread_count(1))
      ->capture_default_str();
  app->add_option("--out-dir", o->out_dir, "Where failing .tris files are written")
      ->type_name("DIR")
      ->capture_default_str();
  return Command{app, [o] { return run_stress_command(*o); }};
}

}  // namespace mosaic::cli
