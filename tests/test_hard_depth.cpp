// Depth hard cases, on the reference and every SIMD path: coplanar triangles (z-fighting) resolve
// the same way on every run and for 1, 2 and 7 threads; depth is continuous across shared edges
// (a surface a hair behind a creased mesh never shows through the crease); and reversed-Z (float
// depth cleared to 0, test `greater`) keeps a scene spanning 1e-4 .. 1e6 stable where the
// standard mapping (cleared to 1, test `less`) z-fights.
//
// What breaks them: tiles that merge triangles from several front-end chunks in completion order
// instead of submission order, or a depth race between workers (z-fighting then changes with the
// thread count); a depth plane set up through unsnapped vertices or anchored differently in the two
// triangles of an edge (the surface behind shows through along the crease); a depth buffer or
// interpolation with less than float precision near 0 (reversed-Z then fights as well).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "hard_case_util.hpp"

namespace mosaic {
namespace {

using hard::rule_name;

constexpr FillRule kRules[] = {FillRule::kD3D, FillRule::kOpenGL};
constexpr int kThreadCounts[] = {1, 2, 7};

// A screen-space grid mesh over [x0, x1] x [y0, y1] with `n` x `n` cells and a random diagonal per
// cell, every vertex on `plane` (depth = a + b x + c y), drawn with `state`.
Mesh plane_grid(double x0, double y0, double x1, double y1, int n, glm::dvec3 plane,
                DrawState state, test::Rng& rng, std::uint32_t color_base) {
  Mesh m = test::screen_mesh(state);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = x0 + (x1 - x0) * i / n + (i > 0 && i < n ? rng.uniform(-0.4, 0.4) : 0);
      const double y = y0 + (y1 - y0) * j / n + (j > 0 && j < n ? rng.uniform(-0.4, 0.4) : 0);
      const double z = plane.x + plane.y * x + plane.z * y;
      m.positions.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z),
                               1.0f);
    }
  const auto row = static_cast<std::uint32_t>(n + 1);
  for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j)
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
      const std::uint32_t p = j * row + i;
      if (rng.coin()) {
        m.indices.insert(m.indices.end(), {p, p + 1, p + row + 1, p, p + row + 1, p + row});
      } else {
        m.indices.insert(m.indices.end(), {p, p + 1, p + row, p + 1, p + row + 1, p + row});
      }
      for (int k = 0; k < 2; ++k)
        m.colors.push_back(
            test::distinct_color(color_base + static_cast<std::uint32_t>(m.colors.size())));
    }
  return m;
}

TEST(HardDepth, CoplanarTrianglesAtEqualDepthFollowTheTieRule) {
  // Two different triangulations of the same constant-depth rectangle: every covered sample has
  // exactly the same depth in both, so the tie rule alone decides: `less` keeps the first draw's
  // colour, `less-equal` the second's. Expected colours come from each mesh drawn alone.
  constexpr int kW = 100, kH = 70, kSamples = 4;
  test::Rng rng(1001);
  for (DepthTest test : {DepthTest::kLess, DepthTest::kLessEqual}) {
    DrawState st;
    st.depth_test = test;
    const Mesh a = plane_grid(-3, -3, 103, 73, 7, {0.5, 0, 0}, st, rng, 0);
    const Mesh b = plane_grid(-3, -3, 103, 73, 9, {0.5, 0, 0}, st, rng, 1000);
    const hard::Rendered ra = hard::render_on({a}, {kW, kH, kSamples}, Isa::kReference, 1);
    const hard::Rendered rb = hard::render_on({b}, {kW, kH, kSamples}, Isa::kReference, 1);
    const hard::Rendered& winner = test == DepthTest::kLess ? ra : rb;
    for (Isa isa : available_isas()) {
      for (int threads : kThreadCounts) {
        const hard::Rendered r = hard::render_on({a, b}, {kW, kH, kSamples}, isa, threads);
        EXPECT_EQ(hard::differences(r, winner), 0u)
            << to_string(isa) << " threads " << threads << " test " << int(test);
      }
    }
  }
}

