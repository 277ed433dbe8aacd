// io/image.cpp — writing a render target's resolved image to a file.
//
// Takes: a RenderTarget and a path ending in .png or .ppm. Gives: an RGBA PNG (through
// stb_image_write, compiled in Debian's libstb) or a binary RGB PPM (P6, alpha dropped). The
// image is encoded in memory, written to a temporary file in the same folder and renamed over
// the path, so a failure never leaves a partial image.
#include <stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/write_file.hpp"
#include "mosaic/errors.hpp"
#include "mosaic/scene.hpp"

namespace mosaic {
namespace {

/// Bytes per pixel of the encodings: RGBA for PNG, RGB for PPM.
constexpr int kPngChannels = 4;
constexpr int kPpmChannels = 3;
/// Largest channel value of an 8-bit PPM (the "maxval" header field).
constexpr int kPpmMaxValue = 255;

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// Appends what stb_image_write produces to a byte vector.
void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  const auto* bytes = static_cast<const unsigned char*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

/// The image in r, g, b, a order, row-major without padding: the target's own, or a copy of the
/// caller's memory it renders into.
std::vector<Rgba8> rgba_copy(const RenderTarget& target) {
  std::vector<Rgba8> out;
  out.reserve(static_cast<std::size_t>(target.width()) * target.height());
  for (int y = 0; y < target.height(); ++y)
    for (int x = 0; x < target.width(); ++x) out.push_back(target.pixel(x, y));
  return out;
}

std::vector<unsigned char> encode_png(const RenderTarget& target) {
  static_assert(sizeof(Rgba8) == kPngChannels, "Rgba8 must be four packed bytes");
  const int w = target.width(), h = target.height();
  std::vector<Rgba8> copy;
  if (target.over_caller_memory()) copy = rgba_copy(target);
  const Rgba8* pixels = target.over_caller_memory() ? copy.data() : target.color().data();
  // The row stride is an int: kMaxTargetSize * 4 bytes is far below INT_MAX.
  static_assert(std::int64_t{kMaxTargetSize} * kPngChannels < std::numeric_limits<int>::max());
  std::vector<unsigned char> out;
  const int ok =
      stbi_write_png_to_func(append_bytes, &out, w, h, kPngChannels, pixels, w * kPngChannels);
  if (ok == 0) out.clear();
  return out;
}

std::vector<unsigned char> encode_ppm(const RenderTarget& target) {
  const std::string header = "P6\n" + std::to_string(target.width()) + " " +
                             std::to_string(target.height()) + "\n" + std::to_string(kPpmMaxValue) +
                             "\n";
  std::vector<unsigned char> out(header.begin(), header.end());
  const std::vector<Rgba8> pixels = rgba_copy(target);
  out.reserve(out.size() + pixels.size() * kPpmChannels);
  for (const Rgba8& c : pixels) {
    out.push_back(c.r);
    out.push_back(c.g);
    out.push_back(c.b);
  }
  return out;
}

}  // namespace

void write_image(const RenderTarget& target, const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  std::vector<unsigned char> bytes;
  if (ext == ".png") {
    bytes = encode_png(target);
    if (bytes.empty()) throw Error(Errc::kIo, path.string() + ": PNG encoding failed");
  } else if (ext == ".ppm") {
    bytes = encode_ppm(target);
  } else {
    throw Error(Errc::kInvalidArgument,
                path.string() + ": unknown image type '" + ext + "' (use .png or .ppm)");
  }
  io::write_file_replacing(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace mosaic
