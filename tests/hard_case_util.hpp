// tests/hard_case_util.hpp — helpers shared by the tests/test_hard_*.cpp files.
//
// Takes: owned meshes (reference_test_util.hpp builds them). Gives: one frame rendered on the
// reference and on every SIMD path this CPU runs (mosaic::available_isas()), the per-sample
// results of each, a bit-for-bit comparison of every path with the reference, and the
// "every sample covered exactly once" check used by the watertightness cases.
//
// Exactly once is proved with the depth test off (DepthTest::kAlways, so every covered sample is
// a colour write) and two numbers: FrameStats::samples_written counts every write of every
// triangle, and count_covered() the samples whose colour is not the clear colour. If both equal
// the number of samples in the target, no sample was missed and none was written twice.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "reference_test_util.hpp"

namespace mosaic::hard {

/// Worker threads of a fast-path render: more than one, so binning and tiles run in parallel.
inline constexpr int kFastThreads = 2;

/// What one path produced for a frame.
struct Rendered : test::Captured {
  Isa isa = Isa::kReference;
};

/// A target's clear values and sample count.
struct TargetSpec {
  int width = 1, height = 1, samples = 1;
  Rgba8 clear = test::kClear;
  float clear_depth = 1.0f;
};

/// Renders `meshes` as one frame on `isa` with `threads` workers into a fresh target that keeps
/// per-sample colour and depth.
inline Rendered render_on(const std::vector<Mesh>& meshes, const TargetSpec& spec, Isa isa,
                          int threads, bool ssaa = false) {
  RenderTarget target(spec.width, spec.height, spec.samples, TargetOptions{true, true});
  target.set_clear(spec.clear, spec.clear_depth);
  const std::vector<Draw> draws = test::draws_of(meshes);
  Frame frame;
  frame.draws = draws;
  frame.ssaa = ssaa;
  RendererOptions ro;
  ro.threads = threads;
  ro.isa = isa;
  Renderer renderer(ro);
  Rendered out;
  static_cast<test::Captured&>(out) = test::capture(renderer, frame, target);
  out.isa = isa;
  return out;
}

/// The frame on every path: the reference first (one thread), then each SIMD path.
inline std::vector<Rendered> render_all(const std::vector<Mesh>& meshes, const TargetSpec& spec,
                                        bool ssaa = false) {
  std::vector<Rendered> out;
  for (Isa isa : available_isas())
    out.push_back(render_on(meshes, spec, isa, isa == Isa::kReference ? 1 : kFastThreads, ssaa));
  return out;
}

/// Number of samples whose colour differs from `clear`.
inline std::size_t covered_count(const Rendered& r, Rgba8 clear = test::kClear) {
  std::size_t n = 0;
  for (const Rgba8& c : r.sample_color) n += c == clear ? 0 : 1;
  return n;
}

/// Samples whose colour, depth (bitwise) or pixel differ between two renders of one frame.
inline std::size_t differences(const Rendered& a, const Rendered& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.sample_color.size() && i < b.sample_color.size(); ++i) {
    n += a.sample_color[i] == b.sample_color[i] ? 0 : 1;
    n += std::memcmp(&a.sample_depth[i], &b.sample_depth[i], sizeof(float)) == 0 ? 0 : 1;
  }
  for (std::size_t i = 0; i < a.color.size() && i < b.color.size(); ++i)
    n += a.color[i] == b.color[i] ? 0 : 1;
  n += a.sample_color.size() == b.sample_color.size() ? 0 : 1;
  return n;
}

/// Every SIMD result equals the reference (all[0]) bit for bit, counters included.
inline void expect_paths_agree(const std::vector<Rendered>& all, const std::string& what) {
  ASSERT_FALSE(all.empty());
  ASSERT_EQ(all[0].isa, Isa::kReference);
  for (std::size_t i = 1; i < all.size(); ++i) {
    const std::string where = what + " on " + to_string(all[i].isa);
    EXPECT_EQ(differences(all[0], all[i]), 0u) << where;
    EXPECT_EQ(all[0].stats.samples_written, all[i].stats.samples_written) << where;
    EXPECT_EQ(all[0].stats.triangles_drawn, all[i].stats.triangles_drawn) << where;
    EXPECT_EQ(all[0].stats.triangles_nonfinite, all[i].stats.triangles_nonfinite) << where;
    EXPECT_EQ(all[0].stats.triangles_degenerate, all[i].stats.triangles_degenerate) << where;
  }
}

/// Renders on every path and checks that every sample of the target is written exactly once
/// (the meshes must be drawn with DepthTest::kAlways), and that the paths agree.
inline void expect_exactly_once(const std::vector<Mesh>& meshes, const TargetSpec& spec,
                                const std::string& what) {
  for (const Mesh& m : meshes) ASSERT_EQ(m.state.depth_test, DepthTest::kAlways) << what;
  const std::vector<Rendered> all = render_all(meshes, spec);
  const std::size_t samples = static_cast<std::size_t>(spec.width) * spec.height * spec.samples;
  for (const Rendered& r : all) {
    const std::string where = what + " on " + to_string(r.isa);
    EXPECT_EQ(covered_count(r), samples) << where << ": samples left uncovered";
    EXPECT_EQ(r.stats.samples_written, samples) << where << ": written != samples";
  }
  expect_paths_agree(all, what);
}

/// A screen-space mesh drawn with the depth test off and one colour per triangle.
inline Mesh coverage_mesh(FillRule rule, CullMode cull = CullMode::kNone) {
  DrawState s;
  s.fill_rule = rule;
  s.depth_test = DepthTest::kAlways;
  s.cull = cull;
  return test::screen_mesh(s);
}

/// A random whole number of 1/256 px steps in [lo, hi], in pixels.
inline double random_steps(test::Rng& rng, std::int64_t lo, std::int64_t hi) {
  return static_cast<double>(rng.range(lo, hi)) / test::kUnits;
}

/// Short name of a fill rule for messages.
inline const char* rule_name(FillRule r) { return r == FillRule::kD3D ? "d3d" : "gl"; }

/// Appends a triangle by indices to an indexed mesh, with a distinct colour per triangle.
inline void add_indexed(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  m.indices.insert(m.indices.end(), {a, b, c});
  m.colors.push_back(test::distinct_color(static_cast<std::uint32_t>(m.colors.size())));
}

}  // namespace mosaic::hard
