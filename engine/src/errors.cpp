// errors.cpp — mosaic::Error and printable(): error text that is safe to show on a terminal.
#include "mosaic/errors.hpp"

#include <cstdint>

namespace mosaic {

namespace {

// Length of the well-formed UTF-8 sequence at the start of `s` (1 to 4), or 0 if it is not one:
// overlong forms, surrogates and code points past U+10FFFF are not well formed (Unicode 15,
// table 3-7).
std::size_t utf8_sequence(std::string_view s) {
  const auto byte = [&](std::size_t i) { return static_cast<std::uint8_t>(s[i]); };
  const std::uint8_t b0 = byte(0);
  if (b0 < 0x80) return 1;
  std::size_t n = 0;
  std::uint8_t lo = 0x80, hi = 0xbf;  // the second byte's range
  if (b0 >= 0xc2 && b0 <= 0xdf) {
    n = 2;
  } else if (b0 >= 0xe0 && b0 <= 0xef) {
    n = 3;
    if (b0 == 0xe0) lo = 0xa0;  // overlong
    if (b0 == 0xed) hi = 0x9f;  // surrogates
  } else if (b0 >= 0xf0 && b0 <= 0xf4) {
    n = 4;
    if (b0 == 0xf0) lo = 0x90;  // overlong
    if (b0 == 0xf4) hi = 0x8f;  // past U+10FFFF
  } else {
    return 0;
  }
  if (s.size() < n || byte(1) < lo || byte(1) > hi) return 0;
  for (std::size_t i = 2; i < n; ++i)
    if (byte(i) < 0x80 || byte(i) > 0xbf) return 0;
  return n;
}

void append_hex(std::string& out, std::uint8_t b) {
  static constexpr char kHex[] = "0123456789abcdef";
  out += "\\x";
  out += kHex[b >> 4];
  out += kHex[b & 0xf];
}

}  // namespace

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  while (!text.empty()) {
    const std::size_t n = utf8_sequence(text);
    const auto b0 = static_cast<std::uint8_t>(text[0]);
    // C1 controls (U+0080 to U+009F) are two bytes, 0xc2 0x80 to 0xc2 0x9f.
    const bool c1 = n == 2 && b0 == 0xc2 && static_cast<std::uint8_t>(text[1]) <= 0x9f;
    if (n == 0 || c1 || b0 < 0x20 || b0 == 0x7f) {
      for (std::size_t i = 0; i < (c1 ? 2 : 1); ++i)
        append_hex(out, static_cast<std::uint8_t>(text[i]));
      text.remove_prefix(c1 ? 2 : 1);
    } else {
      out.append(text.substr(0, n));
      text.remove_prefix(n);
    }
  }
  return out;
}

Error::Error(Errc code, const std::string& message)
    : std::runtime_error(printable(message)), code_(code) {}

}  // namespace mosaic
