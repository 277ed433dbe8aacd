// Hard watertightness cases, on the reference and on every SIMD path this CPU runs, under both
// fill rules: fans centred exactly on a sample position and on a pixel corner, vertices on tile
// (64 px) and block (8 px) boundaries, long shared edges crossing many tiles, closed meshes seen
// edge-on, and full-screen triangulations at random subpixel offsets. Each covers every sample
// of the target exactly once (depth test off; see hard_case_util.hpp for how that is proved),
// and every SIMD path matches the reference bit for bit.
//
// What breaks them: a fill rule whose tie-break is not consistent across a shared edge or at a
// shared vertex (a sample on the fan centre or on a tile-boundary edge is then written 0 or 2+
// times), a binner that drops a triangle from a tile its edge only touches, edge stepping that
// drifts over long edges, or a kernel that disagrees with the reference on an edge sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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
using hard::TargetSpec;

constexpr FillRule kRules[] = {FillRule::kD3D, FillRule::kOpenGL};
constexpr int kAllSampleCounts[] = {1, 4, 8, 16};

// A fan of `spokes` triangles around `centre` whose rim (random angles, radius `radius`) encloses
// the whole target; vertices are indexed, so every triangle reads the same centre and rim points.
Mesh fan(glm::dvec2 centre, int spokes, double radius, test::Rng& rng, FillRule rule,
         bool reversed) {
  Mesh m = coverage_mesh(rule);
  // Spoke i at a random angle in its own sector of 0.8 / spokes turns: with 5 or more spokes no
  // gap exceeds 1.8 / 5 turns, so the rim contains the circle of radius 0.43 * radius, which
  // holds the target in every use below.
  std::vector<double> angles;
  for (int i = 0; i < spokes; ++i)
    angles.push_back(2 * std::numbers::pi * (i + rng.uniform(0, 0.8)) / spokes);
  m.positions.emplace_back(static_cast<float>(centre.x), static_cast<float>(centre.y), 0.5f, 1.0f);
  for (double a : angles)
    m.positions.emplace_back(static_cast<float>(centre.x + radius * std::cos(a)),
                             static_cast<float>(centre.y + radius * std::sin(a)), 0.5f, 1.0f);
  for (int i = 0; i < spokes; ++i) {
    const auto a = static_cast<std::uint32_t>(1 + i);
    const auto b = static_cast<std::uint32_t>(1 + (i + 1) % spokes);
    if (reversed)
      hard::add_indexed(m, 0, b, a);
    else
      hard::add_indexed(m, 0, a, b);
  }
  return m;
}

TEST(HardWatertight, FanCentredExactlyOnASamplePosition) {
  // The centre is shared by every triangle, and a sample lies exactly on it: only a consistent
  // tie-break at a vertex (the top-left rule read as a nudge of the sample) writes it once.
  constexpr int kW = 40, kH = 36;
  test::Rng rng(601);
  for (int samples : kAllSampleCounts) {
    for (int s = 0; s < samples; ++s) {
      const glm::dvec2 c = test::sample_px(17, 22, s, samples);
      for (FillRule rule : kRules) {
        const bool reversed = rng.coin();
        const int spokes = static_cast<int>(rng.range(5, 13));
        const Mesh m = fan(c, spokes, 120.0, rng, rule, reversed);
        expect_exactly_once({m}, {kW, kH, samples},
                            std::string("fan on sample ") + std::to_string(s) + "/" +
                                std::to_string(samples) + " " + rule_name(rule));
      }
    }
  }
}

