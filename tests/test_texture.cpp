// Textures (mosaic/texture.hpp): the box-filtered mip chain, caller-made levels, the three
// texel and mip filters, the three addressing modes, the level of detail, hostile coordinates,
// and textured shaders through the renderer: a texture mapped 1:1 comes back texel for texel,
// a minified checkerboard is grey only with mipmaps, and textured random scenes match the
// reference bit for bit on every ISA.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"
#include "reference_test_util.hpp"

namespace mosaic {
namespace {

using test::simd_isas;

/// A w × h image whose texel (x, y) is (x, y, x + y, 255 - x) (all sizes below 256).
std::vector<Rgba8> ramp(int w, int h) {
  std::vector<Rgba8> t;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      t.push_back({std::uint8_t(x), std::uint8_t(y), std::uint8_t(x + y), std::uint8_t(255 - x)});
  return t;
}

/// A checkerboard of `cell`-texel squares, black and white, opaque.
std::vector<Rgba8> checker(int size, int cell) {
  std::vector<Rgba8> t;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const std::uint8_t v = ((x / cell + y / cell) % 2) ? 255 : 0;
      t.push_back({v, v, v, 255});
    }
  return t;
}

glm::vec4 color(const Rgba8& c) { return glm::vec4(c.r, c.g, c.b, c.a) / 255.0f; }

void expect_color(glm::vec4 got, glm::vec4 want, const std::string& what, float tol = 1e-6f) {
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(got[k], want[k], tol) << what << " channel " << k;
}

TEST(Texture, MipChainIsTheRoundedBoxFilterDownToOneTexel) {
  const std::vector<Rgba8> img = ramp(8, 4);
  const Texture t = Texture::from_image({8, 4, img});
  ASSERT_EQ(t.levels(), 4);
  const int sizes[4][2] = {{8, 4}, {4, 2}, {2, 1}, {1, 1}};
  for (int l = 0; l < 4; ++l) {
    EXPECT_EQ(t.width(l), sizes[l][0]);
    EXPECT_EQ(t.height(l), sizes[l][1]);
  }
  // Level 1 texel (1, 0) averages level 0 texels x 2..3, y 0..1: r = (2+3+2+3+2)/4 = 3 (2.5
  // rounded up), b = (2+3+3+4+2)/4 = 3.
  EXPECT_EQ(t.texel(1, 1, 0), (Rgba8{3, 1, 3, 253}));
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const int r = (4 * (2 * x) + 2 + 2) / 4;  // two columns 2x, 2x+1, twice each
      EXPECT_EQ(t.texel(1, x, y).r, r);
    }
  EXPECT_EQ(Texture::from_image({8, 4, img}, false).levels(), 1);
}

TEST(Texture, OddSizesDropTheLastRowAndOneWideLevelsReadTheirColumnTwice) {
  std::vector<Rgba8> img(5 * 3, Rgba8{0, 0, 0, 0});
  img[4] = {255, 255, 255, 255};  // last column of row 0: dropped by 5 -> 2
  const Texture t = Texture::from_image({5, 3, img});
  ASSERT_EQ(t.levels(), 3);
  EXPECT_EQ(t.width(1), 2);
  EXPECT_EQ(t.height(1), 1);
  EXPECT_EQ(t.texel(1, 1, 0), (Rgba8{0, 0, 0, 0}));
  // A 1 × 4 column: level 1 is 1 × 2, each the mean of two texels read twice.
  const std::vector<Rgba8> col{{0, 0, 0, 0}, {100, 0, 0, 0}, {1, 0, 0, 0}, {2, 0, 0, 0}};
  const Texture c = Texture::from_image({1, 4, col});
  ASSERT_EQ(c.levels(), 3);
  EXPECT_EQ(c.texel(1, 0, 0).r, 50);
  EXPECT_EQ(c.texel(1, 0, 1).r, 2);  // (1 + 2 + 1 + 2 + 2) / 4 = 2 (1.5 rounded up)
}

TEST(Texture, BadImagesAndChainsAreRejected) {
  const std::vector<Rgba8> img = ramp(4, 4);
  const auto rejects = [](auto make) {
    try {
      make();
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kInvalidArgument) << e.what();
    }
  };
  rejects([&] { Texture::from_image({0, 4, {}}); });
  rejects([&] { Texture::from_image({4, -1, img}); });
  rejects([&] { Texture::from_image({kMaxTextureSize + 1, 1, img}); });
  rejects([&] { Texture::from_image({4, 3, img}); });  // 16 texels for 12
  rejects([&] { Texture::from_levels({}); });
  const std::vector<Rgba8> two = ramp(2, 2), one = ramp(1, 1), three = ramp(3, 1);
  const TextureImage wrong_size[] = {{4, 4, img}, {3, 1, three}};
  rejects([&] { Texture::from_levels(wrong_size); });
  const TextureImage wrong_count[] = {{4, 4, img}, {2, 2, one}};
  rejects([&] { Texture::from_levels(wrong_count); });
  const TextureImage good[] = {{4, 4, img}, {2, 2, two}};
  EXPECT_EQ(Texture::from_levels(good).levels(), 2);  // a chain may stop early
}

