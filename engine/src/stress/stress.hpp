// stress/stress.hpp — random-mesh stress testing: the generator, the checker, the reducer and
// the run loop behind `mosaic stress`.
//
// Takes: a seed and limits. Gives: random screen-space cases (closed meshes, full-screen grids,
// fans, triangle soups) with random transforms, target sizes, sample counts and fill rules; a
// check of each against invariants (every sample exactly once for grids and fans, front and back
// faces of a closed mesh balanced, fast path bit-equal to the reference, the image independent of
// the thread count, no exception); and, for a failure, the smallest failing triangle subset that
// delta debugging finds, written as a `.tris` file.
//
// Cases are built in screen space (closed meshes are projected by the generator, with the eye
// outside them), so a `.tris` file reproduces a case exactly: save_tris writes every float in its
// shortest round-trip form.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "mosaic/renderer.hpp"
#include "mosaic/scene.hpp"

namespace mosaic::stress {

/// The shape of a random case.
enum class CaseKind : std::uint8_t {
  kClosed,  ///< a closed mesh (sphere, box, torus) in perspective: fronts and backs balance
  kGrid,    ///< a jittered, rotated full-screen triangulation: every sample exactly once
  kFan,     ///< rings of a polar fan around a point, rim up to 1e30 px away: exactly once
  kSoup,    ///< unrelated triangles: tiny, slivers, needles, huge, random depth state
};

/// "closed", "grid", "fan" or "soup".
const char* to_string(CaseKind kind) noexcept;

/// One random case: a screen-space mesh and the target it is drawn into.
struct StressCase {
  CaseKind kind = CaseKind::kSoup;
  int width = 1, height = 1, samples = 1;
  Mesh mesh;  ///< screen space, indexed or not, one colour per triangle
};

/// Builds case number `index` of the run with `seed`; deterministic. `msaa` 0 picks the sample
/// count at random, otherwise it is used (1, 4, 8 or 16).
StressCase generate_case(std::uint64_t seed, std::uint64_t index, int msaa = 0);

/// What broke.
enum class FailureKind : std::uint8_t {
  kNone,
  kReferenceMismatch,  ///< the fast path's samples differ from the reference's
  kThreadMismatch,     ///< two thread counts (and tile sizes) gave different samples
  kCoverage,           ///< a grid or fan did not cover every sample exactly once
  kBalance,            ///< a closed mesh's front and back faces covered different samples
  kException,          ///< render() threw
};

/// How a case is checked.
struct CheckOptions {
  int threads = 2;        ///< threads of the fast path's main render
  int other_threads = 7;  ///< a second thread count the image must not depend on
  /// The tile size of that second render (the first uses the renderer's choice): small tiles put
  /// tile edges through most triangles, where binning and the kernels' clipping to the tile work.
  int other_tile_size = 16;
  Isa isa = Isa::kAuto;  ///< the fast path checked against the reference
};

/// The outcome of a check; `message` is one line naming the failure.
struct CheckResult {
  FailureKind kind = FailureKind::kNone;
  std::string message;
  bool ok() const { return kind == FailureKind::kNone; }
};

/// Checks one case against every invariant that applies to its kind.
CheckResult check_case(const StressCase& c, const CheckOptions& options);

/// One unindexed screen-space triangle with its flat colour.
struct Triangle {
  glm::vec4 v[3];
  Rgba8 color;
};

/// The case's triangles in draw order, unindexed.
std::vector<Triangle> triangles_of(const StressCase& c);
/// A screen-space mesh of `tris` drawn with `state`.
Mesh mesh_of(const std::vector<Triangle>& tris, const DrawState& state);

/// Delta debugging (Zeller's ddmin) over the items 0..n-1: a smallest subset (1-minimal: no
/// single item can be removed) for which `fails` holds, given that it holds for all n items.
/// Stops refining after `max_tests` calls of `fails` and returns the smallest failing subset
/// found so far.
std::vector<std::size_t> ddmin(std::size_t n,
                               const std::function<bool(const std::vector<std::size_t>&)>& fails,
                               int max_tests);

/// Reduces a failing case: the triangles of the smallest subset that still fails the same way.
/// For a coverage or balance failure "the same way" means the engine disagrees with an exact
/// integer coverage oracle on the subset (possible only while every vertex lies within the
/// 16.8 range; otherwise the case is returned whole).
std::vector<Triangle> reduce_failure(const StressCase& c, const CheckResult& failure,
                                     const CheckOptions& options, int max_tests);

/// Writes `tris` as a `.tris` file for a c.width × c.height target, with comment lines saying
/// what failed and how to replay it with `mosaic render`. Throws Error{kIo}.
void write_failure(const StressCase& c, const std::vector<Triangle>& tris, const std::string& what,
                   const std::filesystem::path& path);

/// Limits and outputs of a stress run.
struct RunOptions {
  std::uint64_t seed = 1;
  double minutes = 1;                   ///< wall-clock budget
  std::uint64_t frames = 0;             ///< also stop after this many cases (0: no limit)
  int msaa = 0;                         ///< 0: random per case
  int threads = 2;                      ///< threads of the fast path
  std::filesystem::path out_dir = ".";  ///< where failing .tris files go
  int max_reduce_tests = 400;           ///< delta-debugging budget per failure
  double progress_seconds = 5;          ///< seconds between progress lines
};

/// What a run did.
struct RunSummary {
  std::uint64_t frames = 0, triangles = 0, failures = 0;
  std::vector<std::filesystem::path> files;  ///< the .tris written, one per failure
};

/// Generates and checks cases until the time or frame limit; prints progress lines to `log`.
RunSummary run_stress(const RunOptions& options, std::ostream& log);

}  // namespace mosaic::stress
