// Slivers and degenerates, on the reference and every SIMD path, under both fill rules: triangles
// of less than 1/65536 px², a fan of such triangles around a sample, collinear and repeated
// vertices (and repeated indices) between ordinary triangles, and needles 10,000 px long and
// 1/256 px wide, alone and as pairs sharing their long edge.
//
// Coverage is checked sample by sample against the independent oracle of reference_test_util.hpp
// (exact integers on the 1/256 px grid, the fill rule stated as a nudge of the sample): every
// triangle here has its vertices on that grid, so snapping moves nothing and the oracle is exact.
// What breaks them: an area or edge test done in float (a 1-unit² triangle has area 2^-17 px²,
// below float's resolution next to coordinates of 5000 px), a "too small to matter" early-out, a
// bounding box that rounds a 1/256 px needle away, or edge stepping that loses precision over
// 10,000 px.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hard_case_util.hpp"

namespace mosaic {
namespace {

using hard::coverage_mesh;
using hard::rule_name;
using test::Fx;

constexpr FillRule kRules[] = {FillRule::kD3D, FillRule::kOpenGL};

struct TriFx {
  Fx a, b, c;
};

// Renders `tris` (in order, depth off, distinct colours) on every path and compares every sample
// with the oracle: the colour of the last triangle covering it, or the clear colour, and the total
// number of writes.
void expect_matches_oracle(const std::vector<TriFx>& tris, int w, int h, int samples, FillRule rule,
                           const std::string& what) {
  ASSERT_LE(tris.size(), 1u << 16) << "distinct_color has 2^16 colours";
  Mesh m = coverage_mesh(rule);
  for (std::size_t i = 0; i < tris.size(); ++i)
    test::add_tri_fx(m, tris[i].a, tris[i].b, tris[i].c,
                     test::distinct_color(static_cast<std::uint32_t>(i)));
  std::vector<Rgba8> expected(static_cast<std::size_t>(w) * h * samples, test::kClear);
  std::uint64_t writes = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int s = 0; s < samples; ++s) {
        const Fx p = test::sample_fx(x, y, s, samples);
        for (std::size_t i = 0; i < tris.size(); ++i) {
          if (!test::oracle_covers_tri(tris[i].a, tris[i].b, tris[i].c, p, rule)) continue;
          ++writes;
          expected[(static_cast<std::size_t>(y) * w + x) * samples + s] =
              test::distinct_color(static_cast<std::uint32_t>(i));
        }
      }
  const auto all = hard::render_all({m}, {w, h, samples});
  for (const hard::Rendered& r : all) {
    const std::string where = what + " on " + to_string(r.isa);
    EXPECT_EQ(r.stats.samples_written, writes) << where;
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < expected.size(); ++i)
      wrong += r.sample_color[i] == expected[i] ? 0 : 1;
    EXPECT_EQ(wrong, 0u) << where;
  }
  hard::expect_paths_agree(all, what);
}

TEST(HardSlivers, TrianglesBelowOneSixtyFiveThousandthOfAPixel) {
  // Doubled areas of 1 to 3 units² (areas of 2^-17 to 1.5 * 2^-16 px²), at and next to sample
  // positions, in every orientation: a vertex on a sample, an edge through one, or neither.
  constexpr int kW = 20, kH = 16;
  test::Rng rng(701);
  for (int samples : {1, 4, 16}) {
    for (FillRule rule : kRules) {
      std::vector<TriFx> tris;
      for (int i = 0; i < 3000; ++i) {
        const int px = static_cast<int>(rng.range(0, kW - 1)),
                  py = static_cast<int>(rng.range(0, kH - 1));
        Fx a = test::sample_fx(px, py, static_cast<int>(rng.range(0, samples - 1)), samples);
        a.x += rng.range(-1, 1);
        a.y += rng.range(-1, 1);
        // Two short edge vectors whose cross product is 1..3: (1, 0) and (k, 1..3), or a long
        // thin one: (L, 1) and (L + 1, 1) has cross product -1 for any L.
        Fx b, c;
        if (rng.coin()) {
          const std::int64_t k = rng.range(-2, 2);
          b = {a.x + 1, a.y};
          c = {a.x + k, a.y + rng.range(1, 3)};
        } else {
          const std::int64_t l = rng.range(2, 600);
          b = {a.x + l, a.y + 1};
          c = {a.x + l + 1, a.y + 1};
        }
        if (rng.coin()) std::swap(b.x, b.y), std::swap(c.x, c.y), std::swap(a.x, a.y);
        if (rng.coin()) std::swap(b, c);
        tris.push_back({a, b, c});
      }
      expect_matches_oracle(
          tris, kW, kH, samples, rule,
          std::string("tiny ") + std::to_string(samples) + "x " + rule_name(rule));
    }
  }
}

