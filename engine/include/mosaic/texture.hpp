// mosaic/texture.hpp — 2D RGBA8 textures with mipmaps, sampled from fragment shaders.
//
// Takes: an RGBA8 image (and optionally its mip levels). Gives: a Texture, and Sampler states for
// nearest, bilinear and trilinear filtering with repeat, clamp and mirror addressing.
//
// Conventions. Texture coordinates (u, v) span the image over [0, 1]²: u to the right, v down,
// so (0, 0) is the top-left corner of texel (0, 0) and texel (i, j) of a level of size w × h is
// centred at ((i + 0.5) / w, (j + 0.5) / h), as pixels are on the screen. Level k + 1 is
// max(1, floor(size_k / 2)) in each direction. The level of detail is
//   lod = log2(max(|duv/dx|, |duv/dy|) measured in level-0 texels) + Sampler::lod_bias,
// the isotropic rule of the GL specification, from the shader's screen-space derivatives of the
// UV (Fragment::sample()): below 0 the texture is magnified and level 0 is used.
//
// Sampling is a pure function of its arguments, compiled once, so that every SIMD path and the
// reference rasterizer, which call a shader with bit-identical inputs, get bit-identical colours.
// A Texture is immutable after construction; copies share its texels, and it may be sampled from
// any number of threads at once.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <span>
#include <vector>

#include "mosaic/types.hpp"

namespace mosaic {

/// Largest width or height of a texture, in texels: as for targets, so that texel-space
/// coordinates of a reduced UV keep 24-bit float precision to well under a texel.
inline constexpr int kMaxTextureSize = 16384;

/// How a level is read between texel centres.
enum class TexelFilter : std::uint8_t {
  kNearest,  ///< the texel that contains the point
  kLinear,   ///< bilinear: the four nearest texel centres, weighted by distance
};

/// How levels are chosen from the level of detail.
enum class MipFilter : std::uint8_t {
  kNone,     ///< level 0 always: a minified texture aliases
  kNearest,  ///< the level nearest the level of detail
  kLinear,   ///< the two levels around it, blended (with TexelFilter::kLinear: trilinear)
};

/// What a coordinate outside [0, 1] reads.
enum class Address : std::uint8_t {
  kRepeat,  ///< the texture tiles the plane
  kClamp,   ///< the edge texels extend outwards
  kMirror,  ///< the texture tiles, every other copy mirrored: no seam at the edges
};

/// How a texture is sampled. The defaults are trilinear filtering with repeat addressing.
struct Sampler {
  TexelFilter filter = TexelFilter::kLinear;
  MipFilter mip = MipFilter::kLinear;
  Address address_u = Address::kRepeat;
  Address address_v = Address::kRepeat;
  float lod_bias = 0.0f;  ///< added to the level of detail; a non-finite bias counts as 0

  static constexpr Sampler nearest(Address a = Address::kRepeat) {
    return {TexelFilter::kNearest, MipFilter::kNone, a, a, 0.0f};
  }
  static constexpr Sampler bilinear(Address a = Address::kRepeat) {
    return {TexelFilter::kLinear, MipFilter::kNone, a, a, 0.0f};
  }
  /// Bilinear within the nearest mip level.
  static constexpr Sampler bilinear_mip(Address a = Address::kRepeat) {
    return {TexelFilter::kLinear, MipFilter::kNearest, a, a, 0.0f};
  }
  static constexpr Sampler trilinear(Address a = Address::kRepeat) {
    return {TexelFilter::kLinear, MipFilter::kLinear, a, a, 0.0f};
  }
};

/// A view of one RGBA8 image: `texels` holds width × height texels, row by row from the top,
/// with no padding between rows. The texels are copied by Texture; the view need not outlive it.
struct TextureImage {
  int width = 0;
  int height = 0;
  std::span<const Rgba8> texels;
};

/// An immutable 2D RGBA8 texture and its mip levels.
class Texture {
 public:
  /// An empty texture: levels() is 0 and every sample is transparent black (0, 0, 0, 0).
  Texture() = default;

  /// A texture of `image`. With `mipmaps`, the library builds every level down to 1 × 1 with a
  /// 2 × 2 box filter: each channel of a texel is the mean of the four texels below it, rounded
  /// half up (straight alpha, as stored). A level of odd size drops its last row or column; a
  /// level 1 texel wide reads its one column twice. Throws Error(kInvalidArgument) if a size is
  /// outside [1, kMaxTextureSize] or the texel count is not width × height.
  static Texture from_image(const TextureImage& image, bool mipmaps = true);

  /// A texture whose levels the caller made: levels[0] is the image, and each next level must be
  /// max(1, floor(size / 2)) of the one before it (a chain may stop before 1 × 1). Throws
  /// Error(kInvalidArgument) if there are no levels, a level has the wrong size, or its texel
  /// count is not width × height.
  static Texture from_levels(std::span<const TextureImage> levels);

  int levels() const noexcept;     ///< mip levels, 0 for an empty texture
  int width(int level = 0) const;  ///< size of `level` (0 <= level < levels())
  int height(int level = 0) const;
  Rgba8 texel(int level, int x, int y) const;  ///< one stored texel (all arguments in range)

  /// The level of detail at which `sample` reads for these UV derivatives (before the sampler's
  /// bias): log2 of the longer derivative in level-0 texels. −infinity when both are zero; a
  /// non-finite derivative counts as 0.
  float lod(glm::vec2 duv_dx, glm::vec2 duv_dy) const noexcept;

  /// The filtered colour at `uv`, straight alpha in 0..1, for a pixel whose UV changes by
  /// `duv_dx` and `duv_dy` per pixel along x and y. A non-finite coordinate reads as 0.
  glm::vec4 sample(const Sampler& sampler, glm::vec2 uv, glm::vec2 duv_dx,
                   glm::vec2 duv_dy) const noexcept;

  /// The filtered colour at `uv` at level of detail `lod` (the sampler's bias is added).
  glm::vec4 sample_lod(const Sampler& sampler, glm::vec2 uv, float lod) const noexcept;

 private:
  struct Level {
    int width = 0, height = 0;
    std::vector<Rgba8> texels;
  };
  explicit Texture(std::vector<Level> levels);
  glm::vec4 read_level(const Sampler& sampler, int level, glm::vec2 uv) const noexcept;

  std::shared_ptr<const std::vector<Level>> levels_;
};

}  // namespace mosaic