TEST(HardDepth, ZFightingOfCoplanarSlopedMeshesIsTheSameEveryRunAndThreadCount) {
  // Two triangulations of one sloped plane: their float depths differ by rounding, so which one
  // wins flickers from sample to sample (z-fighting) — but always the same way. Enough triangles
  // for several front-end chunks, drawn as several draws, on every path, 1, 2 and 7 threads, twice.
  constexpr int kW = 160, kH = 120, kSamples = 4;
  test::Rng rng(1002);
  for (DepthTest test : {DepthTest::kLess, DepthTest::kLessEqual}) {
    DrawState st;
    st.depth_test = test;
    const glm::dvec3 plane{0.2, 0.003, 0.002};
    const std::vector<Mesh> meshes{plane_grid(-2, -2, 162, 122, 40, plane, st, rng, 0),
                                   plane_grid(-2, -2, 162, 122, 37, plane, st, rng, 20000),
                                   plane_grid(-2, -2, 162, 122, 29, plane, st, rng, 40000)};
    const hard::Rendered ref = hard::render_on(meshes, {kW, kH, kSamples}, Isa::kReference, 1);
    // The case is a real fight: every mesh wins somewhere, and no mesh everywhere.
    std::array<std::size_t, 3> wins{};
    for (const Rgba8& c : ref.sample_color) {
      const std::uint32_t id = c.r | (std::uint32_t{c.g} << 8);
      wins[id < 20000 ? 0 : id < 40000 ? 1 : 2] += 1;
    }
    for (std::size_t k = 0; k < 3; ++k) EXPECT_GT(wins[k], 1000u) << "mesh " << k;
    for (Isa isa : available_isas()) {
      for (int threads : kThreadCounts) {
        for (int run = 0; run < 2; ++run) {
          const hard::Rendered r = hard::render_on(meshes, {kW, kH, kSamples}, isa, threads);
          EXPECT_EQ(hard::differences(r, ref), 0u)
              << to_string(isa) << " threads " << threads << " run " << run;
        }
      }
    }
  }
}

TEST(HardDepth, NoCrackAlongSharedEdgesWhereASurfaceBehindCouldShowThrough) {
  // A creased surface: depth = D0 + kTilt x + s (y - yc) with s = kSlopeAbove above the crease
  // y = yc and kSlopeBelow below it. A plane with the middle slope kSlopeBehind, kGap farther at
  // the crease, is drawn first: it is behind the creased surface everywhere, and only kGap behind
  // along the crease. The creased mesh has its crease vertices at random x off the 1/256 grid;
  // if the two sides of the crease disagreed on depth there by more than kGap, or left a sample
  // uncovered, the plane behind would show. It must show nowhere. (Depth rises along the crease
  // and crosses it, so the clamp to each triangle's vertex depth range cannot hide an error.)
  //
  // kGap is 2e-6 (about 30 float ulps at 0.5): the float evaluation of a depth plane is good to a
  // few ulps of its terms (~3e-7 here), while a plane through unsnapped vertices would be off by
  // up to kSlopeAbove / 512 = 1.6e-5 at the crease.
  constexpr double kD0 = 0.5, kTilt = 0.001, kSlopeAbove = 0.008, kSlopeBelow = 0.004;
  constexpr double kSlopeBehind = 0.006, kGap = 2e-6;
  constexpr int kW = 130, kH = 70;
  constexpr Rgba8 kBehindColor{1, 200, 1, 255};
  test::Rng rng(1003);
  for (FillRule rule : kRules) {
    for (int samples : {4, 16}) {
      DrawState st;
      st.fill_rule = rule;
      const double yc = 35.3 + rng.uniform(0, 1);
      auto surface = [&](double x, double y, double slope) {
        return kD0 + kTilt * x + slope * (y - yc);
      };
      auto vertex = [](double x, double y) {
        return glm::dvec2(static_cast<float>(x), static_cast<float>(y));
      };
      Mesh behind = test::screen_mesh(st);
      const glm::dvec2 corners[4] = {vertex(-2, -2), vertex(kW + 2, -2), vertex(kW + 2, kH + 2),
                                     vertex(-2, kH + 2)};
      for (int k : {0, 1, 2, 0, 2, 3}) {
        const glm::dvec2 p = corners[k];
        behind.positions.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y),
                                      static_cast<float>(surface(p.x, p.y, kSlopeBehind) + kGap),
                                      1.0f);
      }
      behind.colors = {kBehindColor, kBehindColor};
      Mesh creased = test::screen_mesh(st);
      const int n = 23;
      for (int row = 0; row < 3; ++row)
        for (int i = 0; i <= n; ++i) {
          const double x0 = i == 0 ? -5.0 : i == n ? kW + 5.0 : -5.0 + (kW + 10.0) * i / n;
          const glm::dvec2 p = vertex(x0 + rng.uniform(-1, 1), row == 0   ? -5.0
                                                               : row == 1 ? yc
                                                                          : kH + 5.0);
          const double slope = p.y < yc ? kSlopeAbove : kSlopeBelow;
          creased.positions.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y),
                                         static_cast<float>(surface(p.x, p.y, slope)), 1.0f);
        }
      const auto row = static_cast<std::uint32_t>(n + 1);
      for (std::uint32_t j = 0; j < 2; ++j)
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
          const std::uint32_t p = j * row + i;
          if (rng.coin()) {
            hard::add_indexed(creased, p, p + 1, p + row + 1);
            hard::add_indexed(creased, p, p + row + 1, p + row);
          } else {
            hard::add_indexed(creased, p, p + 1, p + row);
            hard::add_indexed(creased, p + 1, p + row + 1, p + row);
          }
        }
      const auto all = hard::render_all({behind, creased}, {kW, kH, samples});
      hard::expect_paths_agree(all, std::string("crease ") + rule_name(rule));
      for (const hard::Rendered& r : all) {
        std::size_t shows = 0;
        for (const Rgba8& c : r.sample_color) shows += c == kBehindColor ? 1 : 0;
        EXPECT_EQ(shows, 0u) << to_string(r.isa) << " " << samples << "x " << rule_name(rule);
      }
    }
  }
}

