// The stress tool (engine/src/stress, `mosaic stress`): delta debugging finds a 1-minimal failing
// subset; cases are deterministic per seed and pass their checks; the checks catch a hole in a
// grid and an unbalanced closed mesh; a written failure file replays bit for bit; and the CLI
// runs a few seconds with a fixed seed (the CI smoke run), prints progress and rejects bad
// options with one line and exit status 2.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "reference_test_util.hpp"
#include "stress/stress.hpp"

namespace mosaic::stress {
namespace {

namespace fs = std::filesystem;

TEST(StressDdmin, FindsExactlyTheItemsThatTogetherFail) {
  // Fails iff items 3, 17 and 90 are all present: ddmin must return exactly those three.
  int calls = 0;
  auto fails = [&](const std::vector<std::size_t>& s) {
    ++calls;
    const std::set<std::size_t> in(s.begin(), s.end());
    return in.count(3) && in.count(17) && in.count(90);
  };
  const auto r = ddmin(200, fails, 1000);
  EXPECT_EQ(r, (std::vector<std::size_t>{3, 17, 90}));
  EXPECT_LT(calls, 300);
  // A single culprit; and a budget too small to finish still returns a failing subset.
  const auto one = ddmin(
      1000,
      [](const auto& s) { return std::find(s.begin(), s.end(), std::size_t{777}) != s.end(); },
      1000);
  EXPECT_EQ(one, std::vector<std::size_t>{777});
  const auto partial = ddmin(1000, fails, 3);
  EXPECT_TRUE(fails(partial));
  EXPECT_LT(partial.size(), 1000u);
}

TEST(StressCases, DeterministicPerSeedAndIndexAndAllKindsAppear) {
  std::set<CaseKind> kinds;
  for (std::uint64_t i = 0; i < 40; ++i) {
    const StressCase a = generate_case(5, i), b = generate_case(5, i);
    ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
    EXPECT_EQ(0, std::memcmp(a.mesh.positions.data(), b.mesh.positions.data(),
                             a.mesh.positions.size() * sizeof(glm::vec4)));
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.samples, b.samples);
    kinds.insert(a.kind);
  }
  EXPECT_EQ(kinds.size(), 4u);
  EXPECT_NE(generate_case(5, 0).mesh.positions, generate_case(6, 0).mesh.positions);
  EXPECT_EQ(generate_case(5, 3, 8).samples, 8);
}

TEST(StressCases, GeneratedCasesPassEveryCheck) {
  for (std::uint64_t i = 0; i < 40; ++i) {
    const StressCase c = generate_case(11, i);
    const CheckResult r = check_case(c, CheckOptions{});
    EXPECT_TRUE(r.ok()) << "case " << i << " (" << to_string(c.kind) << "): " << r.message;
  }
}

// The number of grid cells whose two triangles overlap once snapped to 1/256 px: the vertex that
// is not on the cell's diagonal lies on the same side of it in both. Cells with a vertex beyond
// 65536 px (the far border) are skipped; their products would leave int64's exact range.
int folded_cells(const StressCase& c) {
  using test::Fx;
  const Mesh& m = c.mesh;
  if (c.kind != CaseKind::kGrid || m.indices.size() != 3 * m.triangle_count()) {
    ADD_FAILURE() << "not an indexed grid";
    return -1;
  }
  int folded = 0;
  auto cross = [](Fx o, Fx a, Fx b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  for (std::size_t t = 0; t + 1 < m.triangle_count(); t += 2) {
    const std::uint32_t* i0 = &m.indices[3 * t];
    const std::uint32_t* i1 = &m.indices[3 * t + 3];
    std::vector<std::uint32_t> shared, own;
    for (int k = 0; k < 3; ++k)
      (std::find(i1, i1 + 3, i0[k]) != i1 + 3 ? shared : own).push_back(i0[k]);
    for (int k = 0; k < 3; ++k)
      if (std::find(i0, i0 + 3, i1[k]) == i0 + 3) own.push_back(i1[k]);
    if (shared.size() != 2) {
      ADD_FAILURE() << "triangles " << t << " and " << t + 1 << " share no edge";
      continue;
    }
    Fx p[4];
    const std::uint32_t ids[4] = {shared[0], shared[1], own[0], own[1]};
    bool near = true;
    for (int k = 0; k < 4; ++k) {
      const glm::vec4& v = m.positions[ids[k]];
      near = near && std::abs(v.x) < 65536 && std::abs(v.y) < 65536;
    }
    if (!near) continue;  // snapping it, or its products, would leave int64
    for (int k = 0; k < 4; ++k)
      p[k] = test::snap_fx({m.positions[ids[k]].x, m.positions[ids[k]].y});
    const std::int64_t side2 = cross(p[0], p[1], p[2]), side3 = cross(p[0], p[1], p[3]);
    if (side2 != 0 && side3 != 0 && (side2 > 0) == (side3 > 0)) ++folded;
  }
  return folded;
}

TEST(StressCases, GridCellsNeverFold) {
  // A grid must cover every sample exactly once, so no cell may fold: seed 11's frame 9053 at 1x
  // once jittered a vertex across its cell's diagonal, and the check reported a correct image.
  EXPECT_EQ(folded_cells(generate_case(11, 9053, 1)), 0);
  int grids = 0;
  for (std::uint64_t seed : {11, 12, 13})
    for (std::uint64_t i = 0; i < 2000; ++i) {
      const StressCase c = generate_case(seed, i, 1);
      if (c.kind != CaseKind::kGrid) continue;
      ++grids;
      EXPECT_EQ(folded_cells(c), 0) << "seed " << seed << " case " << i;
    }
  EXPECT_GT(grids, 1000);
}

TEST(StressChecks, AFoldedCellCoversASampleTwiceAndTheEngineAgrees) {
  // The reduced false alarm: two triangles of a folded cell overlap, so exact rasterization
  // writes one sample twice. The oracle and both renderers agree; the generator was at fault.
  Mesh m = test::screen_mesh(DrawState{.depth_test = DepthTest::kAlways, .cull = CullMode::kNone});
  test::add_tri(m, {22.41658, 17.953146}, {29.576397, 17.374908}, {29.04652, 24.171745},
                test::distinct_color(1));
  test::add_tri(m, {22.41658, 17.953146}, {25.9719, 20.93228}, {29.04652, 24.171745},
                test::distinct_color(2));
  std::int64_t oracle_writes = 0, twice = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 73; ++x) {
      const test::Fx s = test::sample_fx(x, y, 0, 1);
      int n = 0;
      for (std::size_t t = 0; t < 2; ++t) {
        const glm::vec4* v = &m.positions[3 * t];
        n += test::oracle_covers_tri(test::snap_fx({v[0].x, v[0].y}),
                                     test::snap_fx({v[1].x, v[1].y}),
                                     test::snap_fx({v[2].x, v[2].y}), s, m.state.fill_rule);
      }
      oracle_writes += n;
      twice += n == 2;
    }
  EXPECT_GT(twice, 0);
  for (Isa isa : {Isa::kReference, Isa::kAuto}) {
    RenderTarget target = test::sample_target(73, 240, 1);
    const Draw d = m.draw();
    Renderer r(RendererOptions{2, isa});
    const FrameStats st = r.render(Frame{std::span<const Draw>(&d, 1)}, target);
    EXPECT_EQ(static_cast<std::int64_t>(st.samples_written), oracle_writes);
  }
}

// The first case of `kind` for seed 11.
StressCase first_case(CaseKind kind) {
  for (std::uint64_t i = 0;; ++i) {
    StressCase c = generate_case(11, i, 4);
    if (c.kind == kind && c.mesh.triangle_count() > 8) return c;
  }
}

// The case's triangles, those containing the target's centre first, then by decreasing area:
// removing one of the first few surely uncovers samples, so the loops below stay short.
std::vector<std::size_t> removal_order(const StressCase& c) {
  const std::vector<Triangle> tris = triangles_of(c);
  const glm::dvec2 p{c.width * 0.5 + 0.13, c.height * 0.5 + 0.07};
  std::vector<std::pair<double, std::size_t>> keyed;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const glm::dvec2 a(tris[t].v[0]), b(tris[t].v[1]), d(tris[t].v[2]);
    auto cross = [](glm::dvec2 u, glm::dvec2 v) { return u.x * v.y - u.y * v.x; };
    const double e0 = cross(b - a, p - a), e1 = cross(d - b, p - b), e2 = cross(a - d, p - d);
    const bool contains = (e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0);
    const double area = std::abs(cross(b - a, d - a));
    keyed.emplace_back(contains ? -1e300 : -std::min(area, 1e300), t);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::size_t> order;
  for (const auto& k : keyed) order.push_back(k.second);
  return order;
}

StressCase without_triangle(const StressCase& c, std::size_t t) {
  StressCase broken = c;
  broken.mesh.indices.erase(broken.mesh.indices.begin() + static_cast<std::ptrdiff_t>(3 * t),
                            broken.mesh.indices.begin() + static_cast<std::ptrdiff_t>(3 * t + 3));
  broken.mesh.colors.erase(broken.mesh.colors.begin() + static_cast<std::ptrdiff_t>(t));
  return broken;
}

TEST(StressChecks, AHoleInAGridOrAFanIsACoverageFailure) {
  for (CaseKind kind : {CaseKind::kGrid, CaseKind::kFan}) {
    const StressCase c = first_case(kind);
    ASSERT_TRUE(check_case(c, {}).ok());
    // Without the triangle over the target's centre some sample is left uncovered.
    const CheckResult r = check_case(without_triangle(c, removal_order(c).front()), {});
    EXPECT_EQ(r.kind, FailureKind::kCoverage) << to_string(kind) << ": " << r.message;
  }
}

TEST(StressChecks, AnOpenClosedMeshIsABalanceFailure) {
  const StressCase c = first_case(CaseKind::kClosed);
  ASSERT_TRUE(check_case(c, {}).ok());
  // Without one of its largest (visible) triangles the mesh is open: front and back differ.
  bool caught = false;
  const std::vector<std::size_t> order = removal_order(c);
  for (std::size_t k = 0; k < order.size() && k < 10 && !caught; ++k) {
    const CheckResult r = check_case(without_triangle(c, order[k]), {});
    if (!r.ok()) {
      EXPECT_EQ(r.kind, FailureKind::kBalance) << r.message;
      caught = true;
    }
  }
  EXPECT_TRUE(caught);
}

TEST(StressReduce, CoverageFailuresTheOracleAgreesWithAreNotReduced) {
  // A hole the generator made (not the engine) is no engine failure: the exact oracle agrees
  // with the engine, so the case is kept whole rather than "reduced" to nothing.
  StressCase c = first_case(CaseKind::kFan);
  c.mesh.indices.resize(c.mesh.indices.size() - 3);
  c.mesh.colors.pop_back();
  const CheckResult r = check_case(c, {});
  ASSERT_EQ(r.kind, FailureKind::kCoverage) << r.message;
  EXPECT_EQ(reduce_failure(c, r, {}, 100).size(), c.mesh.triangle_count());
}

TEST(StressReduce, WrittenFailureReplaysBitForBit) {
  const fs::path dir = fs::temp_directory_path() / "mosaic_test_stress_write";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (CaseKind kind : {CaseKind::kSoup, CaseKind::kClosed, CaseKind::kFan}) {
    const StressCase c = first_case(kind);
    std::vector<Triangle> tris = triangles_of(c);
    tris.resize(std::min<std::size_t>(tris.size(), 50));
    const fs::path file = dir / (std::string(to_string(kind)) + ".tris");
    write_failure(c, tris, "a test", file);
    const Scene s = load_tris(file);
    EXPECT_EQ(s.width, c.width);
    EXPECT_EQ(s.height, c.height);
    // Render both with culling off and the case's fill rule and depth state (the replay line).
    DrawState st = c.mesh.state;
    st.cull = CullMode::kNone;
    Mesh original = mesh_of(tris, st);
    if (c.mesh.state.cull != CullMode::kNone) {
      // The file leaves out what the case culled: cull the original the same way instead.
      original.state.cull = c.mesh.state.cull;
      original.state.front_face = c.mesh.state.front_face;
    }
    Mesh replay = s.meshes.at(0);
    replay.state = st;
    auto image = [&](const Mesh& m) {
      RenderTarget t(c.width, c.height, c.samples, {true, true});
      t.set_clear(s.clear_color);
      const Draw d = m.draw();
      Renderer r(RendererOptions{1, Isa::kReference});
      r.render(Frame{std::span<const Draw>(&d, 1)}, t);
      return std::vector<Rgba8>(t.sample_color().begin(), t.sample_color().end());
    };
    EXPECT_EQ(image(original), image(replay)) << to_string(kind);
    std::ifstream in(file);
    std::string first;
    std::getline(in, first);
    EXPECT_NE(first.find("a test"), std::string::npos) << first;
  }
  fs::remove_all(dir);
}

// ---- The CLI ----

struct CliRun {
  int status = -1;
  std::string err;
};

CliRun run_cli(const std::string& args) {
  // One file per process: ctest runs this binary's tests in parallel processes.
  const fs::path err =
      fs::temp_directory_path() / ("mosaic_test_stress_err_" + std::to_string(getpid()) + ".txt");
  const std::string cmd =
      std::string(MOSAIC_CLI_PATH) + " " + args + " 2> " + err.string() + " > /dev/null";
  const int raw = std::system(cmd.c_str());
  CliRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(err);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  return r;
}

TEST(StressCli, FixedSeedRunsForAFewSecondsAndPasses) {
  // The CI smoke run: a fixed seed, a few seconds (or 200 frames, whichever comes first).
  // The output folder does not exist yet: the tool makes it (and its parent).
  const fs::path dir = fs::temp_directory_path() / "mosaic_test_stress_cli" / "failures";
  fs::remove_all(dir.parent_path());
  const CliRun r =
      run_cli("stress --seed 7 --minutes 0.05 --frames 200 --threads 2 --out-dir " + dir.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("failures 0"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("stress: passed"), std::string::npos) << r.err;
  ASSERT_TRUE(fs::is_directory(dir));
  EXPECT_TRUE(fs::is_empty(dir)) << "no failure files";
  fs::remove_all(dir.parent_path());
}

TEST(StressCli, AnOutputFolderThatCannotBeMadeIsAnErrorBeforeAnyFrame) {
  // A regular file stands where the folder (or its parent) should be.
  const fs::path file = fs::temp_directory_path() / "mosaic_test_stress_not_a_dir";
  std::ofstream(file) << "x";
  for (const fs::path& dir : {file, file / "sub"}) {
    const CliRun r = run_cli("stress --seed 7 --frames 5 --out-dir " + dir.string());
    EXPECT_EQ(r.status, 1) << dir << ": " << r.err;
    EXPECT_NE(r.err.find("--out-dir: cannot make the folder"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("frame"), std::string::npos) << "no frame ran: " << r.err;
  }
  fs::remove(file);
}

TEST(StressCli, BadOptionsAreOneLineAndExitTwo) {
  for (const std::string& args : std::vector<std::string>{
           "stress --msaa 3", "stress --minutes -1", "stress --minutes soon", "stress --threads 0",
           "stress --seed -4", "stress --frames x", "stress --threads 100000", "stress extra",
           "stress --threads " +
               std::to_string(4 * std::max(1u, std::thread::hardware_concurrency()) + 1)}) {
    const CliRun r = run_cli(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("mosaic: ", 0), 0u) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
}

}  // namespace
}  // namespace mosaic::stress
