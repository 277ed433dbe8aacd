// simd/mask.hpp — lane masks as integers, for each instruction set mosaic compiles.
//
// xsimd 8 has no portable batch_bool <-> bit-mask conversion, so this is where the
// instructions are named: movmskps on SSE and AVX2, k-registers on AVX-512. Lane i is bit i.
// Also here, for the same reason: rounding double lanes to float precision (to_float()), and
// packing the lanes a mask selects into the low lanes, in order (compress()), each lane's bit of
// four 64-bit masks (pixel_nibbles()), and, where the set has it, storing lanes to computed
// addresses (scatter()).
#pragma once

#include <array>
#include <cstdint>
#include <xsimd/xsimd.hpp>

namespace mosaic::simd {

namespace detail {
// compress() on AVX2: for each 8-bit mask, the source lane of each packed lane, 4 bits each
// (lane i in bits 4i .. 4i + 3), for vpermd. Lanes past the mask's count take lane 0.
inline constexpr std::array<std::uint32_t, 256> kCompress8 = [] {
  std::array<std::uint32_t, 256> t{};
  for (unsigned m = 0; m < 256; ++m) {
    unsigned k = 0;
    for (unsigned l = 0; l < 8; ++l)
      if (m >> l & 1u) t[m] |= l << (4 * k++);
  }
  return t;
}();
// compress() on SSE4.1: for each 4-bit mask, the pshufb control that packs its lanes' bytes.
inline constexpr std::array<std::array<std::uint8_t, 16>, 16> kCompress4 = [] {
  std::array<std::array<std::uint8_t, 16>, 16> t{};
  for (unsigned m = 0; m < 16; ++m) {
    unsigned k = 0;
    for (unsigned l = 0; l < 4; ++l) {
      if (!(m >> l & 1u)) continue;
      for (unsigned b = 0; b < 4; ++b) t[m][4 * k + b] = static_cast<std::uint8_t>(4 * l + b);
      ++k;
    }
    for (; k < 4; ++k)
      for (unsigned b = 0; b < 4; ++b) t[m][4 * k + b] = static_cast<std::uint8_t>(b);
  }
  return t;
}();
#if XSIMD_WITH_SSE4_1
// The rows 4 * half .. 4 * half + 3 of four 8×8 bit masks (a byte a row), one 32-bit word a row:
// byte k of row r's word is row r of words[k]. Bit c of byte k is then pixel (c, r) of mask k.
inline __m128i row_words(const std::uint64_t* words, int half) {
  const auto row_bytes = [&](int k) {
    return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(words + k));
  };
  const __m128i w01 = _mm_unpacklo_epi8(row_bytes(0), row_bytes(1));  // rows' bytes of 0 and 1
  const __m128i w23 = _mm_unpacklo_epi8(row_bytes(2), row_bytes(3));
  return half == 0 ? _mm_unpacklo_epi16(w01, w23) : _mm_unpackhi_epi16(w01, w23);
}
#endif
}  // namespace detail

template <class A>
struct Mask;

