// simd/mask.hpp — lane masks as integers, for each instruction set mosaic compiles.
//
// xsimd 8 has no portable batch_bool <-> bit-mask conversion, so this is where the
// instructions are named: movmskps on SSE and AVX2, k-registers on AVX-512. Lane i is bit i.
// Also here, for the same reason: rounding double lanes to float precision (to_float()),
// converting between float memory and double lanes (widen(), narrow()), and
// packing the lanes a mask selects into the low lanes, in order (compress()), the box mean of
// each pixel's RGBA8 samples (means(): the resolve), integer gathers (gather(): xsimd 8's reads
// a lane at a time) and a pixel's four samples stored under a mask (store_samples4()).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
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
// For each 4-bit mask, the 32-bit lanes it selects (all ones) for a 128-bit blend.
inline constexpr std::array<std::array<std::int32_t, 4>, 16> kLanes4 = [] {
  std::array<std::array<std::int32_t, 4>, 16> t{};
  for (unsigned m = 0; m < 16; ++m)
    for (unsigned l = 0; l < 4; ++l) t[m][l] = (m >> l & 1u) ? -1 : 0;
  return t;
}();
#if XSIMD_WITH_AVX2
// The channel sums of the four RGBA8 samples in each 128-bit half of v: r, g, b, a as int32
// (bytes gathered by channel, then added in pairs twice).
inline __m256i quad_sums256(__m256i v) {
  const __m256i by_channel = _mm256_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15,
                                              0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15);
  return _mm256_madd_epi16(
      _mm256_maddubs_epi16(_mm256_shuffle_epi8(v, by_channel), _mm256_set1_epi8(1)),
      _mm256_set1_epi16(1));
}
// means<S>() of eight pixels, S 256-bit vectors of their samples, pixel-major.
template <int S>
inline __m256i means256(const __m256i* v) {
  constexpr int kShift = S == 4 ? 2 : S == 8 ? 3 : 4;
  static_assert(S == 4 || S == 8 || S == 16);
  __m256i mean[4];  // pixel 2k's r, g, b, a means in mean[k]'s low 128-bit half, 2k + 1's above
  for (int k = 0; k < 4; ++k) {
    __m256i sums;
    if constexpr (S == 4) {
      sums = quad_sums256(v[k]);
    } else {
      constexpr int kPer = S / 8;  // vectors a pixel
      __m256i a = quad_sums256(v[2 * k * kPer]), b = quad_sums256(v[(2 * k + 1) * kPer]);
      for (int i = 1; i < kPer; ++i) {
        a = _mm256_add_epi32(a, quad_sums256(v[2 * k * kPer + i]));
        b = _mm256_add_epi32(b, quad_sums256(v[(2 * k + 1) * kPer + i]));
      }
      sums = _mm256_add_epi32(_mm256_permute2x128_si256(a, b, 0x20),
                              _mm256_permute2x128_si256(a, b, 0x31));
    }
    mean[k] = _mm256_srli_epi32(_mm256_add_epi32(sums, _mm256_set1_epi32(S / 2)), kShift);
  }
  // The packs work within 128-bit halves: pixels 0, 2, 4, 6 below and 1, 3, 5, 7 above.
  const __m256i bytes = _mm256_packus_epi16(_mm256_packus_epi32(mean[0], mean[1]),
                                            _mm256_packus_epi32(mean[2], mean[3]));
  return _mm256_permutevar8x32_epi32(bytes, _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7));
}
#endif
}  // namespace detail

