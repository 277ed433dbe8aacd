// test_quality_texture.cpp — the texture aliasing measurement (quality/texture_plane.cpp): its
// ground truth is the mean of point samples (by hand on a few pixels), and against it the
// filters order as filtering before sampling says: every mipmapped filter beats point sampling,
// and trilinear beats nearest and bilinear without mipmaps.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "quality/quality.hpp"

namespace mosaic {
namespace {

constexpr int kW = 160, kH = 90;

quality::ErrorStats error_of(const Sampler& s, const quality::Image& truth, Renderer& r) {
  RenderTarget target(kW, kH, 1);
  quality::render_textured_plane(s, target, r);
  return quality::compare(truth, quality::to_image(target.color(), kW, kH, {0, 0, kW, kH}));
}

TEST(TextureAliasing, TruthIsTheMeanOfPointSamples) {
  Renderer r;
  const quality::Image truth = quality::textured_plane_truth(kW, kH, r);
  // The same view at kTextureTruthGrid times the size in one target, averaged by hand.
  constexpr int G = quality::kTextureTruthGrid;
  RenderTarget big(kW * G, kH * G, 1);
  quality::render_textured_plane(Sampler::nearest(), big, r);
  int checked = 0;
  for (const int y : {5, 40, 60, 89})
    for (const int x : {0, 33, 80, 159}) {
      double sum = 0;
      for (int j = 0; j < G; ++j)
        for (int i = 0; i < G; ++i)
          sum += big.color()[std::size_t(y * G + j) * kW * G + (x * G + i)].g;
      EXPECT_NEAR(truth.at(x, y, 1), sum / (255.0 * G * G), 1e-12) << x << "," << y;
      ++checked;
    }
  EXPECT_EQ(checked, 16);
}

TEST(TextureAliasing, MipmapsLowerTheErrorAndTrilinearMost) {
  Renderer r;
  const quality::Image truth = quality::textured_plane_truth(kW, kH, r);
  const double nearest = error_of(Sampler::nearest(), truth, r).rms;
  const double bilinear = error_of(Sampler::bilinear(), truth, r).rms;
  const double mip = error_of(Sampler::bilinear_mip(), truth, r).rms;
  const double trilinear = error_of(Sampler::trilinear(), truth, r).rms;
  EXPECT_LT(mip, nearest);
  EXPECT_LT(trilinear, nearest);
  EXPECT_LT(trilinear, bilinear);
  EXPECT_GT(nearest, 0.05) << "the floor should alias without mipmaps";
}

}  // namespace
}  // namespace mosaic
