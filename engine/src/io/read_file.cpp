// io/read_file.cpp — see read_file.hpp.
#include "io/read_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <system_error>

#include "mosaic/errors.hpp"

namespace mosaic::io {

std::string read_scene_file(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st))
    throw Error(Errc::kIo, file + ": cannot open: " +
                               (ec ? ec.message() : std::string(std::strerror(ENOENT))));
  if (std::filesystem::is_directory(st))
    throw Error(Errc::kIo, file + ": cannot open: it is a directory");
  if (!std::filesystem::is_regular_file(st))
    throw Error(Errc::kIo, file + ": cannot open: not a regular file (a device, pipe or socket)");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(Errc::kIo, file + ": cannot open: " + ec.message());
  if (size > kMaxSceneFileBytes)
    throw Error(Errc::kIo, file + ": " + std::to_string(size) + " bytes, more than the " +
                               std::to_string(kMaxSceneFileBytes) + " a scene file may have");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(Errc::kIo, file + ": cannot open: " + std::strerror(errno));
  // Read what the size said, and one byte more to see whether the file grew meanwhile.
  std::string text(static_cast<std::size_t>(size) + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw Error(Errc::kIo, file + ": read error");
  const auto got = static_cast<std::size_t>(in.gcount());
  if (got > size) throw Error(Errc::kIo, file + ": it grew while it was read");
  text.resize(got);
  return text;
}

void check_scene_memory(const std::string& file, std::uintmax_t triangles,
                        std::uintmax_t bytes_per_triangle) {
  constexpr std::uintmax_t kMaxTriangles = std::numeric_limits<std::uint32_t>::max() / 3;
  if (triangles > kMaxTriangles || triangles * bytes_per_triangle > kMaxSceneMeshBytes)
    throw Error(Errc::kParse, file + ": " + std::to_string(triangles) + " triangles need " +
                                  std::to_string(triangles * bytes_per_triangle) +
                                  " bytes, more than the " + std::to_string(kMaxSceneMeshBytes) +
                                  " a scene may take");
}

}  // namespace mosaic::io
