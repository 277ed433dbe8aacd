// Camera-plane hard cases, on the reference and every SIMD path: an eye inside a closed room
// (every view ray leaves through exactly one wall, so every sample is covered exactly once while
// most walls cross w = 0 behind the eye), with near and far planes from 1e-4 to 1e6; and random
// triangles whose vertices have tiny positive w (1e-30 .. 1e-7), negative w or w = -0, checked
// sample by sample against a homogeneous oracle that never divides by w; and screen-space
// positions with w other than 1, which are window-homogeneous as types.hpp documents.
//
// What breaks them: dividing by w before clipping (a vertex behind the eye lands mirrored on
// screen: "external" triangles), clipping against w = 0 instead of the near plane, dropping or
// reordering the fan of a clipped polygon, and clipped shared edges that are interpolated from
// different ends in the two triangles (a crack along the near plane).
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "hard_case_util.hpp"

namespace mosaic {
namespace {

using hard::coverage_mesh;
using hard::expect_exactly_once;
using hard::rule_name;

constexpr FillRule kRules[] = {FillRule::kD3D, FillRule::kOpenGL};

// The inside of the box [-1, 1]^3, each wall an n x n grid of indexed triangles (random winding
// per triangle: nothing is culled here, so winding does not matter).
Mesh room(int n, FillRule rule, test::Rng& rng) {
  Mesh m = coverage_mesh(rule);
  m.space = Space::kClip;
  const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int a = 0; a < 3; ++a)
    for (int sign : {-1, 1}) {
      const glm::dvec3 normal = axes[a] * double(sign), u = axes[(a + 1) % 3],
                       v = axes[(a + 2) % 3];
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          const glm::dvec3 p = normal + u * (2.0 * i / n - 1) + v * (2.0 * j / n - 1);
          m.positions.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y),
                                   static_cast<float>(p.z), 1.0f);
        }
      const auto row = static_cast<std::uint32_t>(n + 1);
      for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j)
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
          const std::uint32_t p = base + j * row + i;
          if (rng.coin()) {
            hard::add_indexed(m, p, p + 1, p + row + 1);
            hard::add_indexed(m, p, p + row + 1, p + row);
          } else {
            hard::add_indexed(m, p, p + row, p + 1);
            hard::add_indexed(m, p + 1, p + row, p + row + 1);
          }
        }
    }
  return m;
}

TEST(HardCamera, EyeInsideAClosedRoomSeesEveryWallSampleOnce) {
  // The eye anywhere within 0.5 of the centre of a 2 x 2 x 2 room, looking in a random direction:
  // every wall point it sees is at least 0.25 in front of it along the view axis (0.5 * cos of
  // the half-diagonal field of view, 60 degrees), so near planes up to 0.05 cut nothing visible,
  // and far planes of 50 or more keep the whole room.
  constexpr int kW = 96, kH = 64;
  test::Rng rng(901);
  const std::pair<double, double> planes[] = {{1e-4, 1e6}, {0.05, 50}, {1e-4, 50}, {0.05, 1e6}};
  std::uint64_t clipped = 0;
  for (const auto& [near, far] : planes) {
    for (FillRule rule : kRules) {
      Mesh m = room(2, rule, rng);  // big wall triangles: most reach behind the eye
      const glm::dmat4 proj = glm::perspectiveRH_ZO(1.5, double(kW) / kH, near, far);
      const glm::dvec3 eye{rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)};
      const glm::dvec3 look =
          glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
      const glm::dvec3 up = std::abs(look.y) > 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
      const glm::dmat4 vp = proj * glm::lookAtRH(eye, eye + look, up);
      for (glm::vec4& p : m.positions) p = glm::vec4(vp * glm::dvec4(p));
      const std::string what =
          "near " + std::to_string(near) + " far " + std::to_string(far) + " " + rule_name(rule);
      for (int samples : {1, 4}) expect_exactly_once({m}, {kW, kH, samples}, what);
      const FrameStats s = hard::render_on({m}, {kW, kH, 1}, Isa::kReference, 1).stats;
      clipped += s.triangles_clipped;
      EXPECT_GT(s.triangles_outside, 0u) << what << ": walls lie wholly behind the eye";
    }
  }
  EXPECT_GT(clipped, 10u) << "walls cross the near plane in front of the eye";
}

// The homogeneous coverage oracle: whether the clip-space triangle shows at pixel position p, and
// whether p is too close to a decision boundary to say (then it is skipped). Nothing is divided
// by w: the point of the triangle's plane that projects to p is found by Cramer's rule
// (test::homogeneous_barycentrics); it is visible iff its barycentrics are all >= 0, its w is
// positive and 0 <= z / w <= 1.
struct OracleAnswer {
  bool covered = false;
  bool ambiguous = false;
};