TEST(HardWatertight, FanCentredExactlyOnAPixelCorner) {
  // Pixel corners are tile and block corners too when they are multiples of 64 and 8; at 16x the
  // sample (-8, 0) of every pixel lies on its left border, so spokes along x run through samples.
  constexpr int kW = 136, kH = 72;
  test::Rng rng(602);
  for (glm::dvec2 c : {glm::dvec2{17, 22}, glm::dvec2{64, 64}, glm::dvec2{8, 16}}) {
    for (int samples : kAllSampleCounts) {
      for (FillRule rule : kRules) {
        Mesh m = fan(c, static_cast<int>(rng.range(6, 12)), 400.0, rng, rule, rng.coin());
        // Axis-aligned spokes as well: the rim gets points straight right of and below the
        // centre, so two spokes run along a pixel row border and a pixel column border.
        const std::uint32_t right = static_cast<std::uint32_t>(m.positions.size());
        m.positions.emplace_back(static_cast<float>(c.x + 400), static_cast<float>(c.y), 0.5f, 1);
        m.positions.emplace_back(static_cast<float>(c.x), static_cast<float>(c.y + 400), 0.5f, 1);
        m.positions.emplace_back(static_cast<float>(c.x - 400), static_cast<float>(c.y + 400), 0.5f,
                                 1);
        m.positions.emplace_back(static_cast<float>(c.x - 400), static_cast<float>(c.y - 400), 0.5f,
                                 1);
        m.positions.emplace_back(static_cast<float>(c.x + 400), static_cast<float>(c.y - 400), 0.5f,
                                 1);
        Mesh axis = coverage_mesh(rule);
        axis.positions = m.positions;
        for (std::uint32_t k = 0; k < 5; ++k)
          hard::add_indexed(axis, 0, right + k, right + (k + 1) % 5);
        expect_exactly_once({axis}, {kW, kH, samples},
                            std::string("axis fan at corner ") + std::to_string(c.x) + "," +
                                std::to_string(c.y) + " " + rule_name(rule));
        expect_exactly_once({m}, {kW, kH, samples},
                            std::string("fan at corner ") + std::to_string(c.x) + "," +
                                std::to_string(c.y) + " " + std::to_string(samples) + "x " +
                                rule_name(rule));
      }
    }
  }
}

// An indexed grid with the given column and row coordinates and a random diagonal per cell.
Mesh grid(const std::vector<double>& xs, const std::vector<double>& ys, test::Rng& rng,
          FillRule rule, glm::dvec2 offset = {0, 0}) {
  Mesh m = coverage_mesh(rule);
  for (double y : ys)
    for (double x : xs)
      m.positions.emplace_back(static_cast<float>(x + offset.x), static_cast<float>(y + offset.y),
                               0.5f, 1.0f);
  const auto cols = static_cast<std::uint32_t>(xs.size());
  for (std::uint32_t j = 0; j + 1 < ys.size(); ++j) {
    for (std::uint32_t i = 0; i + 1 < cols; ++i) {
      const std::uint32_t a = j * cols + i, b = a + 1, c = a + cols + 1, d = a + cols;
      auto tri = [&](std::uint32_t p, std::uint32_t q, std::uint32_t r) {
        if (rng.coin())
          hard::add_indexed(m, p, q, r);
        else
          hard::add_indexed(m, p, r, q);
      };
      if (rng.coin()) {
        tri(a, b, c);
        tri(a, c, d);
      } else {
        tri(a, b, d);
        tri(b, c, d);
      }
    }
  }
  return m;
}

TEST(HardWatertight, VerticesOnTileAndBlockBoundaries) {
  // Columns and rows exactly on 8 px block and 64 px tile borders, and one 1/256 px step either
  // side of a tile border (thin rows of triangles between them), over a target that tiles do not
  // divide. Edges lying on a tile border belong to triangles binned to both tiles.
  constexpr double kStep = 1.0 / 256;
  const std::vector<double> xs{-3, 8, 56, 64 - kStep, 64, 64 + kStep, 72, 120, 128, 136, 184, 195};
  const std::vector<double> ys{-2, 8, 16, 63, 64 - kStep, 64, 64 + kStep, 72, 128, 139};
  constexpr int kW = 190, kH = 136;
  test::Rng rng(603);
  for (int samples : kAllSampleCounts) {
    for (FillRule rule : kRules) {
      expect_exactly_once(
          {grid(xs, ys, rng, rule)}, {kW, kH, samples},
          std::string("tile borders ") + std::to_string(samples) + "x " + rule_name(rule));
    }
  }
}

