// io/numbers.hpp — reading the numbers of a scene file.
//
// Takes: one token. Gives: for one that std::from_chars found out of range, whether it is too
// small (so a zero to the renderer) rather than too large, which the .tris and OBJ readers both
// need; and the OBJ reader's fast path for short decimals.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
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

/// A plain decimal `[-]digits[.digits]` whose digits make an integer m <= 2^24 with k <= 10 of
/// them after the point, read as m / 10^k: m and 10^k are floats exactly, so one division rounds
/// correctly, as from_chars does, at a fraction of its cost. False for anything else.
inline bool read_short_decimal(std::string_view w, float& value) {
  constexpr std::uint32_t kMaxExact = 1u << 24;  // every integer up to 2^24 is a float exactly
  constexpr float kPow10[] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f, 1e7f, 1e8f, 1e9f, 1e10f};
  constexpr std::size_t kMaxFraction = std::size(kPow10) - 1;
  std::size_t i = !w.empty() && w[0] == '-' ? 1 : 0;
  const bool negative = i == 1;
  std::uint32_t m = 0;
  std::size_t digits = 0, fraction = 0;
  bool point = false;
  for (; i < w.size(); ++i) {
    const char ch = w[i];
    if (ch == '.' && !point) {
      point = true;
      continue;
    }
    if (ch < '0' || ch > '9') return false;
    m = m * 10 + static_cast<std::uint32_t>(ch - '0');
    if (m > kMaxExact) return false;
    ++digits;
    fraction += point ? 1 : 0;
  }
  if (digits == 0 || fraction > kMaxFraction) return false;
  const float q = static_cast<float>(m) / kPow10[fraction];
  value = negative ? -q : q;
  return true;
}

}  // namespace mosaic::io