TEST(Texture, NearestReadsTheContainingTexelUnderEveryAddressMode) {
  const std::vector<Rgba8> img = ramp(4, 2);
  const Texture t = Texture::from_image({4, 2, img});
  const auto at = [&](Address a, float u, float v) {
    return t.sample_lod(Sampler::nearest(a), {u, v}, 0.0f);
  };
  for (const Address a : {Address::kRepeat, Address::kClamp, Address::kMirror})
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 4; ++x)
        expect_color(at(a, (float(x) + 0.5f) / 4, (float(y) + 0.5f) / 2), color(img[y * 4 + x]),
                     "centre");
  expect_color(at(Address::kRepeat, 1.3f, -0.25f), color(img[1 * 4 + 1]), "repeat");
  expect_color(at(Address::kClamp, 7.0f, -3.0f), color(img[0 * 4 + 3]), "clamp");
  // Mirror: u = 1.3 reads 0.7 (texel 2), v = -0.25 reads 0.25 (row 0).
  expect_color(at(Address::kMirror, 1.3f, -0.25f), color(img[0 * 4 + 2]), "mirror");
  expect_color(at(Address::kMirror, 2.3f, 0.75f), color(img[1 * 4 + 1]), "mirror period 2");
}

TEST(Texture, BilinearWeighsTheFourCentresAndWrapsAtTheEdges) {
  const std::vector<Rgba8> img = ramp(4, 2);
  const Texture t = Texture::from_image({4, 2, img});
  const auto at = [&](Address a, float u, float v) {
    return t.sample_lod(Sampler::bilinear(a), {u, v}, 0.0f);
  };
  // Between the centres of texels 1 and 2 of row 0, a quarter of the way down to row 1.
  const glm::vec4 want = 0.75f * 0.5f * (color(img[1]) + color(img[2])) +
                         0.25f * 0.5f * (color(img[5]) + color(img[6]));
  expect_color(at(Address::kClamp, 0.5f, 0.375f), want, "interior", 1e-5f);
  // At u = 0, repeat blends the last and first columns; clamp reads the first; mirror the first.
  const glm::vec4 c0 = color(img[0]), c3 = color(img[3]);
  expect_color(at(Address::kRepeat, 0.0f, 0.25f), 0.5f * (c0 + c3), "repeat seam", 1e-5f);
  expect_color(at(Address::kClamp, 0.0f, 0.25f), c0, "clamp edge", 1e-5f);
  expect_color(at(Address::kMirror, 0.0f, 0.25f), c0, "mirror edge", 1e-5f);
}

TEST(Texture, LevelOfDetailIsLog2OfTheLongerDerivativeInTexels) {
  const std::vector<Rgba8> img = ramp(64, 32);
  const Texture t = Texture::from_image({64, 32, img});
  EXPECT_FLOAT_EQ(t.lod({1.0f / 64, 0}, {0, 1.0f / 32}), 0.0f);
  EXPECT_FLOAT_EQ(t.lod({4.0f / 64, 0}, {0, 1.0f / 32}), 2.0f);
  EXPECT_FLOAT_EQ(t.lod({0, 0}, {0, 8.0f / 32}), 3.0f);
  EXPECT_FLOAT_EQ(t.lod({3.0f / 64, 4.0f / 32}, {0, 0}), std::log2(5.0f));
  EXPECT_EQ(t.lod({0, 0}, {0, 0}), -std::numeric_limits<float>::infinity());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FLOAT_EQ(t.lod({nan, 2.0f / 32}, {INFINITY, 0}), 1.0f);
  EXPECT_EQ(Texture().lod({1, 1}, {1, 1}), -std::numeric_limits<float>::infinity());
}