TEST(HardWatertight, LongSharedEdgesCrossingManyTiles) {
  // Zig-zag strips of tall (or wide) thin triangles spanning the whole target: every shared
  // edge is a slanted line across 4 to 5 tiles, at random 1/256 px positions.
  constexpr int kW = 320, kH = 256;
  test::Rng rng(604);
  for (FillRule rule : kRules) {
    for (bool vertical : {true, false}) {
      Mesh m = coverage_mesh(rule);
      const double along = vertical ? kH : kW, across = vertical ? kW : kH;
      const int strips = 9;
      const double width = (across + 20) / strips;
      for (int i = 0; i <= strips + 1; ++i) {
        for (int end = 0; end < 2; ++end) {
          const double a = -10 + width * (i + 0.5 * end) + hard::random_steps(rng, -256, 256);
          const double b = end == 0 ? -1.5 - hard::random_steps(rng, 0, 256)
                                    : along + 1.5 + hard::random_steps(rng, 0, 256);
          m.positions.emplace_back(static_cast<float>(vertical ? a : b),
                                   static_cast<float>(vertical ? b : a), 0.5f, 1.0f);
        }
      }
      for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(strips) + 1; ++i) {
        const std::uint32_t top0 = 2 * i, bot0 = 2 * i + 1, top1 = 2 * i + 2, bot1 = 2 * i + 3;
        hard::add_indexed(m, top0, bot0, top1);
        hard::add_indexed(m, top1, bot0, bot1);
      }
      // Left and right ends: close the strip against far points so it covers the target.
      const auto n = static_cast<std::uint32_t>(m.positions.size());
      const float far = 1000.0f;
      if (vertical) {
        m.positions.emplace_back(-far, -far, 0.5f, 1.0f);
        m.positions.emplace_back(-far, far, 0.5f, 1.0f);
        m.positions.emplace_back(far, -far, 0.5f, 1.0f);
        m.positions.emplace_back(far, far, 0.5f, 1.0f);
      } else {
        m.positions.emplace_back(-far, -far, 0.5f, 1.0f);
        m.positions.emplace_back(far, -far, 0.5f, 1.0f);
        m.positions.emplace_back(-far, far, 0.5f, 1.0f);
        m.positions.emplace_back(far, far, 0.5f, 1.0f);
      }
      // The first and last columns of the strip meet the far quads along their own edges.
      hard::add_indexed(m, n, n + 1, 0);
      hard::add_indexed(m, 0, n + 1, 1);
      hard::add_indexed(m, n + 2, n - 2, n + 3);
      hard::add_indexed(m, n - 2, n - 1, n + 3);
      // The top and bottom of the target: far triangles above and below the strip's ends.
      std::vector<std::uint32_t> tops, bottoms;
      for (std::uint32_t k = 0; k < n; k += 2) tops.push_back(k);
      for (std::uint32_t k = 1; k < n; k += 2) bottoms.push_back(k);
      for (std::size_t k = 0; k + 1 < tops.size(); ++k)
        hard::add_indexed(m, n, tops[k], tops[k + 1]);
      hard::add_indexed(m, n, tops.back(), n + 2);
      for (std::size_t k = 0; k + 1 < bottoms.size(); ++k)
        hard::add_indexed(m, n + 1, bottoms[k], bottoms[k + 1]);
      hard::add_indexed(m, n + 1, bottoms.back(), n + 3);
      for (int samples : {1, 4}) {
        expect_exactly_once({m}, {kW, kH, samples},
                            std::string(vertical ? "vertical" : "horizontal") + " strip " +
                                std::to_string(samples) + "x " + rule_name(rule));
      }
    }
  }
}

