// mosaic/errors.hpp — the one error type every mosaic entry point throws.
//
// Takes: nothing. Gives: mosaic::Error, an exception carrying an Errc code and a one-line message.
// Every function that can reject input validates all of it before it writes anything, so a
// thrown Error leaves the render target, and any output file, exactly as it was. Its text is
// printable(): the input it quotes cannot drive the terminal it is shown on.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

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

/// `text` made safe to print on a terminal: control characters (C0, DEL and C1, so also line
/// ends and escape sequences) and bytes that are not well-formed UTF-8 become `\xNN`, one per
/// byte; everything else, backslashes included, is kept. Applying it twice changes nothing more.
std::string printable(std::string_view text);

/// A rejected input. `what()` is a single line, fit to print as is: the message passes through
/// printable(), so input it quotes (a file name, a token) cannot reach a terminal raw.
class Error : public std::runtime_error {
 public:
  /// An error of kind `code`; `message` should be one line that names what was rejected.
  Error(Errc code, const std::string& message);
  /// The category of the rejection, for programs that react to it.
  Errc code() const noexcept { return code_; }

 private:
  Errc code_;
};

}  // namespace mosaic