#if XSIMD_WITH_AVX512BW
template <>
struct Mask<xsimd::avx512bw> {
  using A = xsimd::avx512bw;
  static std::uint32_t bits(const xsimd::batch_bool<std::int32_t, A>& m) {
    return static_cast<__mmask16>(m);
  }
  static std::uint32_t bits(const xsimd::batch_bool<float, A>& m) {
    return static_cast<__mmask16>(m);
  }
  static std::uint32_t bits(const xsimd::batch_bool<double, A>& m) {
    return static_cast<__mmask8>(m);
  }
  /// Each lane rounded to float and back, with the ISA's conversion instructions. A generic
  /// store, convert-each-lane, load came out of GCC 12 -O3 without the rounding, and the depth
  /// planes of clip-space draws differed from the scalar setup's (found by test_front_simd; not
  /// reduced to a minimal case, so whether the compiler or that code was at fault is not known).
  static xsimd::batch<double, A> to_float(const xsimd::batch<double, A>& v) {
    return _mm512_cvtps_pd(_mm512_cvtpd_ps(v));
  }
  /// Lanes whose sign bit is set.
  static std::uint32_t signs(const xsimd::batch<std::int32_t, A>& v) {
    return _mm512_movepi32_mask(v);
  }
  static std::uint32_t signs(const xsimd::batch<double, A>& v) {
    return _mm512_movepi64_mask(_mm512_castpd_si512(v));
  }
  /// Bit j set where bits 16 j .. 16 j + 15 of m (lane group j) are not all zero.
  static std::uint32_t nonzero_groups(std::uint64_t m) {
    return _mm_test_epi16_mask(_mm_cvtsi64_si128(static_cast<long long>(m)),
                               _mm_cvtsi64_si128(static_cast<long long>(m)));
  }
  static xsimd::batch_bool<std::int32_t, A> ints(std::uint32_t b) {
    return xsimd::batch_bool<std::int32_t, A>(static_cast<__mmask16>(b));
  }
  static xsimd::batch_bool<float, A> floats(std::uint32_t b) {
    return xsimd::batch_bool<float, A>(static_cast<__mmask16>(b));
  }
  /// The lanes set in `b`, packed into the low lanes in order; the lanes above them unspecified.
  static xsimd::batch<float, A> compress(const xsimd::batch<float, A>& v, std::uint32_t b) {
    return _mm512_maskz_compress_ps(static_cast<__mmask16>(b), v);
  }
  static xsimd::batch<std::int32_t, A> compress(const xsimd::batch<std::int32_t, A>& v,
                                                std::uint32_t b) {
    return _mm512_maskz_compress_epi32(static_cast<__mmask16>(b), v);
  }
  /// Whether scatter() exists: base[index[l]] = v[l] for the lanes set in `b`, in lane order
  /// (where two lanes' indices are equal, the higher lane's value stays).
  static constexpr bool kScatter = true;
  static void scatter(std::int32_t* base, const xsimd::batch<std::int32_t, A>& index,
                      const xsimd::batch<std::int32_t, A>& v, std::uint32_t b) {
    _mm512_mask_i32scatter_epi32(base, static_cast<__mmask16>(b), index, v, 4);
  }
  /// Per lane, bit k set where bit p of words[k] is (k < 4), p the lane's value in 0..63.
  static xsimd::batch<std::int32_t, A> pixel_nibbles(const std::uint64_t* words,
                                                     const xsimd::batch<std::int32_t, A>& p) {
    const __m256i rows = _mm256_set_m128i(detail::row_words(words, 1), detail::row_words(words, 0));
    const __m512i word =
        _mm512_permutexvar_epi32(_mm512_srli_epi32(p, 3), _mm512_castsi256_si512(rows));
    const __m512i bits =
        _mm512_and_si512(_mm512_srlv_epi32(word, _mm512_and_si512(p, _mm512_set1_epi32(7))),
                         _mm512_set1_epi32(0x01010101));
    return _mm512_srli_epi32(_mm512_mullo_epi32(bits, _mm512_set1_epi32(0x01020408)), 24);
  }
};
#endif

