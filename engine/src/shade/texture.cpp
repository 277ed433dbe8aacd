// shade/texture.cpp — mip chains and filtered texture reads (mosaic/texture.hpp).
//
// Takes: RGBA8 images. Gives: their box-filtered mip chains and the nearest, bilinear and
// trilinear reads with repeat, clamp and mirror addressing. Every read is plain scalar float
// code compiled once, so that all paths that shade a pixel with the same inputs get the same bits.
#include "mosaic/texture.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>

#include "mosaic/errors.hpp"

namespace mosaic {
namespace {

void check_image(const TextureImage& image, int level) {
  const std::string where = "texture level " + std::to_string(level);
  if (image.width < 1 || image.width > kMaxTextureSize || image.height < 1 ||
      image.height > kMaxTextureSize) {
    throw Error(Errc::kInvalidArgument,
                where + " is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                    "; each size must be in [1, " + std::to_string(kMaxTextureSize) + "]");
  }
  const std::size_t want = static_cast<std::size_t>(image.width) * std::size_t(image.height);
  if (image.texels.size() != want) {
    throw Error(Errc::kInvalidArgument, where + " has " + std::to_string(image.texels.size()) +
                                            " texels; " + std::to_string(image.width) + "x" +
                                            std::to_string(image.height) + " needs " +
                                            std::to_string(want));
  }
}

int half(int size) { return std::max(1, size / 2); }

// The next level of `src` by the 2×2 box filter; a 1-wide source reads its one column twice.
template <class Level>
Level downsample(const Level& src) {
  Level dst;
  dst.width = half(src.width);
  dst.height = half(src.height);
  dst.texels.resize(static_cast<std::size_t>(dst.width) * std::size_t(dst.height));
  const auto at = [&](int x, int y) -> const Rgba8& {
    return src
        .texels[static_cast<std::size_t>(std::min(y, src.height - 1)) * std::size_t(src.width) +
                std::size_t(std::min(x, src.width - 1))];
  };
  // Mean of four 8-bit values, rounded half up: (sum + 2) / 4.
  const auto mean = [](int a, int b, int c, int d) {
    return static_cast<std::uint8_t>((a + b + c + d + 2) / 4);
  };
  for (int y = 0; y < dst.height; ++y) {
    for (int x = 0; x < dst.width; ++x) {
      const Rgba8& p = at(2 * x, 2 * y);
      const Rgba8& q = at(2 * x + 1, 2 * y);
      const Rgba8& r = at(2 * x, 2 * y + 1);
      const Rgba8& s = at(2 * x + 1, 2 * y + 1);
      dst.texels[static_cast<std::size_t>(y) * std::size_t(dst.width) + std::size_t(x)] = {
          mean(p.r, q.r, r.r, s.r), mean(p.g, q.g, r.g, s.g), mean(p.b, q.b, r.b, s.b),
          mean(p.a, q.a, r.a, s.a)};
    }
  }
  return dst;
}

// `u` brought into the range its addressing mode reads, so that texel-space values stay small
// and their conversion to int is defined: repeat to [0, 1), mirror to [0, 2), clamp to [-1, 2].
float reduce(float u, Address mode) {
  if (!std::isfinite(u)) return 0.0f;
  switch (mode) {
    case Address::kRepeat:
      return u - std::floor(u);
    case Address::kMirror:
      return u - 2.0f * std::floor(0.5f * u);
    case Address::kClamp:
      return std::clamp(u, -1.0f, 2.0f);
  }
  return 0.0f;
}

// Texel index `i` (of a reduced coordinate: |i| < 3 size) wrapped into [0, size).
int wrap(int i, int size, Address mode) {
  switch (mode) {
    case Address::kRepeat:
      return ((i % size) + size) % size;
    case Address::kMirror: {
      const int m = ((i % (2 * size)) + 2 * size) % (2 * size);
      return m < size ? m : 2 * size - 1 - m;
    }
    case Address::kClamp:
      return std::clamp(i, 0, size - 1);
  }
  return 0;
}

glm::vec4 to_float(const Rgba8& c) {
  constexpr float kInv255 = 1.0f / 255.0f;
  return {float(c.r) * kInv255, float(c.g) * kInv255, float(c.b) * kInv255, float(c.a) * kInv255};
}

glm::vec4 lerp(const glm::vec4& a, const glm::vec4& b, float t) { return a + (b - a) * t; }

}  // namespace

Texture::Texture(std::vector<Level> levels)
    : levels_(std::make_shared<const std::vector<Level>>(std::move(levels))) {}

Texture Texture::from_image(const TextureImage& image, bool mipmaps) {
  check_image(image, 0);
  std::vector<Level> levels;
  levels.push_back({image.width, image.height, {image.texels.begin(), image.texels.end()}});
  while (mipmaps && (levels.back().width > 1 || levels.back().height > 1)) {
    levels.push_back(downsample(levels.back()));
  }
  return Texture(std::move(levels));
}

Texture Texture::from_levels(std::span<const TextureImage> images) {
  if (images.empty()) throw Error(Errc::kInvalidArgument, "a texture needs at least one level");
  for (std::size_t k = 0; k < images.size(); ++k) {
    check_image(images[k], static_cast<int>(k));
    if (k == 0) continue;
    const int w = half(images[k - 1].width), h = half(images[k - 1].height);
    if (images[k].width != w || images[k].height != h) {
      throw Error(Errc::kInvalidArgument, "texture level " + std::to_string(k) + " is " +
                                              std::to_string(images[k].width) + "x" +
                                              std::to_string(images[k].height) +
                                              "; after the level before it, it must be " +
                                              std::to_string(w) + "x" + std::to_string(h));
    }
  }
  std::vector<Level> levels;
  levels.reserve(images.size());
  for (const TextureImage& image : images) {
    levels.push_back({image.width, image.height, {image.texels.begin(), image.texels.end()}});
  }
  return Texture(std::move(levels));
}

int Texture::levels() const noexcept { return levels_ ? static_cast<int>(levels_->size()) : 0; }
int Texture::width(int level) const { return (*levels_)[std::size_t(level)].width; }
int Texture::height(int level) const { return (*levels_)[std::size_t(level)].height; }
Rgba8 Texture::texel(int level, int x, int y) const {
  const Level& l = (*levels_)[std::size_t(level)];
  return l.texels[static_cast<std::size_t>(y) * std::size_t(l.width) + std::size_t(x)];
}

float Texture::lod(glm::vec2 duv_dx, glm::vec2 duv_dy) const noexcept {
  if (!levels_) return -INFINITY;
  const float w = float(width()), h = float(height());
  const auto length2 = [&](glm::vec2 d) {
    const float x = std::isfinite(d.x) ? d.x * w : 0.0f;
    const float y = std::isfinite(d.y) ? d.y * h : 0.0f;
    const float l2 = x * x + y * y;
    return std::isfinite(l2) ? l2 : 0.0f;
  };
  // log2 of the longer length = half the log2 of its square: one log and no sqrt.
  const float longest2 = std::max(length2(duv_dx), length2(duv_dy));
  return longest2 > 0.0f ? 0.5f * std::log2(longest2) : -INFINITY;
}

glm::vec4 Texture::read_level(const Sampler& sampler, int level, glm::vec2 uv) const noexcept {
  const Level& l = (*levels_)[std::size_t(level)];
  const float u = reduce(uv.x, sampler.address_u) * float(l.width);
  const float v = reduce(uv.y, sampler.address_v) * float(l.height);
  const auto at = [&](int x, int y) {
    x = wrap(x, l.width, sampler.address_u);
    y = wrap(y, l.height, sampler.address_v);
    return to_float(l.texels[static_cast<std::size_t>(y) * std::size_t(l.width) + std::size_t(x)]);
  };
  if (sampler.filter == TexelFilter::kNearest) {
    return at(static_cast<int>(std::floor(u)), static_cast<int>(std::floor(v)));
  }
  // Bilinear between the four texel centres around (u, v); centres sit at half-integers.
  const float s = u - 0.5f, t = v - 0.5f;
  const float fs = std::floor(s), ft = std::floor(t);
  const int x0 = static_cast<int>(fs), y0 = static_cast<int>(ft);
  const float ax = s - fs, ay = t - ft;
  const glm::vec4 top = lerp(at(x0, y0), at(x0 + 1, y0), ax);
  const glm::vec4 bottom = lerp(at(x0, y0 + 1), at(x0 + 1, y0 + 1), ax);
  return lerp(top, bottom, ay);
}

glm::vec4 Texture::sample_lod(const Sampler& sampler, glm::vec2 uv, float lod) const noexcept {
  if (!levels_) return glm::vec4(0.0f);
  const int last = levels() - 1;
  if (sampler.mip == MipFilter::kNone || last == 0) return read_level(sampler, 0, uv);
  if (std::isfinite(sampler.lod_bias)) lod += sampler.lod_bias;
  if (std::isnan(lod) || lod <= 0.0f) return read_level(sampler, 0, uv);
  if (lod >= float(last)) return read_level(sampler, last, uv);
  if (sampler.mip == MipFilter::kNearest) {
    return read_level(sampler, static_cast<int>(std::floor(lod + 0.5f)), uv);
  }
  const float fl = std::floor(lod);
  const int l0 = static_cast<int>(fl);
  const float blend = lod - fl;
  const glm::vec4 a = read_level(sampler, l0, uv);
  return blend > 0.0f ? lerp(a, read_level(sampler, l0 + 1, uv), blend) : a;
}

glm::vec4 Texture::sample(const Sampler& sampler, glm::vec2 uv, glm::vec2 duv_dx,
                          glm::vec2 duv_dy) const noexcept {
  if (!levels_) return glm::vec4(0.0f);
  // A texture of one level, or a sampler without mips, needs no level of detail.
  if (sampler.mip == MipFilter::kNone || levels() == 1) return read_level(sampler, 0, uv);
  return sample_lod(sampler, uv, lod(duv_dx, duv_dy));
}

}  // namespace mosaic