OracleAnswer homogeneous_oracle(const std::array<glm::dvec4, 3>& clip, int w, int h, glm::dvec2 p) {
  // Samples closer than this to an edge line or to the near or far plane's trace are skipped:
  // snapping moves a vertex by at most sqrt(2)/512 px, so 1/32 px is far outside its reach.
  constexpr double kMarginPx = 1.0 / 32;
  OracleAnswer out;
  for (int e = 0; e < 3; ++e) {
    const glm::dvec3 a = test::window_homogeneous(clip[e], w, h);
    const glm::dvec3 b = test::window_homogeneous(clip[(e + 1) % 3], w, h);
    const glm::dvec3 line = glm::cross(a, b);  // the projected edge's line, even through w = 0
    const double norm = std::hypot(line.x, line.y);
    if (norm == 0) continue;
    if (std::abs(glm::dot(line, glm::dvec3(p, 1))) / norm < kMarginPx) out.ambiguous = true;
  }
  auto depth_at = [&](glm::dvec2 q, double& wq) {
    const auto bq = test::homogeneous_barycentrics(clip, w, h, q);
    double z = 0;
    wq = 0;
    for (int i = 0; i < 3; ++i) {
      z += bq[i] * clip[i].z;
      wq += bq[i] * clip[i].w;
    }
    return z / wq;
  };
  const auto bc = test::homogeneous_barycentrics(clip, w, h, p);
  double wp = 0, wx = 0, wy = 0;
  const double zp = depth_at(p, wp);
  // z / w is affine in screen space: its change over one pixel gives the margin in depth.
  const double gx = depth_at(p + glm::dvec2(1, 0), wx) - zp;
  const double gy = depth_at(p + glm::dvec2(0, 1), wy) - zp;
  const double depth_margin = kMarginPx * (std::abs(gx) + std::abs(gy));
  if (!std::isfinite(zp) || std::abs(zp) <= depth_margin || std::abs(zp - 1) <= depth_margin)
    out.ambiguous = true;
  out.covered = bc[0] >= 0 && bc[1] >= 0 && bc[2] >= 0 && wp > 0 && zp >= 0 && zp <= 1;
  return out;
}

TEST(HardCamera, TinyAndNegativeWMatchTheHomogeneousOracle) {
  constexpr int kW = 48, kH = 40, kSamples = 4;
  test::Rng rng(902);
  const double ws[] = {1e-30, 1e-12, 1e-7, -1e-30, -0.0, -1, -3, 0.5, 1, 2, 5};
  std::size_t checked = 0, covered_total = 0, behind = 0;
  for (int round = 0; round < 60; ++round) {
    std::array<glm::dvec4, 3> clip;
    for (glm::dvec4& v : clip) {
      const double wv = ws[rng.range(0, std::size(ws) - 1)];
      const double scale = std::max(std::abs(wv), 1.0);
      // z between -0.5 w and 1.5 w (for negative w too, where the near plane keeps nothing of
      // the vertex itself), x and y within a few times the view.
      v = {rng.uniform(-2, 2) * scale, rng.uniform(-2, 2) * scale,
           rng.uniform(-0.5, 1.5) * (wv == 0 ? 1.0 : wv), wv};
      // Store as float first, so the oracle sees exactly what the renderer gets.
      v = glm::dvec4(glm::vec4(v));
    }
    behind += (clip[0].w <= 0) + (clip[1].w <= 0) + (clip[2].w <= 0);
    for (FillRule rule : kRules) {
      Mesh m = coverage_mesh(rule);
      m.space = Space::kClip;
      for (const glm::dvec4& v : clip) m.positions.push_back(glm::vec4(v));
      m.colors.push_back({255, 255, 255, 255});
      const auto all = hard::render_all({m}, {kW, kH, kSamples});
      hard::expect_paths_agree(all, "round " + std::to_string(round));
      std::size_t wrong = 0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
          for (int s = 0; s < kSamples; ++s) {
            const OracleAnswer o =
                homogeneous_oracle(clip, kW, kH, test::sample_px(x, y, s, kSamples));
            if (o.ambiguous) continue;
            ++checked;
            covered_total += o.covered ? 1 : 0;
            const std::size_t i = (static_cast<std::size_t>(y) * kW + x) * kSamples + s;
            const bool got = !(all[0].sample_color[i] == test::kClear);
            wrong += got == o.covered ? 0 : 1;
          }
      EXPECT_EQ(wrong, 0u) << "round " << round << " " << rule_name(rule) << " w = " << clip[0].w
                           << ", " << clip[1].w << ", " << clip[2].w;
    }
  }
  // The cases are not vacuous: many samples decided, a fair share covered, vertices behind.
  EXPECT_GT(checked, 100000u);
  EXPECT_GT(covered_total, 10000u);
  EXPECT_GT(behind, 40u);
}

