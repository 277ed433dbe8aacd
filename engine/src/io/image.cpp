// io/image.cpp — writing a render target's resolved image to a file.
//
// Takes: a RenderTarget and a path ending in .png or .ppm. Gives: an RGBA PNG (through
// stb_image_write, compiled in Debian's libstb) or a binary RGB PPM (P6, alpha dropped). The
// image is encoded in memory, written to a temporary file in the same folder and renamed over
// the path, so a failure never leaves a partial image.
#include <stb_image_write.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

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

std::vector<unsigned char> encode_png(const RenderTarget& target) {
  static_assert(sizeof(Rgba8) == kPngChannels, "Rgba8 must be four packed bytes");
  const int w = target.width(), h = target.height();
  // The row stride is an int: kMaxTargetSize * 4 bytes is far below INT_MAX.
  static_assert(std::int64_t{kMaxTargetSize} * kPngChannels < std::numeric_limits<int>::max());
  std::vector<unsigned char> out;
  const int ok = stbi_write_png_to_func(append_bytes, &out, w, h, kPngChannels,
                                        target.color().data(), w * kPngChannels);
  if (ok == 0) out.clear();
  return out;
}

std::vector<unsigned char> encode_ppm(const RenderTarget& target) {
  const std::string header = "P6\n" + std::to_string(target.width()) + " " +
                             std::to_string(target.height()) + "\n" + std::to_string(kPpmMaxValue) +
                             "\n";
  std::vector<unsigned char> out(header.begin(), header.end());
  out.reserve(out.size() + target.color().size() * kPpmChannels);
  for (const Rgba8& c : target.color()) {
    out.push_back(c.r);
    out.push_back(c.g);
    out.push_back(c.b);
  }
  return out;
}

/// Writes `bytes` to a new temporary file next to `path` and renames it over `path`.
/// (io/tris.cpp has the same few lines for scene files.) Throws Error{kIo}.
void write_file_replacing(const std::filesystem::path& path,
                          const std::vector<unsigned char>& bytes) {
  const std::string file = path.string();
  // A hidden name with mkstemp's unique suffix. (Built with += because GCC 12 reports a false
  // -Wrestrict on `"." + std::string` at -O3.)
  std::string tmp_name(".");
  tmp_name += path.filename().string();
  tmp_name += ".XXXXXX";
  std::string tmp = (path.parent_path() / tmp_name).string();
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) throw Error(Errc::kIo, file + ": cannot write: " + std::strerror(errno));
  std::size_t done = 0;
  int err = 0;
  while (done < bytes.size() && err == 0) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno != EINTR) err = errno;
    if (n > 0) done += static_cast<std::size_t>(n);
  }
  // mkstemp creates the file 0600; rw-r--r-- is the usual mode of a file a user writes (reading
  // the umask would mean changing it, which races with other threads).
  constexpr mode_t kFileMode = 0644;
  if (err == 0 && ::fchmod(fd, kFileMode) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && std::rename(tmp.c_str(), file.c_str()) != 0) err = errno;
  if (err != 0) {
    ::unlink(tmp.c_str());
    throw Error(Errc::kIo, file + ": cannot write: " + std::strerror(err));
  }
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
  write_file_replacing(path, bytes);
}

}  // namespace mosaic
