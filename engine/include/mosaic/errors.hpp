// mosaic/errors.hpp — the one error type every mosaic entry point throws.
//
// Takes: nothing. Gives: mosaic::Error, an exception carrying an Errc code and a one-line message.
// Every function that can reject input validates all of it before it writes anything, so a
// thrown Error leaves the render target, and any output file, exactly as it was.
#pragma once

#include <stdexcept>
#include <string>

namespace mosaic {

/// What kind of input was rejected.
enum class Errc {
  kInvalidTargetSize,       ///< width or height outside [1, kMaxTargetSize]
  kUnsupportedSampleCount,  ///< samples not one of 1, 4, 8, 16
  kIndexOutOfRange,         ///< an index buffer names a vertex that does not exist
  kInvalidDraw,             ///< a draw's buffers do not fit together (counts, missing data)
  kParse,                   ///< a scene file is malformed; the message names file and line
  kIo,                      ///< a file could not be read or written
  kUnsupportedIsa,          ///< a SIMD path was requested that this CPU or build cannot run
  kInvalidArgument,         ///< any other argument outside its documented range
  kBusy,                    ///< a Renderer entered while it renders (another thread, a shader)
};

/// A rejected input. `what()` is a single line, fit to print as is.
class Error : public std::runtime_error {
 public:
  /// An error of kind `code`; `message` should be one line that names what was rejected.
  Error(Errc code, const std::string& message) : std::runtime_error(message), code_(code) {}
  /// The category of the rejection, for programs that react to it.
  Errc code() const noexcept { return code_; }

 private:
  Errc code_;
};

}  // namespace mosaic
