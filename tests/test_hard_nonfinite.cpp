// Non-finite input, on the reference and every SIMD path: NaN, +Inf or -Inf in any one coordinate
// (x, y, z or w) of any vertex, in screen and clip space, indexed and not, and in positions_xyz
// through a transform. As draw.hpp documents, such a triangle is culled and counted in
// FrameStats::triangles_nonfinite, and it never affects another triangle: a watertight
// triangulation drawn with bad triangles interleaved gives the very image it gives alone.
// Colours are 8-bit integers in the API and cannot be non-finite; in a .tris file a colour of
// "nan" or "inf" is a parse error (test_hard_bad_input.cpp).
//
// What breaks it: a NaN that reaches min/max in binning or bounding boxes (NaN compares false, so
// a box can become "everything" or a tile index garbage), a snap of NaN (undefined conversion to
// int), a NaN vertex shared through an index with good triangles, or a per-chunk counter that a
// culled triangle skips.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "hard_case_util.hpp"

namespace mosaic {
namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kBadValues[] = {kNan, kInf, -kInf};

// A full-screen grid of 2 * (n x n) triangles over a w x h target, as unindexed vertices (each
// triangle its own three), depth off, in screen space.
Mesh grid_soup(int w, int h, int n, test::Rng& rng) {
  Mesh m = hard::coverage_mesh(FillRule::kD3D);
  auto at = [&](int i, int j) {
    return glm::dvec2(-1.0 + (w + 2.0) * i / n, -1.0 + (h + 2.0) * j / n);
  };
  std::uint32_t id = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec2 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (rng.coin()) {
        test::add_tri(m, a, b, c, test::distinct_color(id++));
        test::add_tri(m, a, c, d, test::distinct_color(id++));
      } else {
        test::add_tri(m, a, b, d, test::distinct_color(id++));
        test::add_tri(m, b, c, d, test::distinct_color(id++));
      }
    }
  return m;
}

// Converts a screen-space mesh to clip space for a w x h target, with a random w per vertex.
void to_clip(Mesh& m, int w, int h, test::Rng& rng) {
  m.space = Space::kClip;
  for (glm::vec4& p : m.positions) {
    const double wv = rng.uniform(0.5, 3);
    const double x = p.x, y = p.y;
    p = glm::vec4(static_cast<float>((x / w * 2 - 1) * wv),
                  static_cast<float>((1 - y / h * 2) * wv), static_cast<float>(p.z * wv),
                  static_cast<float>(wv));
  }
}

TEST(HardNonFinite, AnyBadCoordinateCullsOnlyItsTriangle) {
  constexpr int kW = 56, kH = 40, kSamples = 4;
  test::Rng rng(1101);
  for (Space space : {Space::kScreen, Space::kClip}) {
    Mesh good = grid_soup(kW, kH, 4, rng);
    if (space == Space::kClip) to_clip(good, kW, kH, rng);
    const auto expected = hard::render_all({good}, {kW, kH, kSamples});
    // Every bad value in every coordinate of every vertex slot: a copy of a good triangle with
    // that one value replaced, inserted at a random place among the good ones.
    Mesh mixed = good;
    std::uint64_t bad = 0;
    for (float value : kBadValues)
      for (int vertex = 0; vertex < 3; ++vertex)
        for (int coord = 0; coord < 4; ++coord) {
          const auto tris = mixed.positions.size() / 3;
          const std::size_t src = static_cast<std::size_t>(rng.range(0, 2 * 16 - 1)) * 3;
          const std::size_t at =
              static_cast<std::size_t>(rng.range(0, static_cast<std::int64_t>(tris))) * 3;
          std::array<glm::vec4, 3> t{good.positions[src], good.positions[src + 1],
                                     good.positions[src + 2]};
          t[static_cast<std::size_t>(vertex)][coord] = value;
          mixed.positions.insert(mixed.positions.begin() + static_cast<std::ptrdiff_t>(at),
                                 t.begin(), t.end());
          mixed.colors.insert(mixed.colors.begin() + static_cast<std::ptrdiff_t>(at / 3),
                              Rgba8{255, 0, 255, 255});
          ++bad;
        }
    const auto got = hard::render_all({mixed}, {kW, kH, kSamples});
    for (std::size_t i = 0; i < got.size(); ++i) {
      const std::string where =
          std::string(space == Space::kClip ? "clip" : "screen") + " on " + to_string(got[i].isa);
      EXPECT_EQ(got[i].stats.triangles_nonfinite, bad) << where;
      EXPECT_EQ(got[i].stats.triangles_in, good.positions.size() / 3 + bad) << where;
      EXPECT_EQ(got[i].stats.samples_written, expected[i].stats.samples_written) << where;
      EXPECT_EQ(hard::differences(got[i], expected[i]), 0u) << where;
    }
    hard::expect_paths_agree(got, "non-finite mixed");
  }
}

