// quality/texture_plane.cpp — texture aliasing: a checkerboard floor at a grazing angle.
//
// Takes: a size, a Sampler and a Renderer. Gives: the floor rendered with that sampler, and its
// ground truth: the same camera rendered kTextureTruthGrid times larger with point sampling,
// averaged over each pixel's kTextureTruthGrid² block (a box filter of the texture as seen).
#include <algorithm>
#include <cstddef>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <span>
#include <vector>

#include "quality/quality.hpp"

namespace mosaic::quality {
namespace {

// The scene, in world units: a camera kEyeHeight above a floor that runs from under it to
// kFloorFar ahead. With a 50° vertical field of view at 640×360, a far pixel covers about 24
// texels (3 cells) along v, a near one a tenth of a texel: the level of detail runs from −3 to
// +4.6. Cells of 8 texels keep the blur of magnified bilinear reads to the cells' edges.
constexpr float kEyeHeight = 1.0f;
constexpr float kFloorNear = 1.5f, kFloorFar = -10.0f, kFloorHalfWidth = 8.0f;
constexpr float kFovYDegrees = 50.0f;
// 64 texels per world unit, in copies of a kTexturePlaneSize-texel checkerboard of 8-texel cells.
constexpr float kTexelsPerUnit = 64.0f;
constexpr int kCellTexels = 8;
constexpr Rgba8 kSky{140, 170, 210, 255};

Texture checker_texture() {
  std::vector<Rgba8> t;
  t.reserve(std::size_t{kTexturePlaneSize} * kTexturePlaneSize);
  for (int y = 0; y < kTexturePlaneSize; ++y)
    for (int x = 0; x < kTexturePlaneSize; ++x) {
      const bool white = ((x / kCellTexels) + (y / kCellTexels)) % 2 != 0;
      t.push_back(white ? Rgba8{255, 255, 255, 255} : Rgba8{0, 0, 0, 255});
    }
  return Texture::from_image({kTexturePlaneSize, kTexturePlaneSize, t});
}

struct Floor {
  std::vector<glm::vec3> positions;
  std::vector<float> uvs;
  Floor() {
    const float x[4] = {-kFloorHalfWidth, kFloorHalfWidth, kFloorHalfWidth, -kFloorHalfWidth};
    const float z[4] = {kFloorNear, kFloorNear, kFloorFar, kFloorFar};
    constexpr float kUvPerUnit = kTexelsPerUnit / float(kTexturePlaneSize);
    for (const int k : {0, 1, 2, 0, 2, 3}) {
      positions.emplace_back(x[k], 0.0f, z[k]);
      uvs.insert(uvs.end(),
                 {(x[k] + kFloorHalfWidth) * kUvPerUnit, (kFloorNear - z[k]) * kUvPerUnit});
    }
  }
};

glm::mat4 view_projection(int width, int height) {
  const glm::mat4 projection = glm::perspectiveRH_ZO(glm::radians(kFovYDegrees),
                                                     float(width) / float(height), 0.05f, 100.0f);
  // Looking 20° below the horizon: the floor's far edge sits in the upper part of the image.
  const glm::mat4 view = glm::lookAtRH(glm::vec3(0, kEyeHeight, 2.0f),
                                       glm::vec3(0, kEyeHeight - 3.64f, -8.0f), glm::vec3(0, 1, 0));
  return projection * view;
}

// One frame of the floor as seen at width × height, through viewport `vp` of `target`.
void render_floor(const Sampler& sampler, int width, int height, PixelRect vp, RenderTarget& target,
                  Renderer& renderer) {
  static const Floor ground;
  static const Texture texture = checker_texture();
  static constexpr std::uint32_t kUv[] = {0, 1};
  Draw d;
  d.positions_xyz = ground.positions;
  d.transform = view_projection(width, height);
  d.attributes = ground.uvs;
  d.attribute_count = 2;
  d.varyings = kUv;
  d.shader = make_shader([sampler](const Fragment& f) { return f.sample(texture, sampler, 0); },
                         ShaderUses{2, true, false});
  d.state.viewport = vp;
  target.set_clear(kSky);
  const Draw draws[] = {d};
  Frame frame;
  frame.draws = draws;
  renderer.render(frame, target);
}

}  // namespace

void render_textured_plane(const Sampler& sampler, RenderTarget& target, Renderer& renderer) {
  render_floor(sampler, target.width(), target.height(), {0, 0, target.width(), target.height()},
               target, renderer);
}

Image textured_plane_truth(int width, int height, Renderer& renderer) {
  constexpr int G = kTextureTruthGrid;
  // The whole image magnified G times, placed so that the tile lands in the target.
  return magnified_means({0, 0, width, height}, G, [&](Rect tile, RenderTarget& target) {
    render_floor(Sampler::nearest(), width, height,
                 {-tile.x * G, -tile.y * G, width * G, height * G}, target, renderer);
  });
}

}  // namespace mosaic::quality