TEST(HardSlivers, FanOfTinyTrianglesAroundASampleCoversItOnce) {
  // Eight triangles of doubled area 1 or 2 units² around a sample, their rim one 1/256 px step
  // away: the sample, a shared vertex of all eight, is covered by exactly one of them.
  for (int samples : {1, 4, 8, 16}) {
    for (FillRule rule : kRules) {
      for (int s = 0; s < samples; ++s) {
        const Fx c = test::sample_fx(3, 2, s, samples);
        const Fx rim[8] = {{c.x + 1, c.y}, {c.x + 1, c.y + 1}, {c.x, c.y + 1}, {c.x - 1, c.y + 1},
                           {c.x - 1, c.y}, {c.x - 1, c.y - 1}, {c.x, c.y - 1}, {c.x + 1, c.y - 1}};
        std::vector<TriFx> tris;
        for (int k = 0; k < 8; ++k) tris.push_back({c, rim[k], rim[(k + 1) % 8]});
        expect_matches_oracle(tris, 6, 5, samples, rule,
                              "tiny fan on sample " + std::to_string(s) + "/" +
                                  std::to_string(samples) + " " + rule_name(rule));
        // And independently of the oracle: exactly one write in the whole target.
        Mesh m = coverage_mesh(rule);
        for (const TriFx& t : tris) test::add_tri_fx(m, t.a, t.b, t.c, {255, 255, 255, 255});
        for (const hard::Rendered& r : hard::render_all({m}, {6, 5, samples}))
          EXPECT_EQ(r.stats.samples_written, 1u) << to_string(r.isa) << " sample " << s;
      }
    }
  }
}

TEST(HardSlivers, CollinearAndRepeatedVerticesDrawNothingAndDisturbNothing) {
  // Degenerate triangles on the 1/256 grid (exactly degenerate after snapping) placed between the
  // two halves of a full-screen quad: collinear ones running through samples and across the
  // target, 10,000 px long ones, repeated vertices, all three the same, and repeated indices.
  constexpr int kW = 70, kH = 40;
  test::Rng rng(702);
  for (FillRule rule : kRules) {
    Mesh m = coverage_mesh(rule);
    m.positions = {{-5, -5, 0.5f, 1}, {80, -5, 0.5f, 1}, {80, 50, 0.5f, 1}, {-5, 50, 0.5f, 1}};
    hard::add_indexed(m, 0, 1, 2);
    std::uint32_t degenerate = 0;
    for (int i = 0; i < 200; ++i) {
      const Fx a = test::sample_fx(static_cast<int>(rng.range(0, kW - 1)),
                                   static_cast<int>(rng.range(0, kH - 1)), 0, 4);
      const Fx d{rng.range(-64, 64), rng.range(-64, 64)};
      const std::int64_t t1 = rng.range(-3000, 3000), t2 = rng.range(-3000, 3000);
      Fx b{a.x + d.x * t1, a.y + d.y * t1}, c{a.x + d.x * t2, a.y + d.y * t2};
      switch (i % 4) {
        case 1:
          b = a;
          break;  // two vertices the same
        case 2:
          b = a, c = a;
          break;  // all three the same
        default:
          break;  // three on a line
      }
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      for (const Fx& p : {a, b, c}) {
        const glm::dvec2 q = test::fx_to_px(p);
        m.positions.emplace_back(static_cast<float>(q.x), static_cast<float>(q.y), 0.5f, 1.0f);
      }
      if (i % 4 == 3)
        hard::add_indexed(m, base, base + 1, base);  // an index repeated
      else
        hard::add_indexed(m, base, base + 1, base + 2);
      ++degenerate;
    }
    hard::add_indexed(m, 0, 2, 3);
    const auto all = hard::render_all({m}, {kW, kH, 4});
    hard::expect_paths_agree(all, std::string("degenerates ") + rule_name(rule));
    const std::size_t samples = static_cast<std::size_t>(kW) * kH * 4;
    for (const hard::Rendered& r : all) {
      EXPECT_EQ(r.stats.triangles_degenerate, degenerate) << to_string(r.isa);
      EXPECT_EQ(r.stats.triangles_drawn, 2u) << to_string(r.isa);
      EXPECT_EQ(r.stats.samples_written, samples) << to_string(r.isa);
      EXPECT_EQ(hard::covered_count(r), samples) << to_string(r.isa);
    }
  }
}