TEST(HardNonFinite, BadSharedVertexCullsExactlyTheTrianglesThatUseIt) {
  // Indexed: one vertex of an indexed grid made NaN (or Inf). The triangles using it are culled,
  // the others still draw exactly the samples they draw with the vertex intact.
  constexpr int kW = 48, kH = 48, kSamples = 4;
  test::Rng rng(1102);
  for (float value : kBadValues) {
    for (int coord = 0; coord < 4; ++coord) {
      Mesh m = hard::coverage_mesh(FillRule::kOpenGL);
      const int n = 5;
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
          m.positions.emplace_back(static_cast<float>(-1.0 + 50.0 * i / n),
                                   static_cast<float>(-1.0 + 50.0 * j / n), 0.5f, 1.0f);
      for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j)
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
          const std::uint32_t p = j * (n + 1) + i;
          hard::add_indexed(m, p, p + 1, p + n + 2);
          hard::add_indexed(m, p, p + n + 2, p + n + 1);
        }
      const std::uint32_t victim = static_cast<std::uint32_t>(rng.range(0, (n + 1) * (n + 1) - 1));
      // Reference image: the same mesh without the triangles that use the victim.
      Mesh without = m;
      without.indices.clear();
      without.colors.clear();
      std::uint64_t users = 0;
      for (std::size_t t = 0; t < m.indices.size() / 3; ++t) {
        const std::uint32_t* tri = &m.indices[3 * t];
        if (tri[0] == victim || tri[1] == victim || tri[2] == victim) {
          ++users;
          continue;
        }
        without.indices.insert(without.indices.end(), tri, tri + 3);
        without.colors.push_back(m.colors[t]);
      }
      m.positions[victim][coord] = value;
      const auto expected = hard::render_all({without}, {kW, kH, kSamples});
      const auto got = hard::render_all({m}, {kW, kH, kSamples});
      for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].stats.triangles_nonfinite, users) << to_string(got[i].isa);
        EXPECT_EQ(hard::differences(got[i], expected[i]), 0u)
            << to_string(got[i].isa) << " vertex " << victim << " coord " << coord;
      }
      EXPECT_GT(users, 0u);
    }
  }
}

TEST(HardNonFinite, TransformedPositionsOnEveryPath) {
  // positions_xyz through a transform: a NaN or Inf position culls its triangles only.
  constexpr int kW = 32, kH = 32;
  for (float value : kBadValues) {
    Mesh good;
    good.space = Space::kClip;
    good.state.depth_test = DepthTest::kAlways;
    good.color_source = ColorSource::kPerTriangle;
    std::vector<glm::vec3> xyz;
    for (int k = 0; k < 12; ++k) {
      const float x = -0.9f + 0.15f * static_cast<float>(k);
      xyz.insert(xyz.end(), {{x, -0.9f, 0.5f}, {x + 0.14f, -0.9f, 0.5f}, {x, 0.9f, 0.5f}});
      good.colors.push_back(test::distinct_color(static_cast<std::uint32_t>(k)));
    }
    std::vector<glm::vec3> bad = xyz;
    bad[4].y = value;   // triangle 1
    bad[30].z = value;  // triangle 10
    auto render = [&](const std::vector<glm::vec3>& pos, const std::vector<Rgba8>& colors) {
      std::vector<hard::Rendered> out;
      for (Isa isa : available_isas()) {
        Draw d;
        d.positions_xyz = pos;
        d.color_source = ColorSource::kPerTriangle;
        d.colors = colors;
        d.state = good.state;
        RenderTarget t(kW, kH, 4, TargetOptions{true, true});
        const Frame f{std::span<const Draw>(&d, 1)};
        Renderer r(RendererOptions{2, isa});
        hard::Rendered res;
        res.isa = isa;
        res.stats = r.render(f, t);
        res.color.assign(t.color().begin(), t.color().end());
        res.sample_color.assign(t.sample_color().begin(), t.sample_color().end());
        res.sample_depth.assign(t.sample_depth().begin(), t.sample_depth().end());
        out.push_back(res);
      }
      return out;
    };
    // The expectation: the same draw with triangles 1 and 10 moved out of view (x = 5: culled).
    std::vector<glm::vec3> moved = xyz;
    for (int v : {3, 4, 5, 30, 31, 32}) moved[static_cast<std::size_t>(v)].x = 5.0f;
    const auto expected = render(moved, good.colors);
    const auto got = render(bad, good.colors);
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].stats.triangles_nonfinite, 2u) << to_string(got[i].isa);
      EXPECT_EQ(hard::differences(got[i], expected[i]), 0u) << to_string(got[i].isa);
      EXPECT_EQ(got[i].stats.samples_written, expected[i].stats.samples_written);
    }
  }
}

}  // namespace
}  // namespace mosaic
