// Frame::color_load and depth_load, on the reference and every SIMD path, at 1, 4, 8 and 16
// samples (MSAA and SSAA): a frame that loads draws over the previous one, so two passes give
// the one frame of both passes' draws bit for bit (image, sample colour, sample depth and the
// hierarchical z), whatever the split; a depth-only load is the occluder pass of a second pass;
// a target never rendered loads its clear values; and a load the target cannot serve is an
// error that changes nothing.
//
// What breaks it: a tile that loads its samples in another order than it writes them, edge
// tiles that load past the image, block or tile depth bounds left at the clear depth (then
// hierarchical z rejects samples the loaded depth would pass), or a resolve skipped for a frame
// that draws no colour over loaded colour.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "reference_test_util.hpp"

namespace mosaic {
namespace {

// Odd sizes: edge tiles cut by the image on both axes.
constexpr int kW = 77, kH = 53;

struct Result {
  std::vector<Rgba8> color, sample_color;
  std::vector<float> sample_depth, hiz_min, hiz_max;
  std::uint64_t samples_written = 0;
};

// Renders `meshes` into `t` as one frame with the given loads, keeping the hierarchical z.
Result render(Renderer& r, RenderTarget& t, const std::vector<Mesh>& meshes, bool ssaa,
              LoadOp color, LoadOp depth) {
  const std::vector<Draw> draws = test::draws_of(meshes);
  Frame f;
  f.draws = draws;
  f.ssaa = ssaa;
  f.keep_hierarchical_z = true;
  f.color_load = color;
  f.depth_load = depth;
  Result out;
  out.samples_written = r.render(f, t).samples_written;
  out.color.assign(t.color().begin(), t.color().end());
  out.sample_color.assign(t.sample_color().begin(), t.sample_color().end());
  out.sample_depth.assign(t.sample_depth().begin(), t.sample_depth().end());
  out.hiz_min.assign(r.hierarchical_z().zmin().begin(), r.hierarchical_z().zmin().end());
  out.hiz_max.assign(r.hierarchical_z().zmax().begin(), r.hierarchical_z().zmax().end());
  return out;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void expect_same(const Result& a, const Result& b, const std::string& what) {
  EXPECT_TRUE(a.color == b.color) << what << ": image";
  EXPECT_TRUE(a.sample_color == b.sample_color) << what << ": sample colour";
  EXPECT_TRUE(same_bits(a.sample_depth, b.sample_depth)) << what << ": sample depth";
  EXPECT_TRUE(same_bits(a.hiz_min, b.hiz_min)) << what << ": hierarchical z (near)";
  EXPECT_TRUE(same_bits(a.hiz_max, b.hiz_max)) << what << ": hierarchical z (far)";
}

TEST(LoadOp, TwoPassesEqualOneFrameOfBothOnEveryPath) {
  test::Rng rng(5150);
  const std::vector<Mesh> draws = test::random_draws(kW, kH, 6, 40, rng);
  for (int samples : {1, 4, 8, 16})
    for (bool ssaa : {false, true}) {
      if (ssaa && samples == 1) continue;
      for (Isa isa : available_isas()) {
        const std::string what = std::string(to_string(isa)) + " " + std::to_string(samples) +
                                 (ssaa ? "x SSAA" : "x MSAA");
        Renderer r(RendererOptions{2, isa});
        RenderTarget one = test::sample_target(kW, kH, samples);
        const Result whole = render(r, one, draws, ssaa, LoadOp::kClear, LoadOp::kClear);
        EXPECT_GT(whole.samples_written, 1000u) << what;
        // Split after draw 1 and after draw 4: three passes, each loading the last.
        RenderTarget passes = test::sample_target(kW, kH, samples);
        const std::vector<Mesh> a(draws.begin(), draws.begin() + 2),
            b(draws.begin() + 2, draws.begin() + 5), c(draws.begin() + 5, draws.end());
        const Result ra = render(r, passes, a, ssaa, LoadOp::kClear, LoadOp::kClear);
        const Result rb = render(r, passes, b, ssaa, LoadOp::kLoad, LoadOp::kLoad);
        const Result rc = render(r, passes, c, ssaa, LoadOp::kLoad, LoadOp::kLoad);
        expect_same(rc, whole, what);
        EXPECT_EQ(ra.samples_written + rb.samples_written + rc.samples_written,
                  whole.samples_written)
            << what;
      }
    }
}

// Loading depth and clearing colour: the second pass draws against the first one's depth
// only, as one frame whose first draws write no colour.
TEST(LoadOp, DepthLoadedUnderAClearedColourIsAnOccluderPass) {
  test::Rng rng(5151);
  std::vector<Mesh> draws = test::random_draws(kW, kH, 4, 50, rng);
  for (Isa isa : available_isas()) {
    Renderer r(RendererOptions{2, isa});
    RenderTarget one = test::sample_target(kW, kH, 4);
    std::vector<Mesh> depth_first = draws;
    for (int d = 0; d < 2; ++d) depth_first[static_cast<std::size_t>(d)].state.color_write = false;
    const Result whole = render(r, one, depth_first, false, LoadOp::kClear, LoadOp::kClear);
    RenderTarget passes = test::sample_target(kW, kH, 4);
    render(r, passes, {draws[0], draws[1]}, false, LoadOp::kClear, LoadOp::kClear);
    const Result second =
        render(r, passes, {draws[2], draws[3]}, false, LoadOp::kClear, LoadOp::kLoad);
    expect_same(second, whole, to_string(isa));
  }
}

// Loading colour only, under a frame that draws nothing: the image is resolved again from the
// loaded samples and the depth is cleared.
TEST(LoadOp, ColourLoadedIntoAnEmptyFrameResolvesTheSameImage) {
  test::Rng rng(5152);
  const std::vector<Mesh> draws = test::random_draws(kW, kH, 2, 30, rng);
  for (Isa isa : available_isas()) {
    Renderer r(RendererOptions{2, isa});
    RenderTarget t = test::sample_target(kW, kH, 8);
    const Result first = render(r, t, draws, false, LoadOp::kClear, LoadOp::kClear);
    const Result again = render(r, t, {}, false, LoadOp::kLoad, LoadOp::kClear);
    EXPECT_TRUE(again.color == first.color) << to_string(isa);
    EXPECT_TRUE(again.sample_color == first.sample_color) << to_string(isa);
    for (float z : again.sample_depth) ASSERT_EQ(z, 1.0f) << to_string(isa);
  }
}

TEST(LoadOp, AFreshTargetLoadsItsClearValues) {
  test::Rng rng(5153);
  const std::vector<Mesh> draws = test::random_draws(kW, kH, 3, 30, rng);
  for (Isa isa : available_isas()) {
    Renderer r(RendererOptions{2, isa});
    RenderTarget cleared = test::sample_target(kW, kH, 4), loaded = test::sample_target(kW, kH, 4);
    const Result a = render(r, cleared, draws, false, LoadOp::kClear, LoadOp::kClear);
    const Result b = render(r, loaded, draws, false, LoadOp::kLoad, LoadOp::kLoad);
    expect_same(b, a, to_string(isa));
  }
}

TEST(LoadOp, ALoadTheTargetCannotServeIsAnErrorThatChangesNothing) {
  test::Rng rng(5154);
  const std::vector<Mesh> draws = test::random_draws(kW, kH, 1, 20, rng);
  std::vector<Draw> views;
  for (const Mesh& m : draws) views.push_back(m.draw());
  for (const TargetOptions options : {TargetOptions{false, true}, TargetOptions{true, false}}) {
    RenderTarget t(kW, kH, 4, options);
    Renderer r(RendererOptions{2});
    Frame f;
    f.draws = views;
    r.render(f, t);
    const std::uint64_t before = t.image_hash();
    f.draws = {};
    f.color_load = options.keep_sample_color ? LoadOp::kClear : LoadOp::kLoad;
    f.depth_load = options.keep_sample_depth ? LoadOp::kClear : LoadOp::kLoad;
    try {
      r.render(f, t);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kInvalidArgument);
      EXPECT_NE(std::string(e.what()).find(options.keep_sample_color ? "keep_sample_depth"
                                                                     : "keep_sample_color"),
                std::string::npos)
          << e.what();
    }
    EXPECT_EQ(t.image_hash(), before);
  }
}

}  // namespace
}  // namespace mosaic