TEST(HardWatertight, FullScreenTriangulationsAtRandomSubpixelOffsets) {
  // A jittered grid (a third of the vertices anywhere on the 1/256 grid, a third on the 1/16 grid
  // where samples lie, a third on pixel centres), the whole of it moved by a random subpixel
  // offset, at every sample count.
  constexpr int kW = 72, kH = 56;
  constexpr int kCols = 10, kRows = 8;
  test::Rng rng(605);
  for (int round = 0; round < 3; ++round) {
    for (int samples : kAllSampleCounts) {
      for (FillRule rule : kRules) {
        std::vector<double> xs, ys;
        for (int i = 0; i < kCols; ++i) xs.push_back(i == 0 ? -2.0 : i * (kW + 4.0) / (kCols - 1));
        for (int j = 0; j < kRows; ++j) ys.push_back(j == 0 ? -2.0 : j * (kH + 4.0) / (kRows - 1));
        const glm::dvec2 offset{hard::random_steps(rng, 0, 255), hard::random_steps(rng, 0, 255)};
        Mesh m = grid(xs, ys, rng, rule, offset);
        for (std::size_t k = 0; k < m.positions.size(); ++k) {
          const std::size_t i = k % kCols, j = k / kCols;
          if (i == 0 || j == 0 || i == kCols - 1 || j == kRows - 1) continue;  // keep the rim out
          for (int axis = 0; axis < 2; ++axis) {
            const std::int64_t step = rng.range(0, 2) == 0 ? 1 : rng.coin() ? 16 : 128;
            m.positions[k][axis] +=
                static_cast<float>(rng.range(-512 / step, 512 / step) * step) / 256.0f;
          }
        }
        expect_exactly_once({m}, {kW, kH, samples},
                            "jittered grid round " + std::to_string(round) + " " +
                                std::to_string(samples) + "x " + rule_name(rule));
      }
    }
  }
}

// --- Closed meshes seen edge-on ---------------------------------------------------------------

// A unit cube [-1, 1]^3 with each face an n x n grid, outward winding, indexed.
Mesh cube(int n, FillRule rule, CullMode cull) {
  Mesh m = coverage_mesh(rule, cull);
  m.space = Space::kClip;  // positions are replaced by transformed ones below
  const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int a = 0; a < 3; ++a) {
    for (int sign : {-1, 1}) {
      const glm::dvec3 normal = axes[a] * double(sign);
      const glm::dvec3 u = axes[(a + 1) % 3] * double(sign), v = axes[(a + 2) % 3];
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
          hard::add_indexed(m, p, p + 1, p + row + 1);
          hard::add_indexed(m, p, p + row + 1, p + row);
        }
    }
  }
  return m;
}

// A UV sphere of radius 1 with `seg` segments and `rings` rings, outward winding, indexed.
Mesh sphere(int seg, int rings, FillRule rule, CullMode cull) {
  Mesh m = coverage_mesh(rule, cull);
  m.space = Space::kClip;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < seg; ++s) {
      const double th = std::numbers::pi * r / rings, ph = 2 * std::numbers::pi * s / seg;
      m.positions.emplace_back(static_cast<float>(std::sin(th) * std::cos(ph)),
                               static_cast<float>(std::cos(th)),
                               static_cast<float>(std::sin(th) * std::sin(ph)), 1.0f);
    }
  auto id = [&](int r, int s) { return static_cast<std::uint32_t>(r * seg + (s % seg)); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < seg; ++s) {
      // The pole rows hold seg copies of the pole: their triangles with two copies are
      // degenerate, and the others meet at the pole in a fan.
      hard::add_indexed(m, id(r, s), id(r + 1, s), id(r + 1, s + 1));
      hard::add_indexed(m, id(r, s), id(r + 1, s + 1), id(r, s + 1));
    }
  return m;
}

// Applies a clip-space transform to every position (in double, rounded to float once).
void transform(Mesh& m, const glm::dmat4& t) {
  for (glm::vec4& p : m.positions) p = glm::vec4(t * glm::dvec4(p));
}

// Samples covered by at least one triangle, and the total number of writes.
struct Coverage {
  std::vector<bool> covered;
  std::uint64_t written = 0;
};
Coverage coverage_of(const hard::Rendered& r) {
  Coverage c;
  for (const Rgba8& s : r.sample_color) c.covered.push_back(!(s == test::kClear));
  c.written = r.stats.samples_written;
  return c;
}

