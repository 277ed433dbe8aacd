// textured — a checkerboard floor seen at a grazing angle, behind a cut-out fence.
//
// Takes: an optional output path ending in .png or .ppm (default textured.png) and
// `--filter nearest|bilinear|trilinear` (default trilinear). Gives: a 320×180 image, 4 samples
// per pixel, and one line of stats. Shows textures (mosaic/texture.hpp: a mip chain built by
// the library, sampled with the level of detail from the UV derivatives) and the shader
// features: the fence discards where its texture is transparent, and colours its back faces
// darker than its front. Uses only the public API.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <mosaic/mosaic.hpp>
#include <optional>
#include <string>
#include <vector>

namespace {

constexpr int kWidth = 320, kHeight = 180;
constexpr int kSamples = 4;
constexpr mosaic::Rgba8 kSky{150, 190, 230, 255};
/// The floor's texture repeats this many times across it: far copies are a few pixels wide, so
/// the floor aliases without mipmaps.
constexpr float kFloorRepeats = 64.0f;
/// Texels per side of the floor's checkerboard (8 × 8 cells) and of the fence's texture.
constexpr int kTextureSize = 256;
/// A fence texel with alpha below this is a hole: the fence shader discards it.
constexpr float kAlphaCutoff = 0.5f;

/// An 8 × 8 checkerboard of two colours, kTextureSize texels square.
mosaic::Texture checkerboard() {
  std::vector<mosaic::Rgba8> texels;
  constexpr int kCell = kTextureSize / 8;
  for (int y = 0; y < kTextureSize; ++y)
    for (int x = 0; x < kTextureSize; ++x)
      texels.push_back(((x / kCell + y / kCell) & 1) ? mosaic::Rgba8{235, 235, 225, 255}
                                                     : mosaic::Rgba8{40, 60, 90, 255});
  return mosaic::Texture::from_image({kTextureSize, kTextureSize, texels});
}

/// A lattice: opaque wood-brown bars, transparent between them.
mosaic::Texture lattice() {
  std::vector<mosaic::Rgba8> texels;
  constexpr int kPitch = kTextureSize / 4, kBar = kPitch / 4;
  for (int y = 0; y < kTextureSize; ++y)
    for (int x = 0; x < kTextureSize; ++x) {
      const bool bar = (x + y) % kPitch < kBar || (x - y + kTextureSize) % kPitch < kBar;
      texels.push_back(bar ? mosaic::Rgba8{150, 100, 60, 255} : mosaic::Rgba8{0, 0, 0, 0});
    }
  return mosaic::Texture::from_image({kTextureSize, kTextureSize, texels});
}

/// A quad as two triangles: corners a, b, c, d (in order around it), UVs from 0 to `uv_max`.
struct Quad {
  std::vector<glm::vec3> positions;
  std::vector<float> uvs;
  Quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, float uv_max) {
    const glm::vec3 corner[4] = {a, b, c, d};
    const float uv[4][2] = {{0, 0}, {uv_max, 0}, {uv_max, uv_max}, {0, uv_max}};
    for (const int k : {0, 1, 2, 0, 2, 3}) {
      positions.push_back(corner[k]);
      uvs.insert(uvs.end(), {uv[k][0], uv[k][1]});
    }
  }
  mosaic::Draw draw(const glm::mat4& transform, mosaic::Shader shader) const {
    static constexpr std::uint32_t kUv[] = {0, 1};
    mosaic::Draw d;
    d.positions_xyz = positions;
    d.transform = transform;
    d.attributes = uvs;
    d.attribute_count = 2;
    d.varyings = kUv;
    d.shader = std::move(shader);
    return d;
  }
};

std::optional<mosaic::Sampler> parse_filter(const char* name) {
  if (std::strcmp(name, "nearest") == 0) return mosaic::Sampler::nearest();
  if (std::strcmp(name, "bilinear") == 0) return mosaic::Sampler::bilinear();
  if (std::strcmp(name, "trilinear") == 0) return mosaic::Sampler::trilinear();
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path out = "textured.png";
  mosaic::Sampler sampler = mosaic::Sampler::trilinear();
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--filter") == 0 && i + 1 < argc) {
      const auto s = parse_filter(argv[++i]);
      if (!s) {
        std::fprintf(stderr, "textured: --filter is nearest, bilinear or trilinear\n");
        return 2;
      }
      sampler = *s;
    } else {
      out = argv[i];
    }
  }
  try {
    const mosaic::Texture floor_texture = checkerboard(), fence_texture = lattice();
    const mosaic::Shader floor_shader = mosaic::make_shader(
        [floor_texture, sampler](const mosaic::Fragment& f) {
          return f.sample(floor_texture, sampler, 0);
        },
        mosaic::ShaderUses{.varyings = 2, .derivatives = true});
    // Returning std::optional makes a discarding shader: no colour means no colour and no depth.
    const mosaic::Shader fence_shader = mosaic::make_shader(
        [fence_texture, sampler](const mosaic::Fragment& f) -> std::optional<glm::vec4> {
          const glm::vec4 c = f.sample(fence_texture, sampler, 0);
          if (c.a < kAlphaCutoff) return std::nullopt;
          const float light = f.front_facing() ? 1.0f : 0.55f;
          return glm::vec4(glm::vec3(c) * light, 1.0f);
        },
        mosaic::ShaderUses{.varyings = 2, .derivatives = true});

    const Quad floor({-40, 0, 2}, {40, 0, 2}, {40, 0, -78}, {-40, 0, -78}, kFloorRepeats);
    const Quad fence({-1.6f, 0, -1}, {1.6f, 0, -1}, {1.6f, 1.6f, -1.8f}, {-1.6f, 1.6f, -1.8f}, 2);
    const glm::mat4 projection =
        glm::perspectiveRH_ZO(glm::radians(50.0f), float(kWidth) / float(kHeight), 0.1f, 200.f);
    const glm::mat4 view =
        glm::lookAtRH(glm::vec3(0, 0.9f, 2.5f), glm::vec3(0, 0.45f, -4), glm::vec3(0, 1, 0));
    std::vector<mosaic::Draw> draws{floor.draw(projection * view, floor_shader),
                                    fence.draw(projection * view, fence_shader)};
    draws[1].state.cull = mosaic::CullMode::kNone;  // the lattice is seen from both sides

    mosaic::Frame frame;
    frame.draws = draws;
    mosaic::RenderTarget target(kWidth, kHeight, kSamples);
    target.set_clear(kSky);
    mosaic::Renderer renderer;
    const mosaic::FrameStats stats = renderer.render(frame, target);
    mosaic::write_image(target, out);
    std::printf(
        "textured: wrote %s (%dx%d, %dx), %llu triangles drawn, %llu samples written, "
        "%.3f ms\n",
        out.string().c_str(), kWidth, kHeight, kSamples,
        static_cast<unsigned long long>(stats.triangles_drawn),
        static_cast<unsigned long long>(stats.samples_written), stats.ms_total);
    return 0;
  } catch (const mosaic::Error& e) {
    std::fprintf(stderr, "textured: %s\n", e.what());
    return 1;
  }
}