TEST(Texture, MipFiltersChooseAndBlendLevels) {
  const std::vector<Rgba8> red(4 * 4, Rgba8{255, 0, 0, 255}), blue(2 * 2, Rgba8{0, 0, 255, 255}),
      green(1, Rgba8{0, 255, 0, 255});
  const TextureImage levels[] = {{4, 4, red}, {2, 2, blue}, {1, 1, green}};
  const Texture t = Texture::from_levels(levels);
  const glm::vec2 uv{0.3f, 0.6f};
  const glm::vec4 r{1, 0, 0, 1}, b{0, 0, 1, 1}, g{0, 1, 0, 1};
  const Sampler tri = Sampler::trilinear(), near = Sampler::bilinear_mip(),
                none = Sampler::bilinear();
  expect_color(t.sample_lod(tri, uv, 0.25f), 0.75f * r + 0.25f * b, "trilinear 0.25");
  expect_color(t.sample_lod(tri, uv, 1.5f), 0.5f * b + 0.5f * g, "trilinear 1.5");
  expect_color(t.sample_lod(tri, uv, -3.0f), r, "magnified");
  expect_color(t.sample_lod(tri, uv, 9.0f), g, "past the last level");
  expect_color(t.sample_lod(near, uv, 0.4f), r, "nearest level 0.4");
  expect_color(t.sample_lod(near, uv, 0.6f), b, "nearest level 0.6");
  expect_color(t.sample_lod(none, uv, 5.0f), r, "no mips");
  Sampler biased = tri;
  biased.lod_bias = 1.0f;
  expect_color(t.sample_lod(biased, uv, 0.25f), 0.75f * b + 0.25f * g, "biased");
  // sample() takes the level from the derivatives: 2 texels per pixel is level 1.
  expect_color(t.sample(tri, uv, {0.5f, 0}, {0, 0.5f}), b, "from derivatives");
  expect_color(t.sample(tri, uv, {0, 0}, {0, 0}), r, "zero derivatives");
}

TEST(Texture, HostileCoordinatesReadATexelAndNeverLeaveTheImage) {
  const std::vector<Rgba8> img = ramp(5, 3);
  const Texture t = Texture::from_image({5, 3, img});
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float hostile[] = {nan, inf, -inf, 1e30f, -1e30f, 16777217.0f, -1e-30f, 0.99999994f};
  for (const Sampler base : {Sampler::nearest(), Sampler::bilinear(), Sampler::trilinear()})
    for (const Address a : {Address::kRepeat, Address::kClamp, Address::kMirror})
      for (const float u : hostile)
        for (const float d : {0.0f, nan, inf, 1e30f}) {
          Sampler s = base;
          s.address_u = s.address_v = a;
          s.lod_bias = d;
          const glm::vec4 c = t.sample(s, {u, -u}, {d, 0}, {0, d});
          for (int k = 0; k < 4; ++k) {
            EXPECT_TRUE(c[k] >= 0.0f && c[k] <= 1.0f) << u << " " << d << " channel " << k;
          }
          const glm::vec4 l = t.sample_lod(s, {u, u}, d);
          EXPECT_TRUE(l.r >= 0.0f && l.r <= 1.0f) << u << " " << d;
        }
  expect_color(Texture().sample(Sampler(), {0.5f, 0.5f}, {0, 0}, {0, 0}), glm::vec4(0), "empty");
}

// --- Through the renderer --------------------------------------------------------------------

test::Captured render(std::span<const Draw> draws, int w, int h, int samples, Isa isa,
                      int threads = 2, bool ssaa = false) {
  return test::render_draws(draws, w, h, {samples, ssaa, isa, threads, false}, {10, 20, 30, 255});
}

/// A screen-space rectangle [0, w) × [0, h) whose varyings 0, 1 run over [0, u1] × [0, v1].
struct TexturedRect {
  std::vector<glm::vec4> pos;
  std::vector<float> attr;
  TexturedRect(float w, float h, float u1, float v1) {
    const float corners[4][4] = {{0, 0, 0, 0}, {w, 0, u1, 0}, {w, h, u1, v1}, {0, h, 0, v1}};
    for (const int c : {0, 1, 2, 0, 2, 3}) {
      pos.emplace_back(corners[c][0], corners[c][1], 0.5f, 1.0f);
      attr.insert(attr.end(), {corners[c][2], corners[c][3]});
    }
  }
};

const std::vector<std::uint32_t> kUv{0, 1};

Shader texture_shader(const Texture& tex, const Sampler& s) {
  return make_shader([tex, s](const Fragment& f) { return f.sample(tex, s, 0); },
                     ShaderUses{2, true, false});
}

Draw rect_draw(const TexturedRect& r, Shader shader) {
  Draw d;
  d.space = Space::kScreen;
  d.positions = r.pos;
  d.attributes = r.attr;
  d.attribute_count = 2;
  d.varyings = kUv;
  d.shader = std::move(shader);
  return d;
}

