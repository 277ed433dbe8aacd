// test_quality_post.cpp — FXAA and the wide resolve filters (mosaic/post.hpp) on tiny images
// checked by hand, the aliasing metric's FFT against its spatial definition, and the claims the
// report rests on (FXAA lowers the error of 1x on an edge; a Gaussian trades error for aliasing).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "mosaic/post.hpp"
#include "quality/quality.hpp"

namespace mosaic {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(Fxaa, LeavesFlatAndLowContrastImagesAlone) {
  const int w = 8, h = 6;
  std::vector<Rgba8> in(w * h, Rgba8{90, 120, 30, 200}), out(w * h);
  post::fxaa(in, w, h, out);
  EXPECT_EQ(in, out);
  // A checkerboard of luma 0.50 and 0.53: a range of 0.03, under the 1/16 minimum threshold.
  for (int i = 0; i < w * h; ++i)
    in[i] = ((i % w + i / w) % 2) ? Rgba8{128, 128, 128, 255} : Rgba8{136, 136, 136, 255};
  post::fxaa(in, w, h, out);
  EXPECT_EQ(in, out);
}

TEST(Fxaa, StraightHorizontalEdgeGetsOnlyTheSubpixelTermByHand) {
  // Rows 0-3 black, 4-7 white. In row 3: lowpass = (2 (N + S + E + W) + diagonals) / 12 =
  // (2 + 2) / 12 = 1/3, range 1, so a = 1/3, smoothstep (3 - 2a) a² = 7/27, squared times 0.75
  // = 0.0504; the edge has no end to walk to, so that is the blend towards the white pixel
  // below: 0.0504 * 255 = 12.85 -> 13. Row 4 mirrors it: 255 - 13 = 242. Alpha is kept.
  const int w = 8, h = 8;
  std::vector<Rgba8> in(w * h), out(w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      in[y * w + x] = y < 4 ? Rgba8{0, 0, 0, 77} : Rgba8{255, 255, 255, 77};
  post::fxaa(in, w, h, out);
  for (int x = 0; x < w; ++x) {
    EXPECT_EQ(out[3 * w + x], (Rgba8{13, 13, 13, 77})) << x;
    EXPECT_EQ(out[4 * w + x], (Rgba8{242, 242, 242, 77})) << x;
    EXPECT_EQ(out[2 * w + x], in[2 * w + x]);
    EXPECT_EQ(out[5 * w + x], in[5 * w + x]);
  }
}

TEST(Fxaa, BlendsOnlyTowardsANeighbour) {
  const int w = 23, h = 17;
  std::mt19937 rng(3);
  std::vector<Rgba8> in(w * h), out(w * h);
  for (Rgba8& c : in) {
    const auto v = static_cast<std::uint8_t>(rng() % 2 ? 255 : 0);
    c = {v, static_cast<std::uint8_t>(rng() % 256), v, 255};
  }
  post::fxaa(in, w, h, out);
  auto at = [&](int x, int y) { return in[std::clamp(y, 0, h - 1) * w + std::clamp(x, 0, w - 1)]; };
  int changed = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const Rgba8 o = out[y * w + x], m = at(x, y);
      bool between_some = false;
      for (const Rgba8 n : {at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1)}) {
        auto in_range = [](int v, int a, int b) {
          return v >= std::min(a, b) && v <= std::max(a, b);
        };
        between_some = between_some || (in_range(o.r, m.r, n.r) && in_range(o.g, m.g, n.g) &&
                                        in_range(o.b, m.b, n.b));
      }
      EXPECT_TRUE(between_some) << x << "," << y;
      changed += !(o == m);
    }
  }
  EXPECT_GT(changed, w * h / 4);
}

TEST(Fxaa, RejectsMismatchedBuffers) {
  std::vector<Rgba8> in(10), out(9);
  EXPECT_THROW(post::fxaa(in, 5, 2, out), Error);
}