#if XSIMD_WITH_AVX2
template <>
struct Mask<xsimd::avx2> {
  using A = xsimd::avx2;
  static std::uint32_t bits(const xsimd::batch_bool<std::int32_t, A>& m) {
    return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_castsi256_ps(m)));
  }
  static std::uint32_t bits(const xsimd::batch_bool<float, A>& m) {
    return static_cast<std::uint32_t>(_mm256_movemask_ps(m));
  }
  static std::uint32_t bits(const xsimd::batch_bool<double, A>& m) {
    return static_cast<std::uint32_t>(_mm256_movemask_pd(m));
  }
  /// Each lane rounded to float and back (see Mask<avx512bw>::to_float).
  static xsimd::batch<double, A> to_float(const xsimd::batch<double, A>& v) {
    return _mm256_cvtps_pd(_mm256_cvtpd_ps(v));
  }
  /// Lanes whose sign bit is set.
  static std::uint32_t signs(const xsimd::batch<std::int32_t, A>& v) {
    return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_castsi256_ps(v)));
  }
  static std::uint32_t signs(const xsimd::batch<double, A>& v) {
    return static_cast<std::uint32_t>(_mm256_movemask_pd(v));
  }
  /// Bit j set where byte j of m (lane group j) is not zero.
  static std::uint32_t nonzero_groups(std::uint64_t m) {
    const __m128i bytes = _mm_cvtsi64_si128(static_cast<long long>(m));
    const auto zero =
        static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(bytes, _mm_setzero_si128())));
    return ~zero & 0xffu;
  }
  static __m256i expand(std::uint32_t b) {
    const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(b)), lane_bit),
                              lane_bit);
  }
  static xsimd::batch_bool<std::int32_t, A> ints(std::uint32_t b) { return expand(b); }
  static xsimd::batch_bool<float, A> floats(std::uint32_t b) {
    return _mm256_castsi256_ps(expand(b));
  }
  /// compress()'s vpermd indices for mask `b`, unpacked from its table entry.
  static __m256i compress_index(std::uint32_t b) {
    const __m256i nibbles = _mm256_set1_epi32(static_cast<int>(detail::kCompress8[b & 0xffu]));
    const __m256i shifts = _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28);
    return _mm256_and_si256(_mm256_srlv_epi32(nibbles, shifts), _mm256_set1_epi32(7));
  }
  /// The lanes set in `b`, packed into the low lanes in order; the lanes above them unspecified.
  static xsimd::batch<float, A> compress(const xsimd::batch<float, A>& v, std::uint32_t b) {
    return _mm256_permutevar8x32_ps(v, compress_index(b));
  }
  static xsimd::batch<std::int32_t, A> compress(const xsimd::batch<std::int32_t, A>& v,
                                                std::uint32_t b) {
    return _mm256_permutevar8x32_epi32(v, compress_index(b));
  }
  static constexpr bool kScatter = false;  ///< AVX2 has gathers only
  /// Per lane, bit k set where bit p of words[k] is (k < 4), p the lane's value in 0..63.
  static xsimd::batch<std::int32_t, A> pixel_nibbles(const std::uint64_t* words,
                                                     const xsimd::batch<std::int32_t, A>& p) {
    const __m128i rows = detail::row_words(words, 0), rows_high = detail::row_words(words, 1);
    const __m256i word =
        _mm256_permutevar8x32_epi32(_mm256_set_m128i(rows_high, rows), _mm256_srli_epi32(p, 3));
    const __m256i bits =
        _mm256_and_si256(_mm256_srlv_epi32(word, _mm256_and_si256(p, _mm256_set1_epi32(7))),
                         _mm256_set1_epi32(0x01010101));
    return _mm256_srli_epi32(_mm256_mullo_epi32(bits, _mm256_set1_epi32(0x01020408)), 24);
  }
};
#endif