// Space::kScreen is window-homogeneous: (x, y, z, w) is the pixel (x / w, y / w) at depth z / w,
// and w weights the interpolation as clip space's w does. So a screen-space draw equals, bit for
// bit, the clip-space draw of the same points (clip x = x / (W / 2) - w, y = w - y / (H / 2)):
// with W, H and w powers of two and x, y on the 1/256 px grid, both give the front end the same
// doubles. Vertices with negative w are clipped at the near plane in both.
TEST(HardCamera, ScreenSpaceWIsHomogeneousLikeClipSpace) {
  constexpr int kW = 64, kH = 32, kSamples = 4;
  constexpr double kHalfW = kW / 2.0, kHalfH = kH / 2.0;
  const double ws[] = {0.25, 0.5, 1, 2, 4, 8, -1, -2};
  test::Rng rng(903);
  Mesh screen = coverage_mesh(FillRule::kD3D);
  screen.state.depth_test = DepthTest::kLess;
  screen.color_source = ColorSource::kPerVertex;
  Mesh unit = screen;  // the same triangles with w = 1: coverage and depth are the same
  int behind = 0;
  for (int t = 0; t < 40; ++t) {
    for (int k = 0; k < 3; ++k) {
      // Mostly in front; one vertex in eight behind the eye.
      const double wv = ws[rng.range(0, std::size(ws) - (t % 8 == 0 ? 1 : 3))];
      behind += wv < 0 ? 1 : 0;
      const double px = std::round(rng.uniform(-8, kW + 8) * 256) / 256;
      const double py = std::round(rng.uniform(-8, kH + 8) * 256) / 256;
      const double depth = std::round(rng.uniform(0.05, 0.95) * 1024) / 1024;
      screen.positions.emplace_back(static_cast<float>(px * wv), static_cast<float>(py * wv),
                                    static_cast<float>(depth * wv), static_cast<float>(wv));
      unit.positions.emplace_back(static_cast<float>(px), static_cast<float>(py),
                                  static_cast<float>(depth), 1.0f);
      const Rgba8 c = test::distinct_color(static_cast<std::uint32_t>(3 * t + k));
      screen.colors.push_back(c);
      unit.colors.push_back(c);
    }
  }
  Mesh clip = screen;
  clip.space = Space::kClip;
  for (glm::vec4& p : clip.positions) {
    const double x = p.x, y = p.y, wv = p.w;
    p.x = static_cast<float>(x / kHalfW - wv);
    p.y = static_cast<float>(wv - y / kHalfH);
    ASSERT_EQ((double(p.x) + wv) * kHalfW, x);  // the conversion is exact
    ASSERT_EQ((wv - double(p.y)) * kHalfH, y);
  }
  const auto got = hard::render_all({screen}, {kW, kH, kSamples});
  const auto want = hard::render_all({clip}, {kW, kH, kSamples});
  hard::expect_paths_agree(got, "screen space, w != 1");
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(hard::differences(got[i], want[i]), 0u) << to_string(got[i].isa);
    EXPECT_EQ(got[i].stats.triangles_clipped, want[i].stats.triangles_clipped);
  }
  // Not vacuous: triangles were drawn and clipped, and w changed the interpolated colours, since
  // the same points with w = 1 give other colours where the triangles are wholly in front.
  EXPECT_GT(got[0].stats.triangles_drawn, 20u);
  EXPECT_GT(got[0].stats.triangles_clipped, 0u);
  EXPECT_GT(behind, 0);
  const auto flat = hard::render_all({unit}, {kW, kH, kSamples});
  EXPECT_GT(hard::differences(got[0], flat[0]), 0u);
}

// A w that is the same on all three vertices of every triangle divides out exactly (by a power
// of two here): coverage, depth and counters equal those of w = 1.
TEST(HardCamera, ScreenSpaceUniformWDividesOut) {
  constexpr int kW = 48, kH = 40, kSamples = 4;
  test::Rng rng(904);
  Mesh unit = coverage_mesh(FillRule::kOpenGL);
  unit.state.depth_test = DepthTest::kLess;
  for (int t = 0; t < 30; ++t) {
    for (int k = 0; k < 3; ++k)
      unit.positions.emplace_back(static_cast<float>(rng.uniform(-4, kW + 4)),
                                  static_cast<float>(rng.uniform(-4, kH + 4)),
                                  static_cast<float>(rng.uniform(0, 1)), 1.0f);
    unit.colors.push_back(test::distinct_color(static_cast<std::uint32_t>(t)));
  }
  for (float wv : {0.5f, 2.0f, 64.0f}) {
    Mesh scaled = unit;
    for (glm::vec4& p : scaled.positions) p *= wv;
    const auto a = hard::render_all({unit}, {kW, kH, kSamples});
    const auto b = hard::render_all({scaled}, {kW, kH, kSamples});
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(hard::differences(a[i], b[i]), 0u) << "w = " << wv << " on " << to_string(a[i].isa);
      EXPECT_EQ(a[i].stats.samples_written, b[i].stats.samples_written);
    }
    EXPECT_GT(a[0].stats.samples_written, 1000u);
  }
}

}  // namespace
}  // namespace mosaic
