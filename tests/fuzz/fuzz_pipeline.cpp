// tests/fuzz/fuzz_pipeline.cpp — libFuzzer target for the whole pipeline on raw vertex bits.
//
// Takes: arbitrary bytes: an 8-byte header (target size 1..64 × 1..64, sample count, space,
// depth test, culling, fill rule, colour source, index mode, SSAA, blending, shader, clear depth,
// tile size, index count / 32) followed by up to 8192 vertices as raw float32 bits x y z w (NaN,
// Inf, denormals and 1e38 included) and, with indices, the raw index bytes at the input's end
// (some out of range, many repeated). Inputs run to about 140 KB (.ci/fuzz.sh's -max_len). Gives:
// nothing, or a crash report. The frame must be either rejected by validate() — and then render()
// throws the same error and leaves the target alone — or rendered identically (every sample's
// colour and depth bit for bit, and the counters) on the reference and on every SIMD path this CPU
// runs; every written depth lies in [0, 1].
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"

namespace {

/// Largest target edge: small frames keep each input to well under a millisecond.
constexpr int kMaxEdge = 64;
/// Bytes of the header before the vertex data.
constexpr std::size_t kHeaderBytes = 8;
/// Bytes per vertex: four float32.
constexpr std::size_t kVertexBytes = 16;
/// At most this many vertices are read: 2730 triangles, more than one front-end chunk of 2048
/// (bin::kChunkTriangles), so that frames of several chunks are fuzzed too.
constexpr std::size_t kMaxVertices = 8192;
/// Index bytes per unit of the header's index count: up to 255 * 32 = 8160 indices.
constexpr std::size_t kIndicesPerCount = 32;

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "fuzz_pipeline: %s\n", what.c_str());
  std::abort();
}

struct Result {
  std::vector<mosaic::Rgba8> color, sample_color;
  std::vector<float> sample_depth;
  mosaic::FrameStats stats;
};

