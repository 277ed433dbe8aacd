// io/write_file.hpp — writing an output file so that a failure never leaves half of it behind.
//
// Takes: a path and the file's bytes. Gives: the file, complete, or an Error{kIo} naming the path
// with the original file (if any) left as it was. Used by every writer (.tris, PNG, PPM).
#pragma once

#include <filesystem>
#include <string_view>

namespace mosaic::io {

/// Writes `bytes` to a new temporary file next to `path` (so the rename stays on one file
/// system) and renames it over `path`. Throws Error{kIo} with the path and the system's reason.
/// A symlink at `path` is replaced by the file, and what it pointed to is left alone: a link
/// planted where output goes can never redirect the write.
void write_file_replacing(const std::filesystem::path& path, std::string_view bytes);

}  // namespace mosaic::io
