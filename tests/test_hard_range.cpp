// Range hard cases, on the reference and every SIMD path, under both fill rules: vertices exactly
// at the edge of the 16.8 fixed-point range (±kGuardBandPx = ±32768 px) and one step beyond it,
// vertices at ±1e6 and ±1e30 px in screen space and after projection (clip space with tiny w),
// the same edge line with its far vertex at 1e4, 1e6 or 1e30 px, and targets of 1×1 and 16384×16.
//
// What breaks them: edge functions or bounding boxes computed in 32 bits (at the guard band the
// products reach 2^47), a guard-band test that clips a vertex lying exactly on the limit (or keeps
// one beyond it, which the snap then saturates, bending its edges), clipping a far edge from its
// outside end (a 1e30 px end rounds the crossing to garbage), and a last tile row or column that
// is skipped when the target is not a multiple of the tile size. Under UBSan (.ci/sanitizers.sh)
// any signed overflow on these inputs also fails.
//
// 16384×16384 is not tested here: the target alone needs 2 GiB of per-sample buffers.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "front/fixed_point.hpp"
#include "hard_case_util.hpp"

namespace mosaic {
namespace {

using hard::coverage_mesh;
using hard::expect_exactly_once;
using hard::rule_name;

constexpr FillRule kRules[] = {FillRule::kD3D, FillRule::kOpenGL};

// A quad with corners (-l, -l) .. (l, l) around (cx, cy), split along a random diagonal.
Mesh square_pair(double cx, double cy, double l, FillRule rule, bool other_diagonal) {
  Mesh m = coverage_mesh(rule);
  m.positions = {{static_cast<float>(cx - l), static_cast<float>(cy - l), 0.5f, 1},
                 {static_cast<float>(cx + l), static_cast<float>(cy - l), 0.5f, 1},
                 {static_cast<float>(cx + l), static_cast<float>(cy + l), 0.5f, 1},
                 {static_cast<float>(cx - l), static_cast<float>(cy + l), 0.5f, 1}};
  if (other_diagonal) {
    hard::add_indexed(m, 0, 1, 3);
    hard::add_indexed(m, 1, 2, 3);
  } else {
    hard::add_indexed(m, 0, 1, 2);
    hard::add_indexed(m, 0, 2, 3);
  }
  return m;
}

TEST(HardRange, VerticesExactlyAtTheFixedPointLimitAreNotClipped) {
  // Corners at exactly ±32768 px: inside the guard band (the test is >=), snapped to ±2^23 units,
  // edge products of 2^47. One step of 1/256 px further they must be clipped, and the coverage
  // must not change.
  constexpr double kLimit = front::kGuardBandPx;
  for (FillRule rule : kRules) {
    for (bool diagonal : {false, true}) {
      const Mesh at = square_pair(0, 0, kLimit, rule, diagonal);
      const Mesh beyond = square_pair(0, 0, kLimit + 1.0 / 256, rule, diagonal);
      for (const auto& [w, h, samples] :
           {std::tuple{16384, 16, 1}, std::tuple{64, 64, 16}, std::tuple{1, 1, 4}}) {
        const std::string what = std::to_string(w) + "x" + std::to_string(h) + " " +
                                 std::to_string(samples) + "x " + rule_name(rule);
        expect_exactly_once({at}, {w, h, samples}, "at the limit " + what);
        expect_exactly_once({beyond}, {w, h, samples}, "beyond the limit " + what);
        for (const hard::Rendered& r : hard::render_all({at}, {w, h, samples}))
          EXPECT_EQ(r.stats.triangles_clipped, 0u) << what;
        for (const hard::Rendered& r : hard::render_all({beyond}, {w, h, samples}))
          EXPECT_EQ(r.stats.triangles_clipped, 2u) << what;
      }
    }
  }
}

// A full-screen triangulation: a ring of `n` points at distance `far` around the target centre
// (each a random 1/256 px step off the circle, so that no two edges are parallel by accident)
// and an inner ring of points inside the target, fanned and stitched.
Mesh far_ring(int w, int h, double far, int n, test::Rng& rng, FillRule rule) {
  Mesh m = coverage_mesh(rule);
  const double cx = w / 2.0 + hard::random_steps(rng, -64, 64);
  const double cy = h / 2.0 + hard::random_steps(rng, -64, 64);
  m.positions.emplace_back(static_cast<float>(cx), static_cast<float>(cy), 0.5f, 1.0f);
  for (int ring = 0; ring < 2; ++ring) {
    for (int i = 0; i < n; ++i) {
      const double a = 2 * 3.141592653589793 * (i + 0.5 * ring) / n;
      const double r = ring == 0 ? 0.3 * std::min(w, h) : far;
      m.positions.emplace_back(static_cast<float>(cx + r * std::cos(a)),
                               static_cast<float>(cy + r * std::sin(a)), 0.5f, 1.0f);
    }
  }
  const auto un = static_cast<std::uint32_t>(n);
  for (std::uint32_t i = 0; i < un; ++i) {
    const std::uint32_t in0 = 1 + i, in1 = 1 + (i + 1) % un;
    const std::uint32_t out0 = 1 + un + i, outp = 1 + un + (i + un - 1) % un;
    hard::add_indexed(m, 0, in0, in1);
    hard::add_indexed(m, in0, outp, out0);  // outer ring point i sits between inner i and i + 1
    hard::add_indexed(m, in0, out0, in1);
  }
  return m;
}

TEST(HardRange, FarVerticesAtOneMillionAndTenToTheThirtyPixels) {
  // Screen space: the outer ring at 1e4 (inside the guard band), 1e6 and 1e30 px.
  constexpr int kW = 80, kH = 72;
  test::Rng rng(801);
  for (double far : {1e4, 1e6, 1e30}) {
    for (FillRule rule : kRules) {
      for (int samples : {1, 4}) {
        expect_exactly_once({far_ring(kW, kH, far, 7, rng, rule)}, {kW, kH, samples},
                            "screen far " + std::to_string(far) + " " + rule_name(rule));
      }
    }
  }
}

TEST(HardRange, FarVerticesAfterProjection) {
  // The same triangulation given in clip space: the outer ring's w is tiny (1e-3 .. 1e-30), so its
  // points project to 1e3 .. 1e30 times farther; the inner points have w in [0.5, 2]. The front
  // end divides in double, clips at the guard band and must still close every shared edge.
  constexpr int kW = 64, kH = 56;
  test::Rng rng(802);
  for (double tiny : {1e-3, 1e-6, 1e-30}) {
    for (FillRule rule : kRules) {
      Mesh m = far_ring(kW, kH, 40.0, 9, rng, rule);
      m.space = Space::kClip;
      for (std::size_t k = 0; k < m.positions.size(); ++k) {
        glm::vec4& p = m.positions[k];
        // Inner points keep their pixel (x, y, z all scaled by w); outer points keep x and y and
        // get the tiny w, so they project 1 / tiny times farther from the NDC origin, which lies
        // within a quarter pixel of the fan centre: the triangulation stays valid.
        const bool outer = k > 9;
        const double wv = outer ? tiny : rng.uniform(0.5, 2.0);
        const double ndc_x = (p.x - kW / 2.0) / (kW / 2.0), ndc_y = (kH / 2.0 - p.y) / (kH / 2.0);
        const double s = outer ? 1.0 : wv;
        p = glm::vec4(static_cast<float>(ndc_x * s), static_cast<float>(ndc_y * s),
                      static_cast<float>(0.5 * wv), static_cast<float>(wv));
      }
      for (int samples : {1, 4}) {
        expect_exactly_once({m}, {kW, kH, samples},
                            "clip tiny w " + std::to_string(tiny) + " " + rule_name(rule));
      }
      for (const hard::Rendered& r : hard::render_all({m}, {kW, kH, 1}))
        EXPECT_GT(r.stats.triangles_clipped, 0u) << "the outer ring is beyond the guard band";
    }
  }
}

TEST(HardRange, FarVertexAtTenThousandOrAMillionPixelsCoversTheSameSamples) {
  // Triangle V0 V1 V2 with V0 on a sample in the target and V1 far below-left outside it, so that
  // inside the target only two edges matter: V0V1 and V0V2, with V2 = V0 + L d along a fixed
  // direction d. Moving V2 from L = 1e4 px to 1e6 or 1e30 px keeps the edge line V0V2; inside the
  // target only that line decides, and V0, V1 are snapped identically in every case.
  //
  // The allowance, reasoned: at L = 1e4, V2 is inside the guard band and snapped to 1/256 px, off
  // the exact line by at most sqrt(2)/512 px; at 1e6 and 1e30 the edge is clipped at the guard
  // band (|x| or |y| = 32768 px, crossing computed in double from the inside end, error ~1e-12 px)
  // and the crossing is snapped, again off the line by at most sqrt(2)/512 px. Seen from V0, an
  // endpoint moved by e at distance D turns the edge by e / D, which moves it by at most
  // e * r / D at distance r from V0. With r <= the target diagonal (< 100 px) and D >= 1e4 px,
  // each case is within 100 * sqrt(2) / 512 / 1e4 < 2.8e-5 px of the exact line, so two cases can
  // differ only at samples within 5.6e-5 px of it. Every sample farther away must agree; samples
  // on the line itself (d is chosen so that the line runs through many of them) may differ.
  //
  // Without guard-band clipping the 1e6 px vertex would saturate at the 16.8 limit (32768, 32768),
  // turning the edge by tens of degrees: thousands of samples would differ.
  constexpr int kW = 80, kH = 64, kSamples = 16;
  constexpr double kAllowancePx = 5.6e-5;
  const glm::dvec2 dirs[] = {{1, 0.3}, {0.25, 1}, {-1, 0.125}, {3, -1}};
  for (FillRule rule : kRules) {
    for (const glm::dvec2& d0 : dirs) {
      const glm::dvec2 d = d0 / glm::length(d0);
      const glm::dvec2 v0 = test::sample_px(40, 30, 5, kSamples);
      // V1: far on the other side, behind V0 and off the line, so V1V2 misses the target.
      const glm::dvec2 side{-d.y, d.x};
      const glm::dvec2 v1 = v0 - 3000.0 * d + 3000.0 * side;
      std::vector<hard::Rendered> base;
      for (double len : {1e4, 1e6, 1e30}) {
        const glm::dvec2 v2 = v0 + len * d;
        Mesh m = coverage_mesh(rule);
        test::add_tri(m, v0, v1, v2, {255, 255, 255, 255});
        const auto all = hard::render_all({m}, {kW, kH, kSamples});
        hard::expect_paths_agree(all, "far " + std::to_string(len));
        if (base.empty()) {
          base = all;
          continue;
        }
        std::size_t on_line = 0, differ = 0, covered = 0;
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x)
            for (int s = 0; s < kSamples; ++s) {
              const std::size_t i = (static_cast<std::size_t>(y) * kW + x) * kSamples + s;
              const bool a = !(base[0].sample_color[i] == test::kClear);
              const bool b = !(all[0].sample_color[i] == test::kClear);
              covered += a ? 1 : 0;
              const glm::dvec2 p = test::sample_px(x, y, s, kSamples) - v0;
              const double dist = std::abs(p.x * d.y - p.y * d.x);
              if (dist <= kAllowancePx) {
                ++on_line;
                continue;
              }
              differ += a == b ? 0 : 1;
            }
        EXPECT_EQ(differ, 0u) << "L = " << len << " d = " << d0.x << "," << d0.y << " "
                              << rule_name(rule);
        EXPECT_GT(covered, 1000u);
      }
    }
  }
}

TEST(HardRange, OneByOneTarget) {
  // Fans around random points covering the single pixel, at every sample count.
  test::Rng rng(803);
  for (int samples : {1, 4, 8, 16}) {
    for (FillRule rule : kRules) {
      for (int round = 0; round < 4; ++round) {
        Mesh m = coverage_mesh(rule);
        const glm::dvec2 c{hard::random_steps(rng, 0, 256), hard::random_steps(rng, 0, 256)};
        m.positions.emplace_back(static_cast<float>(c.x), static_cast<float>(c.y), 0.5f, 1.0f);
        const int n = static_cast<int>(rng.range(4, 9));
        for (int i = 0; i < n; ++i) {
          const double a = 2 * 3.141592653589793 * (i + rng.uniform(0, 0.5)) / n;
          m.positions.emplace_back(static_cast<float>(c.x + 9 * std::cos(a)),
                                   static_cast<float>(c.y + 9 * std::sin(a)), 0.5f, 1.0f);
        }
        for (int i = 0; i < n; ++i)
          hard::add_indexed(m, 0, static_cast<std::uint32_t>(1 + i),
                            static_cast<std::uint32_t>(1 + (i + 1) % n));
        expect_exactly_once({m}, {1, 1, samples},
                            "1x1 " + std::to_string(samples) + "x " + rule_name(rule));
      }
    }
  }
}

TEST(HardRange, SixteenThousandByRowsTarget) {
  // 16384×16, the widest target: a strip of long slanted triangles spanning its whole width (every
  // edge crosses all 256 tile columns' worth of x), so the last tile column ends at the limit.
  constexpr int kW = kMaxTargetSize, kH = 16;
  test::Rng rng(804);
  for (FillRule rule : kRules) {
    Mesh m = coverage_mesh(rule);
    const int n = 5;
    for (int i = 0; i <= n; ++i) {
      const double x = -3 + (kW + 6.0) * i / n;
      m.positions.emplace_back(static_cast<float>(x + hard::random_steps(rng, -2000, 2000)), -1.5f,
                               0.5f, 1.0f);
      m.positions.emplace_back(static_cast<float>(x + hard::random_steps(rng, -2000, 2000)), 17.5f,
                               0.5f, 1.0f);
    }
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
      hard::add_indexed(m, 2 * i, 2 * i + 1, 2 * i + 2);
      hard::add_indexed(m, 2 * i + 2, 2 * i + 1, 2 * i + 3);
    }
    // The two ends, closed by triangles reaching well past the target.
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    m.positions.emplace_back(-100.0f, -50.0f, 0.5f, 1.0f);
    m.positions.emplace_back(static_cast<float>(kW + 100), -50.0f, 0.5f, 1.0f);
    hard::add_indexed(m, base, 1, 0);
    hard::add_indexed(m, 2 * n, 2 * n + 1, base + 1);
    m.positions.emplace_back(-100.0f, 100.0f, 0.5f, 1.0f);
    hard::add_indexed(m, base, base + 2, 1);
    m.positions.emplace_back(static_cast<float>(kW + 100), 100.0f, 0.5f, 1.0f);
    hard::add_indexed(m, base + 1, 2 * n + 1, base + 3);
    for (int samples : {1, 4})
      expect_exactly_once({m}, {kW, kH, samples},
                          "16384x16 " + std::to_string(samples) + "x " + rule_name(rule));
  }
}

}  // namespace
}  // namespace mosaic