// Pairs of camera-facing quads at view distances d and d * (1 + kSeparation), one pair per
// vertical band of the image, for d from 2e-4 to 5e5 (the near plane is 1e-4, the far 1e6). The
// nearer quad of each pair is red, the farther blue; draw order is near-first or far-first.
// Vertices are view-space positions through a float matrix, as an application would give them.
constexpr double kNear = 1e-4, kFar = 1e6, kSeparation = 1e-3;
constexpr double kDistances[] = {2e-4, 1e-2, 1, 100, 1e4, 5e5};

std::vector<Mesh> depth_pairs(const glm::mat4& projection, DepthTest test, bool far_first,
                              int bands) {
  std::vector<Mesh> out;
  for (int pass = 0; pass < 2; ++pass) {
    const bool far = (pass == 0) == far_first;
    Mesh m;
    m.space = Space::kClip;
    m.state.depth_test = test;
    m.color = far ? Rgba8{0, 0, 255, 255} : Rgba8{255, 0, 0, 255};
    for (int b = 0; b < bands; ++b) {
      const double d = kDistances[b] * (far ? 1 + kSeparation : 1.0);
      // The band's NDC x range, scaled by d so the quad covers it at that distance (the
      // projection's x and y scale is 1: fovy = 90 degrees, aspect 1).
      const double x0 = -1 + 2.0 * b / bands, x1 = -1 + 2.0 * (b + 1) / bands;
      const glm::dvec3 corners[4] = {
          {x0 * d, -d, -d}, {x1 * d, -d, -d}, {x1 * d, d, -d}, {x0 * d, d, -d}};
      std::vector<glm::vec4> c;
      for (const glm::dvec3& p : corners)
        c.push_back(projection * glm::vec4(static_cast<float>(p.x), static_cast<float>(p.y),
                                           static_cast<float>(p.z), 1.0f));
      for (int k : {0, 1, 2, 0, 2, 3}) m.positions.push_back(c[static_cast<std::size_t>(k)]);
    }
    out.push_back(std::move(m));
  }
  return out;
}

// Pixels where the nearer quad does not show, over both draw orders, and whether the paths agree.
std::size_t far_wins(const glm::mat4& projection, DepthTest test, float clear_depth,
                     std::size_t& per_band_failures) {
  constexpr int kBands = static_cast<int>(std::size(kDistances));
  constexpr int kW = kBands * 8, kH = 8;
  std::size_t total = 0;
  per_band_failures = 0;
  std::vector<bool> band_failed(kBands, false);
  for (bool far_first : {false, true}) {
    const auto meshes = depth_pairs(projection, test, far_first, kBands);
    hard::TargetSpec spec{kW, kH, 1};
    spec.clear_depth = clear_depth;
    const auto all = hard::render_all(meshes, spec);
    hard::expect_paths_agree(all, "depth pairs");
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const Rgba8 c = all[0].color[static_cast<std::size_t>(y) * kW + x];
        // Not red: the far quad won, or (standard mapping at 5e5, depth 1 - 2e-10 rounds to the
        // clear value 1) neither quad passed the test.
        if (!(c == Rgba8{255, 0, 0, 255})) {
          ++total;
          band_failed[static_cast<std::size_t>(x / 8)] = true;
        }
      }
  }
  for (bool f : band_failed) per_band_failures += f ? 1 : 0;
  return total;
}