// One renderer per (ISA, tile size), kept across inputs: making one starts worker threads.
mosaic::Renderer& renderer(mosaic::Isa isa, int tile_size) {
  struct Kept {
    mosaic::Isa isa;
    int tile_size;
    std::unique_ptr<mosaic::Renderer> renderer;
  };
  static std::vector<Kept> cache;
  for (Kept& k : cache)
    if (k.isa == isa && k.tile_size == tile_size) return *k.renderer;
  const int threads = isa == mosaic::Isa::kReference ? 1 : 2;
  cache.push_back({isa, tile_size,
                   std::make_unique<mosaic::Renderer>(mosaic::RendererOptions{
                       .threads = threads, .isa = isa, .tile_size = tile_size})});
  return *cache.back().renderer;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < kHeaderBytes) return 0;
  static constexpr int kSamples[] = {1, 4, 8, 16};
  const int width = 1 + data[0] % kMaxEdge, height = 1 + data[1] % kMaxEdge;
  const int samples = kSamples[data[2] % 4];
  mosaic::Draw draw;
  draw.space = (data[3] & 1) ? mosaic::Space::kScreen : mosaic::Space::kClip;
  draw.state.depth_test = static_cast<mosaic::DepthTest>((data[3] >> 1) % 5);
  draw.state.depth_write = (data[3] & 0x10) == 0;
  draw.state.cull = static_cast<mosaic::CullMode>(data[4] % 3);
  draw.state.front_face =
      (data[4] & 4) ? mosaic::FrontFace::kClockwise : mosaic::FrontFace::kCounterClockwise;
  draw.state.fill_rule = (data[4] & 8) ? mosaic::FillRule::kOpenGL : mosaic::FillRule::kD3D;
  draw.color_source = static_cast<mosaic::ColorSource>(data[5] % 3);
  const bool indexed = (data[5] & 4) != 0;
  const bool ssaa = (data[5] & 8) != 0;
  // Source-over blending (with alphas other than 255), and the vertex-colour fragment shader
  // reading the raw vertex bits as its four varyings (NaN, Inf and 1e38 colours included).
  const bool blend = (data[5] & 0x10) != 0;
  const bool shaded = (data[5] & 0x20) != 0;
  if (blend) draw.state.blend = mosaic::BlendMode::kSourceOver;
  const float clear_depth = (data[6] & 1) ? 0.0f : 1.0f;
  // The fast paths' tile size: the renderer's choice, or 8 to 128 px (tile edges through a
  // 64 px target).
  const int tile_code = (data[6] >> 1) % 6;
  const int tile_size = tile_code == 0 ? 0 : mosaic::kMinTileSize << (tile_code - 1);
  const std::size_t index_count = data[7] * kIndicesPerCount;

  // With indices, their bytes are the input's last ones; the vertices take what comes before.
  const std::size_t vertex_end = indexed ? size - std::min(size - kHeaderBytes, index_count) : size;
  std::vector<glm::vec4> positions;
  std::size_t at = kHeaderBytes;
  while (at + kVertexBytes <= vertex_end && positions.size() < kMaxVertices) {
    glm::vec4 v;
    std::memcpy(&v, data + at, kVertexBytes);
    positions.push_back(v);
    at += kVertexBytes;
  }
  std::vector<std::uint32_t> indices;
  if (indexed) {
    // Index bytes: mostly in range (mod vertex count + 1: the last value is out of range).
    at = vertex_end;
    for (std::size_t k = 0; k < index_count && at < size; ++k, ++at)
      indices.push_back(positions.empty() ? data[at] : data[at] % (positions.size() + 1));
  } else {
    positions.resize(positions.size() / 3 * 3);
  }
  std::vector<mosaic::Rgba8> colors;
  const std::size_t tris = indexed ? indices.size() / 3 : positions.size() / 3;
  const std::size_t ncolors =
      draw.color_source == mosaic::ColorSource::kPerVertex ? positions.size() : tris;
  for (std::size_t k = 0; k < ncolors; ++k)
    colors.push_back({static_cast<std::uint8_t>(k * 37), static_cast<std::uint8_t>(k * 91),
                      static_cast<std::uint8_t>(k),
                      blend ? static_cast<std::uint8_t>(k * 53) : std::uint8_t{255}});
  draw.positions = positions;
  static constexpr std::uint32_t kColorVaryings[] = {0, 1, 2, 3};
  std::vector<float> attributes;
  if (shaded) {
    for (const glm::vec4& p : positions) attributes.insert(attributes.end(), {p.x, p.y, p.z, p.w});
    draw.attributes = attributes;
    draw.attribute_count = 4;
    draw.varyings = kColorVaryings;
    draw.shader = mosaic::vertex_color_shader();
  }
  draw.indices = indices;
  draw.colors = colors;
  mosaic::Frame frame;
  frame.draws = std::span<const mosaic::Draw>(&draw, 1);
  frame.ssaa = ssaa;

  auto run = [&](mosaic::Isa isa, bool& rejected, mosaic::Errc& code) {
    mosaic::RenderTarget target(width, height, samples, mosaic::TargetOptions{true, true});
    target.set_clear({1, 2, 3, 4}, clear_depth);
    const std::vector<mosaic::Rgba8> before(target.color().begin(), target.color().end());
    Result r;
    rejected = false;
    try {
      r.stats = renderer(isa, isa == mosaic::Isa::kReference ? 0 : tile_size).render(frame, target);
    } catch (const mosaic::Error& e) {
      rejected = true;
      code = e.code();
      if (!std::equal(before.begin(), before.end(), target.color().begin()))
        bug("a rejected frame touched the target");
    }
    r.color.assign(target.color().begin(), target.color().end());
    r.sample_color.assign(target.sample_color().begin(), target.sample_color().end());
    r.sample_depth.assign(target.sample_depth().begin(), target.sample_depth().end());
    return r;
  };

  bool expect_reject = false;
  mosaic::Errc expect_code{};
  try {
    mosaic::validate(frame, mosaic::RenderTarget(width, height, samples));
  } catch (const mosaic::Error& e) {
    expect_reject = true;
    expect_code = e.code();
  }
  try {
    bool rejected = false;
    mosaic::Errc code{};
    const Result ref = run(mosaic::Isa::kReference, rejected, code);
    if (rejected != expect_reject || (rejected && code != expect_code))
      bug("render() and validate() disagree");
    if (rejected) return 0;
    for (float d : ref.sample_depth)
      if (!(d >= 0.0f && d <= 1.0f)) bug("a depth outside [0, 1]");
    for (mosaic::Isa isa : mosaic::available_isas()) {
      if (isa == mosaic::Isa::kReference) continue;
      const Result fast = run(isa, rejected, code);
      if (rejected) bug("the fast path rejected what the reference drew");
      if (fast.sample_color != ref.sample_color || fast.color != ref.color ||
          std::memcmp(fast.sample_depth.data(), ref.sample_depth.data(),
                      ref.sample_depth.size() * sizeof(float)) != 0)
        bug(std::string("samples differ on ") + mosaic::to_string(isa));
      if (fast.stats.samples_written != ref.stats.samples_written ||
          fast.stats.triangles_drawn != ref.stats.triangles_drawn ||
          fast.stats.triangles_nonfinite != ref.stats.triangles_nonfinite)
        bug(std::string("counters differ on ") + mosaic::to_string(isa));
    }
  } catch (const std::exception& e) {
    bug(std::string("unexpected exception: ") + e.what());
  }
  return 0;
}