TEST(TexturedDraw, OneToOneMappingReturnsTheTextureTexelForTexel) {
  const int w = 37, h = 23;
  const std::vector<Rgba8> img = ramp(w, h);
  const Texture tex = Texture::from_image({w, h, img});
  const TexturedRect rect(float(w), float(h), 1.0f, 1.0f);
  for (const Sampler s : {Sampler::nearest(), Sampler::bilinear(), Sampler::trilinear()}) {
    const Draw draws[] = {rect_draw(rect, texture_shader(tex, s))};
    for (const Isa isa : available_isas()) {
      const auto out = render(draws, w, h, 4, isa);
      for (int i = 0; i < w * h; ++i) ASSERT_EQ(out.color[i], img[i]) << to_string(isa) << " " << i;
    }
  }
}

TEST(TexturedDraw, MinifiedCheckerboardIsGreyOnlyWithMipmaps) {
  // 256 texels of 1-texel squares over 30 pixels: 8.5 texels per pixel, so that point samples
  // land on both colours; every level from 1 down is uniform grey.
  const std::vector<Rgba8> img = checker(256, 1);
  const Texture tex = Texture::from_image({256, 256, img});
  const TexturedRect rect(30, 30, 1.0f, 1.0f);
  const auto spread = [&](const Sampler& s) {
    const Draw draws[] = {rect_draw(rect, texture_shader(tex, s))};
    const auto out = render(draws, 30, 30, 1, Isa::kReference, 1);
    int lo = 255, hi = 0;
    for (const Rgba8 c : out.color) {
      lo = std::min<int>(lo, c.r);
      hi = std::max<int>(hi, c.r);
    }
    return std::pair{lo, hi};
  };
  const auto [nlo, nhi] = spread(Sampler::nearest());
  EXPECT_EQ(nhi - nlo, 255);  // point samples of the checker alias to black and white
  for (const Sampler s : {Sampler::bilinear_mip(), Sampler::trilinear()}) {
    const auto [lo, hi] = spread(s);
    EXPECT_GE(lo, 126);
    EXPECT_LE(hi, 129);
  }
}

/// Random clip-space triangles with UVs far outside [0, 1] and perspective.
struct RandomTextured {
  std::vector<glm::vec4> pos;
  std::vector<float> attr;
  explicit RandomTextured(std::uint64_t seed, int triangles) {
    test::Rng rng(seed);
    for (int i = 0; i < triangles * 3; ++i) {
      const double wv = rng.uniform(0.2, 4.0);
      pos.emplace_back(float(rng.uniform(-1.3, 1.3) * wv), float(rng.uniform(-1.3, 1.3) * wv),
                       float(rng.uniform(0.0, 1.0) * wv), float(wv));
      attr.push_back(float(rng.uniform(-3, 3)));
      attr.push_back(float(rng.uniform(-3, 3)));
    }
  }
};

TEST(TexturedDraw, RandomScenesMatchTheReferenceOnEveryPath) {
  const std::vector<Rgba8> img = ramp(61, 45);
  const Texture tex = Texture::from_image({61, 45, img});
  const RandomTextured scene(1234, 120);
  const Address modes[] = {Address::kRepeat, Address::kClamp, Address::kMirror};
  std::vector<Draw> draws;
  int k = 0;
  for (const Sampler base : {Sampler::nearest(), Sampler::bilinear_mip(), Sampler::trilinear()}) {
    Sampler s = base;
    s.address_u = modes[k % 3];
    s.address_v = modes[(k + 1) % 3];
    Draw d;
    d.positions = std::span<const glm::vec4>(scene.pos).subspan(std::size_t(k) * 120, 120);
    d.attributes = std::span<const float>(scene.attr).subspan(std::size_t(k) * 240, 240);
    d.attribute_count = 2;
    d.varyings = kUv;
    d.shader = texture_shader(tex, s);
    d.state.cull = CullMode::kNone;
    draws.push_back(std::move(d));
    ++k;
  }
  for (const int samples : {1, 4})
    for (const bool ssaa : {false, true}) {
      if (ssaa && samples == 1) continue;
      const auto ref = render(draws, 97, 83, samples, Isa::kReference, 1, ssaa);
      EXPECT_GT(ref.stats.samples_written, 0u);
      for (const Isa isa : simd_isas())
        for (const int threads : {1, 2})
          test::expect_same(ref, render(draws, 97, 83, samples, isa, threads, ssaa),
                            std::to_string(samples) + "x ssaa " + std::to_string(ssaa) + " " +
                                to_string(isa) + " threads " + std::to_string(threads));
    }
}

}  // namespace
}  // namespace mosaic
