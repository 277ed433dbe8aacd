// The resolve: a box filter, the per-channel mean of a pixel's samples rounded to nearest with a
// tie going up. Checked on hand-made sample buffers and on samples produced by rendering
// rectangles whose edges cut the standard 4x and 16x patterns at known places.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "reference_test_util.hpp"
#include "resolve/resolve.hpp"

namespace mosaic {
namespace {

TEST(Resolve, BoxMeanOfHandMadeSamples) {
  const Rgba8 w{255, 1, 2, 255}, k{0, 0, 0, 255};
  // 4 samples, two white-ish two black: r 510/4 = 127.5 -> 128 (tie up); g 2/4 = 0.5 -> 1;
  // b 4/4 = 1; a 255.
  // Three of four: r 765/4 = 191.25 -> 191; g 0.75 -> 1; b 6/4 = 1.5 -> 2.
  // One of four: r 63.75 -> 64; g 0.25 -> 0; b 0.5 -> 1.
  const std::vector<Rgba8> in{w, w, k, k, w, k, w, w, k, k, w, k};
  std::vector<Rgba8> out(3);
  resolve::box_resolve(in, 4, out);
  EXPECT_EQ(out[0], (Rgba8{128, 1, 1, 255}));
  EXPECT_EQ(out[1], (Rgba8{191, 1, 2, 255}));
  EXPECT_EQ(out[2], (Rgba8{64, 0, 1, 255}));
  // 1 sample: the identity.
  std::vector<Rgba8> one(12);
  resolve::box_resolve(in, 1, one);
  EXPECT_EQ(one, in);
}

TEST(Resolve, RandomSamplesAgainstTheRoundedMean) {
  test::Rng rng(61);
  for (int n : {1, 4, 8, 16}) {
    std::vector<Rgba8> in(static_cast<std::size_t>(n) * 500);
    for (Rgba8& c : in) {
      // Values near 0 and 255 and anything between, so that sums of all sizes occur.
      auto v = [&] {
        return static_cast<std::uint8_t>(
            rng.range(0, 3) == 0 ? rng.range(0, 2) * 127 + rng.range(0, 1) : rng.range(0, 255));
      };
      c = {v(), v(), v(), v()};
    }
    std::vector<Rgba8> out(500);
    resolve::box_resolve(in, n, out);
    for (std::size_t p = 0; p < out.size(); ++p) {
      double sum[4] = {0, 0, 0, 0};
      for (int s = 0; s < n; ++s) {
        const Rgba8 c = in[p * n + s];
        sum[0] += c.r, sum[1] += c.g, sum[2] += c.b, sum[3] += c.a;
      }
      const std::uint8_t got[4] = {out[p].r, out[p].g, out[p].b, out[p].a};
      for (int ch = 0; ch < 4; ++ch)
        ASSERT_EQ(got[ch], std::floor(sum[ch] / n + 0.5)) << "n " << n << " pixel " << p;
    }
  }
}

// Renders a white rectangle from x = `left` to 30 (rows 2..14) over black, and returns the target.
RenderTarget white_rect(double left, int samples, Rgba8 colour = {255, 255, 255, 255}) {
  RenderTarget t(32, 16, samples, TargetOptions{false, true});
  t.set_clear({0, 0, 0, 255});
  Mesh m = test::screen_mesh();
  test::add_tri(m, {left, 2}, {30, 2}, {30, 14}, colour);
  test::add_tri(m, {left, 2}, {30, 14}, {left, 14}, colour);
  test::render_reference(m, t);
  return t;
}

TEST(Resolve, HalfCoveredFourSamplePixelsThroughRendering) {
  // 4x offsets in x (1/16 px): s0 -2, s1 +6, s2 -6, s3 +2, i.e. samples of column 10 at
  // x = 10.375, 10.875, 10.125, 10.625.
  //   left = 10.5:  s1, s3 covered -> 2 of 4 -> 510/4 = 127.5 -> 128
  //   left = 10.25: s0, s1, s3     -> 3 of 4 -> 191.25 -> 191
  //   left = 10.75: s1             -> 1 of 4 -> 63.75 -> 64
  struct Case {
    double left;
    std::uint8_t expect;
  };
  for (const Case& c : {Case{10.5, 128}, Case{10.25, 191}, Case{10.75, 64}}) {
    const RenderTarget t = white_rect(c.left, 4);
    for (int y = 2; y < 14; ++y) {
      EXPECT_EQ(t.pixel(10, y), (Rgba8{c.expect, c.expect, c.expect, 255})) << c.left << " " << y;
      EXPECT_EQ(t.pixel(9, y), (Rgba8{0, 0, 0, 255}));
      EXPECT_EQ(t.pixel(11, y), (Rgba8{255, 255, 255, 255}));
    }
  }
  // Channels 1 and 2 exercise ties at the bottom of the range: 2 of 4 samples of (255, 1, 2)
  // give (127.5, 0.5, 1) -> (128, 1, 1).
  const RenderTarget t = white_rect(10.5, 4, {255, 1, 2, 255});
  EXPECT_EQ(t.pixel(10, 5), (Rgba8{128, 1, 1, 255}));
}

TEST(Resolve, SixteenSampleCoverageFractions) {
  // For a left edge at x = 10 + 0.5 + e/16 - 1/32 the covered samples of column 10 are those with
  // dx > e - 1/2, counted from the standard 16x table; the pixel is round(255 * k / 16).
  const int dx16[16] = {1, -1, -3, 4, -5, 2, 5, 3, -2, 0, -4, -6, -8, 7, 6, -7};
  for (int e = -7; e <= 8; ++e) {
    int k = 0;
    for (int d : dx16) k += d >= e;
    const double left = 10.5 + e / 16.0 - 1.0 / 32;
    const RenderTarget t = white_rect(left, 16);
    const auto expect = static_cast<std::uint8_t>(std::floor(255.0 * k / 16 + 0.5));
    EXPECT_EQ(t.pixel(10, 7), (Rgba8{expect, expect, expect, 255})) << "e " << e << " k " << k;
  }
}

TEST(Resolve, OneSampleIsTheIdentityAndOptionsDoNotChangeTheImage) {
  Mesh m = test::screen_mesh();
  m.color_source = ColorSource::kPerVertex;
  m.positions = {{1.3f, 2.2f, 0.5f, 1}, {30.1f, 5.7f, 0.5f, 1}, {12.9f, 15.2f, 0.5f, 1}};
  m.colors = {{255, 0, 0, 255}, {0, 255, 0, 128}, {0, 0, 255, 0}};
  for (int samples : {1, 4, 8, 16}) {
    RenderTarget plain(32, 16, samples), kept(32, 16, samples, TargetOptions{true, true});
    test::render_reference(m, plain);
    test::render_reference(m, kept);
    EXPECT_TRUE(plain.sample_color().empty());
    EXPECT_TRUE(plain.sample_depth().empty());
    ASSERT_EQ(kept.sample_color().size(), 32u * 16u * samples);
    EXPECT_EQ(kept.sample_depth().size(), 32u * 16u * samples);
    EXPECT_TRUE(std::equal(plain.color().begin(), plain.color().end(), kept.color().begin(),
                           kept.color().end()));
    EXPECT_EQ(plain.image_hash(), kept.image_hash());
    if (samples == 1) {
      EXPECT_TRUE(std::equal(kept.color().begin(), kept.color().end(), kept.sample_color().begin(),
                             kept.sample_color().end()));
    }
  }
}

}  // namespace
}  // namespace mosaic
