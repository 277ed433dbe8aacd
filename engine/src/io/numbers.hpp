// io/numbers.hpp — reading the numbers of a scene file.
//
// Takes: one token that std::from_chars found out of double's range. Gives: whether it is too
// small for a double (so a zero to the renderer) rather than too large. Shared by the .tris and
// OBJ readers, which both read a number that underflows as 0.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace mosaic::io {

/// For a number from_chars found out of double's range: whether it is too small (its decimal
/// exponent is negative) rather than too large. Only the position of the first non-zero digit
/// and the exponent are read, so 10^8 zeros cost one pass and no big arithmetic.
inline bool underflows(std::string_view t) {
  std::size_t i = (!t.empty() && (t[0] == '-' || t[0] == '+')) ? 1 : 0;
  std::int64_t lead = 0, zeros = 0;     // digits before the point from the first non-zero one,
  bool nonzero = false, point = false;  // and zeros after the point before it
  for (; i < t.size() && t[i] != 'e' && t[i] != 'E'; ++i) {
    if (t[i] == '.') {
      point = true;
    } else if (t[i] != '0' || nonzero) {
      nonzero = true;
      if (!point) ++lead;
    } else if (point) {
      ++zeros;
    }
  }
  // The exponent, saturated: no decimal exponent past +-10^15 fits a parsed double's range.
  constexpr std::int64_t kSaturate = 1'000'000'000'000'000;
  std::int64_t exp = 0;
  bool negative = false;
  if (i < t.size()) {
    ++i;
    if (i < t.size() && (t[i] == '-' || t[i] == '+')) negative = t[i++] == '-';
    for (; i < t.size(); ++i) exp = std::min(kSaturate, exp * 10 + (t[i] - '0'));
  }
  const std::int64_t magnitude = (lead > 0 ? lead - 1 : -(zeros + 1)) + (negative ? -exp : exp);
  return magnitude < 0;
}

}  // namespace mosaic::io
