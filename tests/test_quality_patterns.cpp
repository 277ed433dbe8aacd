// test_quality_patterns.cpp — the error of each sample pattern against exact coverage, for
// straight edges crossing a pixel, and how the rendered modes compare with the ground truth.
//
// The expected figures are derived here, independently of the engine: the standard sample
// positions are restated from the D3D / Vulkan tables, and the exact area of a half-plane in a
// pixel is computed in double by clipping the square. The renderer (fast path, snapping, fill
// rule, resolve) must then reproduce those figures on random edges: it adds no error of its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "quality/exact_area.hpp"
#include "quality/quality.hpp"

namespace mosaic::quality {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Offset {
  int dx, dy;  // 1/16 px from the centre, y down
};
/// The standard positions (D3D11 / Vulkan standard sample locations), restated.
const std::vector<Offset>& pattern(int samples) {
  static const std::vector<Offset> p1{{0, 0}};
  static const std::vector<Offset> p4{{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
  static const std::vector<Offset> p8{{1, -3}, {-1, 3},  {5, 1}, {-3, -5},
                                      {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
  static const std::vector<Offset> p16{{1, 1},  {-1, -3}, {-3, 2}, {4, -1}, {-5, -2}, {2, 5},
                                       {5, 3},  {3, -5},  {-2, 6}, {0, -7}, {-4, -6}, {-6, 4},
                                       {-8, 0}, {7, -4},  {6, 7},  {-7, -8}};
  switch (samples) {
    case 1:
      return p1;
    case 4:
      return p4;
    case 8:
      return p8;
    default:
      return p16;
  }
}

/// Area of {p : n·p <= d} inside the unit square centred at the origin, by clipping the square.
double half_plane_area(double nx, double ny, double d) {
  std::vector<std::array<double, 2>> poly{{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
  std::vector<std::array<double, 2>> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& p = poly[i];
    const auto& q = poly[(i + 1) % poly.size()];
    const double fp = nx * p[0] + ny * p[1] - d, fq = nx * q[0] + ny * q[1] - d;
    if (fp <= 0) out.push_back(p);
    if ((fp < 0) != (fq < 0) && fp != fq) {
      const double t = fp / (fp - fq);
      out.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
    }
  }
  double a2 = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto& p = out[i];
    const auto& q = out[(i + 1) % out.size()];
    a2 += p[0] * q[1] - q[0] * p[1];
  }
  return std::fabs(a2) / 2;
}

struct PatternError {
  double rms = 0, max = 0;
};

/// RMS and max over all lines crossing the pixel, with the invariant measure of lines: normal
/// angle theta uniform in [0, 2 pi), distance d from the centre uniform in (-h, h), where
/// h(theta) = (|cos| + |sin|) / 2 is the square's support. Midpoint rule on a fine grid.
PatternError integrate(int samples) {
  constexpr int kAngles = 1440, kOffsets = 1000;
  const std::vector<Offset>& pat = pattern(samples);
  double sum_w = 0, sum_we2 = 0, mx = 0;
  for (int i = 0; i < kAngles; ++i) {
    const double th = 2 * kPi * (i + 0.5) / kAngles;
    const double nx = std::cos(th), ny = std::sin(th);
    const double h = (std::fabs(nx) + std::fabs(ny)) / 2;
    for (int j = 0; j < kOffsets; ++j) {
      const double d = -h + 2 * h * (j + 0.5) / kOffsets;
      int in = 0;
      for (const Offset& o : pat) in += nx * o.dx / 16.0 + ny * o.dy / 16.0 <= d;
      const double e =
          static_cast<double>(in) / static_cast<double>(pat.size()) - half_plane_area(nx, ny, d);
      const double w = h;  // the cell's share of the measure: d-width 2h / kOffsets
      sum_w += w;
      sum_we2 += w * e * e;
      mx = std::max(mx, std::fabs(e));
    }
  }
  return {std::sqrt(sum_we2 / sum_w), mx};
}

/// Errors of the renderer on random straight edges: each line is a white half-plane (a huge
/// triangle) on black in a 64×64 target; every pixel the edge crosses is one measurement,
/// coverage = white samples / samples against the exact area of the snapped triangle.
struct RenderedError {
  double ms = 0, se_ms = 0, max = 0;
  long pixels = 0;
};

RenderedError render_edges(int samples, int lines) {
  constexpr int kSize = 64;
  // Far enough that the triangle's other two edges miss the target (they pass >= 140 px from
  // the point on the edge, the target is within 91 px of it).
  constexpr float kFar = 200.0f;
  std::mt19937_64 rng(1234 + samples);
  std::uniform_real_distribution<double> pos(0, kSize), ang(0, 2 * kPi);
  Renderer renderer;
  TargetOptions opt;
  opt.keep_sample_color = true;
  RenderTarget target(kSize, kSize, samples, opt);
  target.set_clear({0, 0, 0, 255});
  double sum_c = 0, sum_sq = 0, mx = 0;
  std::vector<std::pair<double, double>> per_line;  // (pixels, sum of squared errors)
  for (int l = 0; l < lines; ++l) {
    const double px = pos(rng), py = pos(rng), a = ang(rng);
    const float dx = static_cast<float>(std::cos(a)), dy = static_cast<float>(std::sin(a));
    const float fx = static_cast<float>(px), fy = static_cast<float>(py);
    const std::vector<glm::vec4> v{{fx - kFar * dx, fy - kFar * dy, 0.5f, 1},
                                   {fx + kFar * dx, fy + kFar * dy, 0.5f, 1},
                                   {fx - kFar * dy, fy + kFar * dx, 0.5f, 1}};
    Draw draw;
    draw.space = Space::kScreen;
    draw.positions = v;
    const std::vector<Draw> draws{draw};
    renderer.render(Frame{draws}, target);
    const SnappedTriangle t = snap_triangle(v[0], v[1], v[2]);
    double line_sq = 0, line_n = 0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        if (classify(t, x, y) != PixelClass::kPartial) continue;
        int white = 0;
        for (int s = 0; s < samples; ++s)
          white +=
              target.sample_color()[(static_cast<std::size_t>(y) * kSize + x) * samples + s].r ==
              255;
        const double e = static_cast<double>(white) / samples - exact_area(t, x, y).get_d();
        line_sq += e * e;
        line_n += 1;
        mx = std::max(mx, std::fabs(e));
      }
    }
    per_line.push_back({line_n, line_sq});
    sum_c += line_n;
    sum_sq += line_sq;
  }
  RenderedError r;
  r.ms = sum_sq / sum_c;
  // Standard error of a ratio of sums over independent lines (the lines are the independent
  // draws; pixels along one line are not).
  double var = 0;
  for (const auto& [n, sq] : per_line) var += (sq - r.ms * n) * (sq - r.ms * n);
  r.se_ms = std::sqrt(var) / sum_c;
  r.max = mx;
  r.pixels = static_cast<long>(sum_c);
  return r;
}

class PatternErrorTest : public ::testing::TestWithParam<int> {};

TEST_P(PatternErrorTest, RendererReproducesThePatternsError) {
  const int samples = GetParam();
  const PatternError expected = integrate(samples);
  constexpr int kLines = 300;
  const RenderedError got = render_edges(samples, kLines);
  const double ms = expected.rms * expected.rms;
  // Four standard errors of the Monte-Carlo estimate over 300 lines, plus 2 % for the
  // integration grid and for snapping the lines to 1/256 px.
  EXPECT_NEAR(got.ms, ms, 4 * got.se_ms + 0.02 * ms)
      << samples << " samples: rendered RMS " << std::sqrt(got.ms) << " over " << got.pixels
      << " edge pixels, integrated " << expected.rms;
  // The sup over lines: the integration grid can miss it by the area swept between grid
  // lines (under 0.01 px² here), the renderer can only stay below it.
  EXPECT_LE(got.max, expected.max + 0.01) << samples;
  RecordProperty("rms_" + std::to_string(samples), std::to_string(std::sqrt(got.ms)));
  std::printf("pattern %2d: integrated RMS %.4f max %.4f | rendered RMS %.4f max %.4f (%ld px)\n",
              samples, expected.rms, expected.max, std::sqrt(got.ms), got.max, got.pixels);
}

INSTANTIATE_TEST_SUITE_P(Standard, PatternErrorTest, ::testing::Values(1, 4, 8, 16));

TEST(PatternError, MatchesTheIssuesTableAndFallsWithSamples) {
  // The figures issue 5 quotes (approximate): 1 sample 0.25 / 0.5, 4x 0.09 / 0.31,
  // 8x 0.057 / 0.23 (RMS / max). "Approximately" is taken as 20 % for RMS and 10 % for max.
  const PatternError p1 = integrate(1), p4 = integrate(4), p8 = integrate(8), p16 = integrate(16);
  EXPECT_NEAR(p1.rms, 0.25, 0.2 * 0.25);
  EXPECT_NEAR(p1.max, 0.5, 0.01);  // exactly 1/2 in theory: a half-plane missing the centre
  EXPECT_NEAR(p4.rms, 0.09, 0.2 * 0.09);
  EXPECT_NEAR(p4.max, 0.31, 0.1 * 0.31);
  EXPECT_NEAR(p8.rms, 0.057, 0.2 * 0.057);
  EXPECT_NEAR(p8.max, 0.23, 0.1 * 0.23);
  EXPECT_GT(p1.rms, p4.rms);
  EXPECT_GT(p4.rms, p8.rms);
  EXPECT_GT(p8.rms, p16.rms);
}

/// RMS error of a mode against the exact ground truth of a scene.
double mode_rms(const Scene& s, const Image& truth, int samples, bool ssaa) {
  Renderer renderer;
  RenderTarget target(s.width, s.height, samples);
  target.set_clear(s.clear_color, s.clear_depth);
  const std::vector<Draw> draws = s.draws();
  renderer.render(Frame{draws, ssaa}, target);
  return compare(truth, to_image(target.color(), s.width, s.height, {0, 0, s.width, s.height})).rms;
}

TEST(ModeError, FallsAsTheSampleCountRises) {
  for (const Scene& s :
       {builtin_scene("star", 160, 96), zone_plate_scene(160, 96), mesh_scene(160, 96)}) {
    const Image truth = exact_box_image(s, {0, 0, s.width, s.height});
    const double e1 = mode_rms(s, truth, 1, false), e4 = mode_rms(s, truth, 4, false),
                 e8 = mode_rms(s, truth, 8, false), e16 = mode_rms(s, truth, 16, false);
    EXPECT_GT(e1, e4) << s.name;
    EXPECT_GT(e4, e8) << s.name;
    EXPECT_GT(e8, e16) << s.name;
    // SSAA shades every sample; on these flat scenes coverage is all that differs, so equal.
    EXPECT_DOUBLE_EQ(mode_rms(s, truth, 4, true), e4) << s.name;
  }
}

TEST(ModeError, StarAt4xIsWithinThePatternsBound) {
  const int size = 256;
  const Scene star = builtin_scene("star", size, size);
  const Image truth = exact_box_image(star, {0, 0, size, size});
  Renderer renderer;
  RenderTarget target(size, size, 4);
  target.set_clear(star.clear_color);
  const std::vector<Draw> draws = star.draws();
  renderer.render(Frame{draws}, target);
  const Image img = to_image(target.color(), size, size, {0, 0, size, size});
  // Between r = 30 px and 90 % of the star's radius (0.45 of the side) every pixel holds at
  // most one edge, a white wedge against a black one: the colour error is the coverage error,
  // bounded by the 4x pattern's worst case, plus 0.5 / 255 for rounding the resolve to 8 bits.
  const double bound = integrate(4).max + 0.01 + 0.5 / 255;
  const double r_out = 0.9 * 0.45 * size;
  double worst = 0, sq = 0;
  long n = 0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double r = std::hypot(x + 0.5 - size / 2.0, y + 0.5 - size / 2.0);
      if (r < 30 || r > r_out) continue;
      const double e = img.at(x, y, 0) - truth.at(x, y, 0);
      if (truth.at(x, y, 0) > 0 && truth.at(x, y, 0) < 1) {
        sq += e * e;
        ++n;
      }
      worst = std::max(worst, std::fabs(e));
    }
  }
  EXPECT_LE(worst, bound);
  EXPECT_GT(n, 1000);
  // Over the star's edge pixels the RMS is the pattern's for the star's 72 edge directions,
  // not the average over all directions: allow a factor of 2 either way.
  const double rms = std::sqrt(sq / static_cast<double>(n)), pattern_rms = integrate(4).rms;
  EXPECT_LT(rms, 2 * pattern_rms);
  EXPECT_GT(rms, pattern_rms / 2);
}

}  // namespace
}  // namespace mosaic::quality
