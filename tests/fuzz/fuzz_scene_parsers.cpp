// tests/fuzz/fuzz_scene_parsers.cpp — libFuzzer target for the scene parsers.
//
// Takes: arbitrary bytes; the first selects the parser (even: .tris text through parse_tris, odd:
// an OBJ file through load_obj), the rest is the file. Gives: nothing, or a crash report. Every
// input must either parse or throw mosaic::Error with a one-line message; any other exception,
// a crash or a sanitizer report is a bug. A parsed scene must also be fit to render: validate()
// accepts it, its .tris round trip (save_tris, parse_tris) gives the same vertices, and a small
// one renders identically on the reference and the default fast path.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "mosaic/mosaic.hpp"

namespace {

/// Largest target (width * height) a parsed .tris is rendered into: keeps each input fast.
constexpr long kMaxRenderPixels = 64 * 64;
/// Size of the target an OBJ is framed for.
constexpr int kObjSize = 32;

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "fuzz_scene_parsers: %s\n", what.c_str());
  std::abort();
}

void check_error(const mosaic::Error& e) {
  const std::string m = e.what();
  if (m.empty() || m.find('\n') != std::string::npos) bug("error message is not one line: " + m);
}

std::filesystem::path scratch(const char* ext) {
  return std::filesystem::temp_directory_path() / ("mosaic_fuzz_" + std::to_string(getpid()) + ext);
}

void render_both(const mosaic::Scene& s) {
  if (static_cast<long>(s.width) * s.height > kMaxRenderPixels) return;
  const auto draws = s.draws();
  mosaic::RenderTarget a(s.width, s.height, 4), b(s.width, s.height, 4);
  static mosaic::Renderer reference(mosaic::RendererOptions{1, mosaic::Isa::kReference});
  static mosaic::Renderer fast(mosaic::RendererOptions{2, mosaic::Isa::kAuto});
  reference.render(mosaic::Frame{draws}, a);
  fast.render(mosaic::Frame{draws}, b);
  if (a.image_hash() != b.image_hash()) bug("fast path differs from the reference");
}

void fuzz_tris(const std::string& text) {
  mosaic::Scene s;
  try {
    s = mosaic::parse_tris(text, "fuzz.tris");
  } catch (const mosaic::Error& e) {
    check_error(e);
    return;
  }
  if (s.width < 1 || s.height < 1 || s.width > mosaic::kMaxTargetSize ||
      s.height > mosaic::kMaxTargetSize)
    bug("accepted a bad size");
  for (const mosaic::Mesh& m : s.meshes)
    for (const glm::vec4& p : m.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || p.w != 1.0f)
        bug("accepted a non-finite coordinate");
  const mosaic::RenderTarget t(1, 1);
  mosaic::validate(mosaic::Frame{s.draws()}, t);
  // Round trip: what save_tris writes parses back to the same floats.
  const auto path = scratch(".tris");
  mosaic::save_tris(s, path);
  const mosaic::Scene back = mosaic::load_tris(path);
  std::filesystem::remove(path);
  if (back.triangle_count() != s.triangle_count()) bug("round trip changed the triangle count");
  for (std::size_t i = 0; i < s.meshes.size() && i < back.meshes.size(); ++i)
    if (s.meshes[i].positions.size() != back.meshes[i].positions.size() ||
        (!s.meshes[i].positions.empty() &&
         std::memcmp(s.meshes[i].positions.data(), back.meshes[i].positions.data(),
                     s.meshes[i].positions.size() * sizeof(glm::vec4)) != 0))
      bug("round trip changed a coordinate");
  render_both(s);
}

void fuzz_obj(const std::string& text) {
  const auto path = scratch(".obj");
  {
    std::ofstream out(path, std::ios::binary);
    out << text;
  }
  try {
    const mosaic::Scene s = mosaic::load_obj(path, kObjSize, kObjSize);
    std::filesystem::remove(path);
    const mosaic::RenderTarget t(kObjSize, kObjSize);
    mosaic::validate(mosaic::Frame{s.draws()}, t);
    render_both(s);
  } catch (const mosaic::Error& e) {
    std::filesystem::remove(path);
    check_error(e);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    if (data[0] % 2 == 0)
      fuzz_tris(text);
    else
      fuzz_obj(text);
  } catch (const mosaic::Error& e) {
    bug(std::string("mosaic::Error after a successful parse: ") + e.what());
  } catch (const std::exception& e) {
    bug(std::string("unexpected exception: ") + e.what());
  }
  return 0;
}