TEST(HardDepth, ReversedZKeepsANearFarRatioOfTenToTheTenStableWhereStandardZFights) {
  // Standard mapping (glm::perspectiveRH_ZO): depth = f (d - n) / (d (f - n)) ~ 1 - n / d, so at
  // d = 100 the pair's depths 1 - 1e-6 and 1 - 0.999e-6 round to the same float (ulp 6e-8): the
  // draw order, not the distance, decides. Reversed-Z maps near to 1 and far to 0, depth ~ n / d,
  // where float's relative precision holds at every distance.
  const glm::mat4 standard =
      glm::perspectiveRH_ZO(glm::radians(90.0f), 1.0f, float(kNear), float(kFar));
  // Reversed: z_clip = n / (f - n) * z_eye + f n / (f - n), w = -z_eye: depth n (f - d) / (d (f -
  // n)).
  glm::mat4 reversed = standard;
  reversed[2][2] = static_cast<float>(kNear / (kFar - kNear));
  reversed[3][2] = static_cast<float>(kFar * kNear / (kFar - kNear));

  std::size_t bands_reversed = 0, bands_standard = 0;
  EXPECT_EQ(far_wins(reversed, DepthTest::kGreater, 0.0f, bands_reversed), 0u)
      << "reversed-Z must resolve every pair at every distance";
  EXPECT_EQ(bands_reversed, 0u);
  // The standard mapping fails, and not only at one distance: this is the failure reversed-Z fixes.
  EXPECT_GT(far_wins(standard, DepthTest::kLess, 1.0f, bands_standard), 0u)
      << "the standard mapping was expected to z-fight at far distances";
  EXPECT_GE(bands_standard, 3u);
}

}  // namespace
}  // namespace mosaic

namespace mosaic {
namespace {

// Found by the pipeline fuzzer: a triangle with one vertex far behind the eye (W = -8.8e21) and
// depths near 0, whose clipped corners have a W so small that the rounding of their Z, divided
// by it, gave every sample a depth of -1.9e-6. Depth is clamped to [0, 1] at the divide.
TEST(HardDepth, ClippedCornersWithATinyWKeepDepthInTheRange) {
  const auto vertex = [](std::uint32_t x, std::uint32_t y, std::uint32_t z, std::uint32_t w) {
    return glm::vec4(std::bit_cast<float>(x), std::bit_cast<float>(y), std::bit_cast<float>(z),
                     std::bit_cast<float>(w));
  };
  const std::vector<glm::vec4> positions{vertex(0x003f0000, 0x003f8000, 0x01010201, 0x3ffffe00),
                                         vertex(0x00130000, 0xc5c50000, 0x0041a000, 0x41a02a00),
                                         vertex(0x3f000000, 0x3f800000, 0x01020100, 0xe3ee0201)};
  Draw draw;
  draw.positions = positions;
  draw.state.depth_test = DepthTest::kLess;
  for (const int samples : {1, 4}) {
    test::RenderSetup how;
    how.samples = samples;
    const test::Captured ref = test::render_draws({&draw, 1}, 48, 30, how, {1, 2, 3, 4});
    ASSERT_GT(ref.stats.samples_written, 0u);
    EXPECT_EQ(ref.stats.triangles_clipped, 1u);
    for (const float d : ref.sample_depth) ASSERT_TRUE(d >= 0.0f && d <= 1.0f) << d;
    for (const Isa isa : test::simd_isas()) {
      how.isa = isa;
      how.threads = 2;
      test::expect_same(ref, test::render_draws({&draw, 1}, 48, 30, how, {1, 2, 3, 4}),
                        std::string(to_string(isa)) + ", " + std::to_string(samples) + "x");
    }
  }
}

}  // namespace
}  // namespace mosaic