// A needle from a to a + len * d (d in units), one 1/256 px step wide across `n`.
TriFx needle(Fx a, Fx d, std::int64_t len, Fx n) {
  const Fx b{a.x + d.x * len, a.y + d.y * len};
  return {a, b, {b.x + n.x, b.y + n.y}};
}

TEST(HardSlivers, NeedlesTenThousandPixelsLongAndOneStepWide) {
  // Each needle runs through a sample of the target along a direction on the sample grid (so it
  // passes exactly through many samples) or along a random direction, and extends thousands of
  // pixels beyond the target on both sides; 10,000 px is 2,560,000 units.
  constexpr int kW = 96, kH = 48;
  constexpr std::int64_t kLength = 10000 * test::kUnits;
  test::Rng rng(703);
  for (int samples : {1, 4, 16}) {
    for (FillRule rule : kRules) {
      std::vector<TriFx> tris;
      const Fx dirs[] = {{16, 0}, {0, 16}, {16, 16}, {48, 16}, {-16, 32}, {112, -32}};
      for (const Fx& d0 : dirs) {
        for (int k = 0; k < 3; ++k) {
          Fx d = d0;
          if (k == 2) d = {rng.range(-300, 300), rng.range(-300, 300)};
          if (d.x == 0 && d.y == 0) d = {1, 0};
          const std::int64_t steps = kLength / std::max(std::abs(d.x), std::abs(d.y));
          const Fx through = test::sample_fx(static_cast<int>(rng.range(0, kW - 1)),
                                             static_cast<int>(rng.range(0, kH - 1)),
                                             static_cast<int>(rng.range(0, samples - 1)), samples);
          const std::int64_t back = steps / 2;
          const Fx a{through.x - d.x * back, through.y - d.y * back};
          const Fx n = k == 0 ? Fx{0, 1} : k == 1 ? Fx{1, 0} : Fx{-1, 0};
          TriFx t = needle(a, d, steps, n);
          if (rng.coin()) std::swap(t.b, t.c);
          tris.push_back(t);
          // Its twin sharing the 10,000 px edge a -> b + n: the pair is a parallelogram one step
          // wide, split along its long diagonal.
          const Fx bn{a.x + d.x * steps + n.x, a.y + d.y * steps + n.y};
          tris.push_back({a, bn, {a.x + n.x, a.y + n.y}});
        }
      }
      expect_matches_oracle(
          tris, kW, kH, samples, rule,
          std::string("needles ") + std::to_string(samples) + "x " + rule_name(rule));
    }
  }
}

}  // namespace
}  // namespace mosaic