#if XSIMD_WITH_SSE4_1
template <>
struct Mask<xsimd::sse4_1> {
  using A = xsimd::sse4_1;
  static std::uint32_t bits(const xsimd::batch_bool<std::int32_t, A>& m) {
    return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(m)));
  }
  static std::uint32_t bits(const xsimd::batch_bool<float, A>& m) {
    return static_cast<std::uint32_t>(_mm_movemask_ps(m));
  }
  static std::uint32_t bits(const xsimd::batch_bool<double, A>& m) {
    return static_cast<std::uint32_t>(_mm_movemask_pd(m));
  }
  /// Each lane rounded to float and back (see Mask<avx512bw>::to_float).
  static xsimd::batch<double, A> to_float(const xsimd::batch<double, A>& v) {
    return _mm_cvtps_pd(_mm_cvtpd_ps(v));
  }
  /// Lanes whose sign bit is set.
  static std::uint32_t signs(const xsimd::batch<std::int32_t, A>& v) {
    return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(v)));
  }
  static std::uint32_t signs(const xsimd::batch<double, A>& v) {
    return static_cast<std::uint32_t>(_mm_movemask_pd(v));
  }
  /// Bit j set where bits 4 j .. 4 j + 3 of m (lane group j) are not all zero.
  static std::uint32_t nonzero_groups(std::uint64_t m) {
    std::uint32_t g = 0;
    for (int j = 0; j < 16; ++j) g |= std::uint32_t{((m >> (4 * j)) & 0xfu) != 0} << j;
    return g;
  }
  static __m128i expand(std::uint32_t b) {
    const __m128i lane_bit = _mm_setr_epi32(1, 2, 4, 8);
    return _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(static_cast<int>(b)), lane_bit), lane_bit);
  }
  static xsimd::batch_bool<std::int32_t, A> ints(std::uint32_t b) { return expand(b); }
  static xsimd::batch_bool<float, A> floats(std::uint32_t b) { return _mm_castsi128_ps(expand(b)); }
  /// The lanes set in `b`, packed into the low lanes in order; the lanes above them unspecified.
  static xsimd::batch<std::int32_t, A> compress(const xsimd::batch<std::int32_t, A>& v,
                                                std::uint32_t b) {
    const __m128i control =
        _mm_loadu_si128(reinterpret_cast<const __m128i*>(detail::kCompress4[b & 0xfu].data()));
    return _mm_shuffle_epi8(v, control);
  }
  static xsimd::batch<float, A> compress(const xsimd::batch<float, A>& v, std::uint32_t b) {
    return _mm_castsi128_ps(compress(xsimd::batch<std::int32_t, A>(_mm_castps_si128(v)), b));
  }
  static constexpr bool kScatter = false;
  /// Per lane, bit k set where bit p of words[k] is (k < 4), p the lane's value in 0..63. SSE4.1
  /// has no variable shift: a multiply by 1 << (7 - column) moves the column's bit to bit 7 of
  /// each byte of the row's word.
  static xsimd::batch<std::int32_t, A> pixel_nibbles(const std::uint64_t* words,
                                                     const xsimd::batch<std::int32_t, A>& p) {
    const __m128i row = _mm_srli_epi32(p, 3), col = _mm_and_si128(p, _mm_set1_epi32(7));
    // Row r's word is dword r % 4 of the low or high rows: pshufb bytes 4 (r % 4) .. + 3.
    const __m128i pick = _mm_add_epi32(
        _mm_mullo_epi32(_mm_and_si128(row, _mm_set1_epi32(3)), _mm_set1_epi32(0x04040404)),
        _mm_set1_epi32(0x03020100));
    const __m128i word = _mm_blendv_epi8(_mm_shuffle_epi8(detail::row_words(words, 0), pick),
                                         _mm_shuffle_epi8(detail::row_words(words, 1), pick),
                                         _mm_cmpgt_epi32(row, _mm_set1_epi32(3)));
    const __m128i powers = _mm_setr_epi8(-128, 64, 32, 16, 8, 4, 2, 1, 0, 0, 0, 0, 0, 0, 0, 0);
    const __m128i multiplier =
        _mm_shuffle_epi8(powers, _mm_or_si128(col, _mm_set1_epi32(static_cast<int>(0x80808000))));
    const __m128i top = _mm_and_si128(_mm_mullo_epi32(word, multiplier),
                                      _mm_set1_epi32(static_cast<int>(0x80808080)));
    return _mm_srli_epi32(_mm_mullo_epi32(_mm_srli_epi32(top, 7), _mm_set1_epi32(0x01020408)), 24);
  }
};
#endif

}  // namespace mosaic::simd