/// A slightly slanted edge at 1x is a staircase; FXAA should bring it closer to the exact
/// coverage (what it is for).
TEST(Fxaa, LowersTheErrorOfAStaircase) {
  Scene s;
  s.width = 96;
  s.height = 48;
  Mesh m;
  m.space = Space::kScreen;
  m.positions = {{-10.0f, 20.3f, 0.5f, 1}, {110.0f, 27.9f, 0.5f, 1}, {-10.0f, 200.0f, 0.5f, 1}};
  s.meshes.push_back(m);
  const quality::Rect all{0, 0, s.width, s.height};
  const quality::Image truth = quality::exact_box_image(s, all);
  Renderer renderer;
  RenderTarget target(s.width, s.height, 1);
  const std::vector<Draw> draws = s.draws();
  renderer.render(Frame{draws}, target);
  std::vector<Rgba8> out(target.color().size());
  post::fxaa(target.color(), s.width, s.height, out);
  const double before =
      quality::compare(truth, quality::to_image(target.color(), s.width, s.height, all)).rms;
  const double after = quality::compare(truth, quality::to_image(out, s.width, s.height, all)).rms;
  EXPECT_LT(after, 0.8 * before) << before << " -> " << after;
}

/// A 2×1 target at 4x whose left pixel's samples are black and right pixel's white.
RenderTarget two_pixels() {
  TargetOptions opt;
  opt.keep_sample_color = true;
  RenderTarget t(2, 1, 4, opt);
  t.sample_color_storage().assign(8, Rgba8{0, 0, 0, 255});
  for (int s = 4; s < 8; ++s) t.sample_color_storage()[s] = {255, 255, 255, 255};
  return t;
}

TEST(Filters, TentOnTwoPixelsByHand) {
  // Left pixel: its own 4 samples (offsets (-2,-6) (6,-2) (-6,2) (2,6) sixteenths) each weigh
  // (1 - |dx|)(1 - |dy|) = 140/256, 560/256 in all; the right pixel's samples sit at dx = 14,
  // 22, 10, 18 sixteenths: only 14 (dy -6: 2/16 * 10/16 = 20/256) and 10 (dy 2: 6/16 * 14/16 =
  // 84/256) reach, 104/256. Left = 255 * 104 / 664 = 39.9 -> 40; right by symmetry
  // 255 * 560 / 664 = 215.06 -> 215.
  const RenderTarget t = two_pixels();
  std::vector<Rgba8> out(2);
  post::filter_resolve(t, post::Filter::kTent, out);
  EXPECT_EQ(out[0], (Rgba8{40, 40, 40, 255}));
  EXPECT_EQ(out[1], (Rgba8{215, 215, 215, 255}));
  // The box keeps every pixel to itself.
  post::filter_resolve(t, post::Filter::kBox, out);
  EXPECT_EQ(out[0], (Rgba8{0, 0, 0, 255}));
  EXPECT_EQ(out[1], (Rgba8{255, 255, 255, 255}));
  // The Gaussian reaches further than the tent: more of the neighbour.
  post::filter_resolve(t, post::Filter::kGaussian, out);
  EXPECT_GT(out[0].r, 40);
  EXPECT_LT(out[1].r, 215);
}

TEST(Filters, WeightsAreWhatTheyClaim) {
  EXPECT_DOUBLE_EQ(post::filter_weight(post::Filter::kTent, 0.25), 0.75);
  EXPECT_DOUBLE_EQ(post::filter_weight(post::Filter::kTent, -1.0), 0.0);
  EXPECT_DOUBLE_EQ(post::filter_weight(post::Filter::kGaussian, 0.5), std::exp(-0.5));
  EXPECT_DOUBLE_EQ(post::filter_weight(post::Filter::kGaussian, 1.6), 0.0);
}

