// io/read_file.hpp — reading a scene file whole, bounded, with an error that names the path.
//
// Takes: a path. Gives: the file's bytes, or an Error{kIo} naming the path and why: missing,
// a directory, not a regular file (a device such as /dev/zero, a pipe: they may never end), or
// larger than kMaxSceneFileBytes. Used by the .tris and OBJ loaders.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace mosaic::io {

/// The largest scene file read: 2 GiB, some 30 M triangles of .tris text. The loaders hold the
/// text and the mesh at once, so a bound on the one bounds the other.
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t{1} << 31;

/// The most memory a loaded scene's mesh may take: 4 GiB, about 70 M triangles of .tris (60 bytes
/// each), the most a 2 GiB file of the shortest `tri` lines holds.
inline constexpr std::uintmax_t kMaxSceneMeshBytes = std::uintmax_t{1} << 32;

/// Reads the regular file at `path` (symlinks followed) whole.
std::string read_scene_file(const std::filesystem::path& path);

/// Throws Error{kParse} naming `file` if `triangles` of `bytes_per_triangle` would take more than
/// kMaxSceneMeshBytes, or more than a Mesh indexes (2^32 vertices).
void check_scene_memory(const std::string& file, std::uintmax_t triangles,
                        std::uintmax_t bytes_per_triangle);

}  // namespace mosaic::io
