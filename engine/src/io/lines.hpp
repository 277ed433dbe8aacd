// io/lines.hpp — the lines of a scene file, each bounded in length.
//
// Takes: a file's text and its name. Gives: its lines in order with their numbers; a line ends
// at LF, CR LF or a CR alone. A line longer than kMaxLineBytes is an Error{kParse} naming it,
// thrown before the loader looks at it, so no line's work grows without bound.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>

#include "mosaic/errors.hpp"

namespace mosaic::io {

/// The longest line of a scene file: 1 MiB. A .tris `tri` line needs about 300 bytes and an OBJ
/// face of 255 vertices about 9 KB; anything near the bound is garbage.
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

class LineReader {
 public:
  LineReader(std::string_view text, const std::string& file)
      : text_(text), file_(file), has_cr_(text.find('\r') != std::string_view::npos) {}

  /// The next line in `line` (without its end), or false at the end of the text.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    // The LF, then a CR before it if the text has any (find_first_of would look each byte up
    // in the set with a call of its own).
    std::size_t eol = std::min(text_.find('\n', pos_), text_.size());
    if (has_cr_) eol = std::min(text_.substr(0, eol).find('\r', pos_), eol);
    ++line_no_;
    if (eol - pos_ > kMaxLineBytes)
      throw Error(Errc::kParse, file_ + ":" + std::to_string(line_no_) + ": a line of " +
                                    std::to_string(eol - pos_) + " bytes, longer than the " +
                                    std::to_string(kMaxLineBytes) + " a line may have");
    line = text_.substr(pos_, eol - pos_);
    pos_ = eol + (text_.compare(eol, 2, "\r\n") == 0 ? 2 : 1);
    return true;
  }
  /// The number of the line next() returned last, from 1.
  std::size_t line_no() const { return line_no_; }

 private:
  std::string_view text_;
  const std::string& file_;
  bool has_cr_;  ///< whether any line ends in a CR (CR LF, or a CR alone)
  std::size_t pos_ = 0, line_no_ = 0;
};

}  // namespace mosaic::io