TEST(Filters, BoxEqualsTheEnginesResolveAndFlatStaysFlat) {
  const Scene s = builtin_scene("star", 80, 60);
  Renderer renderer;
  TargetOptions opt;
  opt.keep_sample_color = true;
  for (int samples : {1, 4, 8, 16}) {
    RenderTarget t(s.width, s.height, samples, opt);
    t.set_clear(s.clear_color);
    const std::vector<Draw> draws = s.draws();
    renderer.render(Frame{draws}, t);
    std::vector<Rgba8> out(t.color().size());
    post::filter_resolve(t, post::Filter::kBox, out);
    EXPECT_TRUE(std::equal(out.begin(), out.end(), t.color().begin())) << samples;
    // A corner of the image is background only: every filter must give the clear colour.
    for (post::Filter f : {post::Filter::kTent, post::Filter::kGaussian}) {
      post::filter_resolve(t, f, out);
      EXPECT_EQ(out[0], s.clear_color);
    }
  }
  RenderTarget no_samples(4, 4, 4);
  std::vector<Rgba8> out(16);
  EXPECT_THROW(post::filter_resolve(no_samples, post::Filter::kTent, out), Error);
}

TEST(Aliasing, FrequencyDomainEnergyEqualsTheWindowedVariance) {
  // Parseval: the DFT energy of the windowed, mean-removed luma over N equals its sum of
  // squares, so A is the mean square per window pixel. Checked against the direct sum.
  const int w = 40, h = 30;
  quality::Image img{w, h, std::vector<double>(w * h * 3)};
  std::mt19937 rng(5);
  for (double& v : img.rgb) v = static_cast<double>(rng() % 1000) / 999.0;
  const quality::Annulus win{20, 15, 4, 12};
  double sum = 0, n = 0;
  std::vector<double> l;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double r = std::hypot(x + 0.5 - 20, y + 0.5 - 15);
      if (r < 4 || r > 12) continue;
      l.push_back(0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2));
      sum += l.back();
      n += 1;
    }
  }
  double var = 0;
  for (double v : l) var += (v - sum / n) * (v - sum / n);
  EXPECT_NEAR(quality::aliasing_energy(img, win), var / n, 1e-12);
}

TEST(Aliasing, SpectrumPeaksAtTheCosinesFrequency) {
  // Luma cos(2 pi 5 x / 64): all its energy is at +-5 cycles per 64 px, row 0 of frequency.
  const int w = 64, h = 32;
  quality::Image img{w, h, std::vector<double>(w * h * 3)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        img.rgb[(y * w + x) * 3 + c] = 0.5 + 0.5 * std::cos(2 * kPi * 5 * x / w);
  const std::vector<Rgba8> s = quality::spectrum_image(img);
  int bright = 0;
  for (int i = 0; i < w * h; ++i) bright += s[i].r == 255;
  EXPECT_EQ(bright, 2);
  EXPECT_EQ(s[(h / 2) * w + w / 2 + 5].r, 255);
  EXPECT_EQ(s[(h / 2) * w + w / 2 - 5].r, 255);
}

TEST(Aliasing, GaussianTradesErrorForAliasingOnTheZonePlate) {
  const int w = 192, h = 128;
  const Scene zp = quality::zone_plate_scene(w, h);
  const quality::Rect all{0, 0, w, h};
  const quality::Image truth = quality::exact_box_image(zp, all);
  const quality::ZonePlate z = quality::zone_plate_for(w, h);
  const quality::Annulus win{z.cx, z.cy, 1.05 * z.nyquist_radius(), 0.98 * z.radius};
  Renderer renderer;
  TargetOptions opt;
  opt.keep_sample_color = true;
  RenderTarget t(w, h, 16, opt);
  const std::vector<Draw> draws = zp.draws();
  renderer.render(Frame{draws}, t);
  std::vector<Rgba8> gauss(t.color().size());
  post::filter_resolve(t, post::Filter::kGaussian, gauss);
  const quality::Image box_img = quality::to_image(t.color(), w, h, all);
  const quality::Image gauss_img = quality::to_image(gauss, w, h, all);
  // Blur: further from the box-filtered truth. Less aliasing: less energy beyond Nyquist, even
  // less than the box-filtered truth itself, whose box filter lets aliasing through.
  EXPECT_GT(quality::compare(truth, gauss_img).rms, quality::compare(truth, box_img).rms);
  const double a_gauss = quality::aliasing_energy(gauss_img, win);
  EXPECT_LT(a_gauss, 0.5 * quality::aliasing_energy(box_img, win));
  EXPECT_LT(a_gauss, quality::aliasing_energy(truth, win));
}

}  // namespace
}  // namespace mosaic