// Front and back faces of a closed mesh, each drawn alone on every path. For any closed mesh
// the projection has degree zero: at every sample as many front faces cover it as back faces,
// whatever snapping did to slivers on the silhouette. So both passes must write the same total
// and cover the same samples; a crack or an overlap in one of the two sides breaks that.
// `convex_once` adds that each side covers each of its samples exactly once (no side folds).
void expect_closed_mesh_balanced(const Mesh& front_only, const Mesh& back_only, int w, int h,
                                 int samples, bool convex_once, const std::string& what) {
  const auto fronts = hard::render_all({front_only}, {w, h, samples});
  const auto backs = hard::render_all({back_only}, {w, h, samples});
  hard::expect_paths_agree(fronts, what + " fronts");
  hard::expect_paths_agree(backs, what + " backs");
  const Coverage f = coverage_of(fronts[0]), b = coverage_of(backs[0]);
  EXPECT_EQ(f.written, b.written) << what;
  EXPECT_TRUE(f.covered == b.covered) << what << ": front and back cover different samples";
  const std::size_t n =
      static_cast<std::size_t>(std::count(f.covered.begin(), f.covered.end(), true));
  EXPECT_GT(n, 0u) << what;
  if (convex_once) {
    EXPECT_EQ(f.written, n) << what << ": a front sample written twice";
    EXPECT_EQ(b.written, n) << what << ": a back sample written twice";
  }
}

TEST(HardWatertight, CubeSeenExactlyEdgeOnAndNearlyEdgeOn) {
  // Orthographic view straight along z: the four side faces project to zero-area lines (setup
  // must drop them as degenerate), the front face alone covers the square. Then tilted by 1e-3
  // and 1e-5 rad, where the sides become strips 0.04 and 0.0004 px wide, and moved by a random
  // subpixel offset.
  constexpr int kW = 80, kH = 64;
  test::Rng rng(606);
  for (double tilt : {0.0, 1e-3, 1e-5}) {
    for (FillRule rule : kRules) {
      for (int samples : {1, 4, 16}) {
        Mesh fronts = cube(3, rule, CullMode::kBack), backs = cube(3, rule, CullMode::kFront);
        const glm::dvec2 off{hard::random_steps(rng, 0, 255), hard::random_steps(rng, 0, 255)};
        // Pixels: x = 40 + 25 * X + off; clip x = x / 40 - 1. Depth z in [0.25, 0.75].
        glm::dmat4 t(1.0);
        t = glm::translate(t, glm::dvec3((off.x) / (kW / 2.0), -(off.y) / (kH / 2.0), 0.5));
        t = glm::scale(t, glm::dvec3(25.0 / (kW / 2.0), 25.0 / (kH / 2.0), 0.25));
        t = glm::rotate(t, tilt, glm::dvec3(1, 0, 0));
        t = glm::rotate(t, tilt * 0.7, glm::dvec3(0, 1, 0));
        transform(fronts, t);
        transform(backs, t);
        // At 1e-5 rad the sides snap to zero or one 1/256 px step wide, and a one-step sliver may
        // fold over the front face: only the balance is required there.
        expect_closed_mesh_balanced(fronts, backs, kW, kH, samples, tilt > 1e-4,
                                    "cube tilt " + std::to_string(tilt) + " " +
                                        std::to_string(samples) + "x " + rule_name(rule));
      }
    }
  }
}

TEST(HardWatertight, SphereInPerspectiveFrontAndBackBalance) {
  // A UV sphere (fans at both poles, slivers along the silhouette) under a perspective camera,
  // at random orientations, including one that looks straight down the pole axis.
  constexpr int kW = 96, kH = 80;
  test::Rng rng(607);
  for (int round = 0; round < 4; ++round) {
    for (FillRule rule : kRules) {
      Mesh fronts = sphere(24, 12, rule, CullMode::kBack);
      Mesh backs = sphere(24, 12, rule, CullMode::kFront);
      const glm::dmat4 proj = glm::perspectiveRH_ZO(0.9, double(kW) / kH, 0.5, 20.0);
      glm::dmat4 view = glm::translate(
          glm::dmat4(1.0), glm::dvec3(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), -3.0));
      if (round == 0) {
        view = glm::rotate(view, std::numbers::pi / 2, glm::dvec3(1, 0, 0));  // pole on the axis
      } else {
        view = glm::rotate(
            view, rng.uniform(0, 6.3),
            glm::normalize(glm::dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))));
      }
      transform(fronts, proj * view);
      transform(backs, proj * view);
      expect_closed_mesh_balanced(fronts, backs, kW, kH, 4, false,
                                  "sphere round " + std::to_string(round) + " " + rule_name(rule));
    }
  }
}

}  // namespace
}  // namespace mosaic