#if XSIMD_WITH_SSE4_1
/// `value` into words[k] for each bit k of bits (0..15) and the other three words left as they
/// are: one 128-bit load, blend and store (every instruction set mosaic compiles has SSE4.1).
[[gnu::always_inline]] inline void store_samples4(std::uint32_t* words, std::uint32_t value,
                                                  std::uint32_t bits) {
  auto* at = reinterpret_cast<__m128i*>(words);
  const __m128i lanes =
      _mm_loadu_si128(reinterpret_cast<const __m128i*>(detail::kLanes4[bits & 0xfu].data()));
  _mm_storeu_si128(
      at, _mm_blendv_epi8(_mm_loadu_si128(at), _mm_set1_epi32(static_cast<int>(value)), lanes));
}
#endif

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
  /// kDLanes floats from p as double lanes (exact), and double lanes stored to p as floats.
  static xsimd::batch<double, A> widen(const float* p) {
    return _mm512_cvtps_pd(_mm256_loadu_ps(p));
  }
  static void narrow(float* p, const xsimd::batch<double, A>& v) {
    _mm256_storeu_ps(p, _mm512_cvtpd_ps(v));
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
  /// Bit p set where nibble p of words[0 .. 4) (laid end to end, little-endian) is not zero: at
  /// 4x, the pixels of a block with a sample set (raster/tile.hpp).
  static std::uint64_t nonzero_nibbles(const std::uint64_t* words) {
    // Byte b to word b, its low nibble to the word's low byte and its high nibble to the high.
    const __m512i w =
        _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(words)));
    const __m512i nibbles =
        _mm512_and_si512(_mm512_or_si512(w, _mm512_slli_epi16(w, 4)), _mm512_set1_epi16(0x0f0f));
    return _mm512_test_epi8_mask(nibbles, nibbles);
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
  /// Lane l: lane idx[l] of v (0 <= idx[l] < L).
  static xsimd::batch<std::int32_t, A> permute(const xsimd::batch<std::int32_t, A>& v,
                                               const xsimd::batch<std::int32_t, A>& idx) {
    return _mm512_permutexvar_epi32(idx, v);
  }
  /// Lane l: base[idx[l]]. (xsimd 8's integer gather falls back to a lane at a time, each
  /// index read back through a store of the whole vector.)
  static xsimd::batch<std::int32_t, A> gather(const std::int32_t* base,
                                              const xsimd::batch<std::int32_t, A>& idx) {
    return _mm512_i32gather_epi32(idx, base, 4);
  }
  static xsimd::batch<std::int32_t, A> compress(const xsimd::batch<std::int32_t, A>& v,
                                                std::uint32_t b) {
    return _mm512_maskz_compress_epi32(static_cast<__mmask16>(b), v);
  }
  /// Lane i: the box mean of pixel i's S RGBA8 samples (S = 4, 8, 16), v[0 .. S) holding the L
  /// pixels' samples pixel-major: per byte (sum + S / 2) / S, as resolve::box_mean().
  template <int S>
  static xsimd::batch<std::int32_t, A> means(const xsimd::batch<std::int32_t, A>* v) {
    const auto eight = [&](int first) {  // pixels 8 * first / S on, from 256-bit halves
      __m256i w[S];
      for (int i = 0; i < S / 2; ++i) {
        w[2 * i] = _mm512_castsi512_si256(v[first + i]);
        w[2 * i + 1] = _mm512_extracti64x4_epi64(v[first + i], 1);
      }
      return detail::means256<S>(w);
    };
    return _mm512_inserti64x4(_mm512_castsi256_si512(eight(0)), eight(S / 2), 1);
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
  /// See Mask<avx512bw>::widen and narrow.
  static xsimd::batch<double, A> widen(const float* p) { return _mm256_cvtps_pd(_mm_loadu_ps(p)); }
  static void narrow(float* p, const xsimd::batch<double, A>& v) {
    _mm_storeu_ps(p, _mm256_cvtpd_ps(v));
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
  /// Bit p set where nibble p of words[0 .. 4) (laid end to end, little-endian) is not zero: at
  /// 4x, the pixels of a block with a sample set (raster/tile.hpp).
  static std::uint64_t nonzero_nibbles(const std::uint64_t* words) {
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(words));
    const __m256i low = _mm256_set1_epi8(0x0f), zero = _mm256_setzero_si256();
    const __m256i lo = _mm256_and_si256(x, low),
                  hi = _mm256_and_si256(_mm256_srli_epi16(x, 4), low);
    // A byte per nibble, in order within each 128-bit half: nibbles 0-15 and 32-47 in `a`,
    // 16-31 and 48-63 in `b`.
    const auto a = static_cast<std::uint32_t>(
        _mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_unpacklo_epi8(lo, hi), zero)));
    const auto b = static_cast<std::uint32_t>(
        _mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_unpackhi_epi8(lo, hi), zero)));
    const std::uint64_t empty = (a & 0xffffu) | std::uint64_t{b & 0xffffu} << 16 |
                                std::uint64_t{a >> 16} << 32 | std::uint64_t{b >> 16} << 48;
    return ~empty;
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
  /// Lane l: lane idx[l] of v (0 <= idx[l] < L).
  static xsimd::batch<std::int32_t, A> permute(const xsimd::batch<std::int32_t, A>& v,
                                               const xsimd::batch<std::int32_t, A>& idx) {
    return _mm256_permutevar8x32_epi32(v, idx);
  }
  /// Lane l: base[idx[l]] (see Mask<avx512bw>::gather()).
  static xsimd::batch<std::int32_t, A> gather(const std::int32_t* base,
                                              const xsimd::batch<std::int32_t, A>& idx) {
    return _mm256_i32gather_epi32(base, idx, 4);
  }
  static xsimd::batch<std::int32_t, A> compress(const xsimd::batch<std::int32_t, A>& v,
                                                std::uint32_t b) {
    return _mm256_permutevar8x32_epi32(v, compress_index(b));
  }
  /// Lane i: the box mean of pixel i's S RGBA8 samples (S = 4, 8, 16), v[0 .. S) holding the L
  /// pixels' samples pixel-major: per byte (sum + S / 2) / S, as resolve::box_mean().
  template <int S>
  static xsimd::batch<std::int32_t, A> means(const xsimd::batch<std::int32_t, A>* v) {
    __m256i w[S];
    for (int i = 0; i < S; ++i) w[i] = v[i];
    return detail::means256<S>(w);
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
  /// See Mask<avx512bw>::widen and narrow.
  static xsimd::batch<double, A> widen(const float* p) {
    double two;  // two floats' bytes
    std::memcpy(&two, p, sizeof two);
    return _mm_cvtps_pd(_mm_castpd_ps(_mm_set_sd(two)));
  }
  static void narrow(float* p, const xsimd::batch<double, A>& v) {
    const double two = _mm_cvtsd_f64(_mm_castps_pd(_mm_cvtpd_ps(v)));
    std::memcpy(p, &two, sizeof two);
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
    __m128i low, high;  // (high: the zero upper half of the register, unused)
    nibble_bytes(_mm_cvtsi64_si128(static_cast<long long>(m)), low, high);
    return ~zero_bytes(low) & 0xffffu;
  }
  /// Bit p set where nibble p of words[0 .. 4) (laid end to end, little-endian) is not zero: at
  /// 4x, the pixels of a block with a sample set (raster/tile.hpp).
  static std::uint64_t nonzero_nibbles(const std::uint64_t* words) {
    std::uint64_t empty = 0;
    for (int h = 0; h < 2; ++h) {  // 16 bytes: nibbles 32 h .. 32 h + 31, a byte each
      __m128i low, high;
      nibble_bytes(_mm_loadu_si128(reinterpret_cast<const __m128i*>(words + 2 * h)), low, high);
      empty |= (zero_bytes(low) | std::uint64_t{zero_bytes(high)} << 16) << (32 * h);
    }
    return ~empty;
  }
  /// The 32 nibbles of x, a byte each, in order: the low nibble of byte i to byte 2i, its high
  /// nibble to byte 2i + 1; those of x's low 8 bytes in `low`, of its high 8 in `high`.
  static void nibble_bytes(__m128i x, __m128i& low, __m128i& high) {
    const __m128i mask = _mm_set1_epi8(0x0f);
    const __m128i lo = _mm_and_si128(x, mask), hi = _mm_and_si128(_mm_srli_epi16(x, 4), mask);
    low = _mm_unpacklo_epi8(lo, hi);
    high = _mm_unpackhi_epi8(lo, hi);
  }
  /// Bit j set where byte j of v is zero.
  static std::uint32_t zero_bytes(__m128i v) {
    return static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_setzero_si128())));
  }
  static __m128i expand(std::uint32_t b) {
    const __m128i lane_bit = _mm_setr_epi32(1, 2, 4, 8);
    return _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(static_cast<int>(b)), lane_bit), lane_bit);
  }
  static xsimd::batch_bool<std::int32_t, A> ints(std::uint32_t b) { return expand(b); }
  static xsimd::batch_bool<float, A> floats(std::uint32_t b) { return _mm_castsi128_ps(expand(b)); }
  /// The lanes set in `b`, packed into the low lanes in order; the lanes above them unspecified.
  /// Lane l: lane idx[l] of v (0 <= idx[l] < L).
  static xsimd::batch<std::int32_t, A> permute(const xsimd::batch<std::int32_t, A>& v,
                                               const xsimd::batch<std::int32_t, A>& idx) {
    // The bytes 4 idx .. 4 idx + 3 of each lane, for pshufb.
    const __m128i bytes =
        _mm_add_epi32(_mm_mullo_epi32(idx, _mm_set1_epi32(0x04040404)), _mm_set1_epi32(0x03020100));
    return _mm_shuffle_epi8(v, bytes);
  }
  /// Lane l: base[idx[l]] (see Mask<avx512bw>::gather()).
  static xsimd::batch<std::int32_t, A> gather(const std::int32_t* base,
                                              const xsimd::batch<std::int32_t, A>& idx) {
    return _mm_setr_epi32(base[_mm_cvtsi128_si32(idx)], base[_mm_extract_epi32(idx, 1)],
                          base[_mm_extract_epi32(idx, 2)], base[_mm_extract_epi32(idx, 3)]);
  }
  static xsimd::batch<std::int32_t, A> compress(const xsimd::batch<std::int32_t, A>& v,
                                                std::uint32_t b) {
    const __m128i control =
        _mm_loadu_si128(reinterpret_cast<const __m128i*>(detail::kCompress4[b & 0xfu].data()));
    return _mm_shuffle_epi8(v, control);
  }
  static xsimd::batch<float, A> compress(const xsimd::batch<float, A>& v, std::uint32_t b) {
    return _mm_castsi128_ps(compress(xsimd::batch<std::int32_t, A>(_mm_castps_si128(v)), b));
  }
  /// Lane i: the box mean of pixel i's S RGBA8 samples (S = 4, 8, 16), v[0 .. S) holding the L
  /// pixels' samples pixel-major: per byte (sum + S / 2) / S, as resolve::box_mean().
  template <int S>
  static xsimd::batch<std::int32_t, A> means(const xsimd::batch<std::int32_t, A>* v) {
    static_assert(S == 4 || S == 8 || S == 16);
    constexpr int kShift = S == 4 ? 2 : S == 8 ? 3 : 4, kPer = S / 4;  // vectors a pixel
    // A vector is four samples: their r bytes, then g, b and a, added in pairs twice.
    const __m128i by_channel = _mm_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15);
    const auto quad_sums = [&](__m128i q) {
      return _mm_madd_epi16(_mm_maddubs_epi16(_mm_shuffle_epi8(q, by_channel), _mm_set1_epi8(1)),
                            _mm_set1_epi16(1));
    };
    __m128i mean[4];
    for (int p = 0; p < 4; ++p) {
      __m128i sums = quad_sums(v[p * kPer]);
      for (int i = 1; i < kPer; ++i) sums = _mm_add_epi32(sums, quad_sums(v[p * kPer + i]));
      mean[p] = _mm_srli_epi32(_mm_add_epi32(sums, _mm_set1_epi32(S / 2)), kShift);
    }
    return _mm_packus_epi16(_mm_packus_epi32(mean[0], mean[1]), _mm_packus_epi32(mean[2], mean[3]));
  }
};
#endif

}  // namespace mosaic::simd
