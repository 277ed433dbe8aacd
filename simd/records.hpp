// simd/records.hpp — records of 64-bit words, one per double lane, turned into lanes and back.
//
// Part of simd/'s vocabulary: it includes nothing from engine/. The front end reads a batch's
// corners from the vertex stage's 32-byte records (or, to pre-cull, their first 16 bytes:
// heads()), and writes its triangles' 128-byte setups;
// loading or storing each record whole and transposing the batch's records takes a few shuffles,
// where moving each field of each lane took a load and a store (and gather instructions were
// slower on the AMD hosts measured). Words travel as the bits of double lanes; int64s(),
// pack_floats() and pack_ints() make a record's words from double lanes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <xsimd/xsimd.hpp>

namespace mosaic::simd {

template <class A>
struct Records;

#if XSIMD_WITH_AVX2
namespace detail {
// Words 0..3 of the four 32-byte records r0..r3 as four vectors of the records' words.
inline void transpose4(__m256d r0, __m256d r1, __m256d r2, __m256d r3, __m256d (&col)[4]) {
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1);  // r0[0] r1[0] r0[2] r1[2]
  const __m256d t1 = _mm256_unpackhi_pd(r0, r1);  // r0[1] r1[1] r0[3] r1[3]
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3);
  const __m256d t3 = _mm256_unpackhi_pd(r2, r3);
  col[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  col[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  col[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  col[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}
}  // namespace detail
#endif

#if XSIMD_WITH_AVX512BW
template <>
struct Records<xsimd::avx512bw> {
  using D = xsimd::batch<double, xsimd::avx512bw>;
  using F = xsimd::batch<float, xsimd::avx512bw>;
  /// col[j] lane l: 32-bit word j of record rows[l] (16-byte aligned), as float bits.
  static void heads(const void* const (&rows)[16], F (&col)[4]) {
    __m512 r[4];
    for (int l = 0; l < 4; ++l) {
      // 128-bit block b holds record l + 4 b.
      __m512 v = _mm512_castps128_ps512(head(rows[l]));
      v = _mm512_insertf32x4(v, head(rows[l + 4]), 1);
      v = _mm512_insertf32x4(v, head(rows[l + 8]), 2);
      r[l] = _mm512_insertf32x4(v, head(rows[l + 12]), 3);
    }
    const __m512 t0 = _mm512_unpacklo_ps(r[0], r[1]), t1 = _mm512_unpackhi_ps(r[0], r[1]);
    const __m512 t2 = _mm512_unpacklo_ps(r[2], r[3]), t3 = _mm512_unpackhi_ps(r[2], r[3]);
    col[0] = _mm512_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    col[1] = _mm512_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    col[2] = _mm512_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
    col[3] = _mm512_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  }
  /// col[j] lane l: word j of record rows[l] (32-byte aligned), its bits as they are.
  static void columns(const void* const (&rows)[8], D (&col)[4]) {
    __m256d lo[4], hi[4];
    detail::transpose4(load(rows[0]), load(rows[1]), load(rows[2]), load(rows[3]), lo);
    detail::transpose4(load(rows[4]), load(rows[5]), load(rows[6]), load(rows[7]), hi);
    for (int j = 0; j < 4; ++j)
      col[j] = _mm512_insertf64x4(_mm512_castpd256_pd512(lo[j]), hi[j], 1);
  }
  /// Each lane's low (first in memory) or high 32 bits, as a float widened to double.
  static D low_floats(const D& v) {
    const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 0, 0, 0, 0, 0, 0, 0, 0);
    return _mm512_cvtps_pd(
        _mm512_castps512_ps256(_mm512_permutexvar_ps(even, _mm512_castpd_ps(v))));
  }
  static D high_floats(const D& v) {
    const __m512i odd = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 0, 0, 0, 0, 0, 0, 0, 0);
    return _mm512_cvtps_pd(_mm512_castps512_ps256(_mm512_permutexvar_ps(odd, _mm512_castpd_ps(v))));
  }
  /// Record l gets words col[0][l] .. col[words - 1][l], at base + l * stride (32-byte aligned);
  /// `words` a multiple of 4.
  static void rows(const D* col, int words, void* base, std::size_t stride) {
    char* out = static_cast<char*>(base);
    for (int j = 0; j < words; j += 4) {
      __m256d lo[4], hi[4];
      detail::transpose4(_mm512_castpd512_pd256(col[j]), _mm512_castpd512_pd256(col[j + 1]),
                         _mm512_castpd512_pd256(col[j + 2]), _mm512_castpd512_pd256(col[j + 3]),
                         lo);
      detail::transpose4(_mm512_extractf64x4_pd(col[j], 1), _mm512_extractf64x4_pd(col[j + 1], 1),
                         _mm512_extractf64x4_pd(col[j + 2], 1),
                         _mm512_extractf64x4_pd(col[j + 3], 1), hi);
      for (int l = 0; l < 4; ++l) {
        _mm256_store_pd(reinterpret_cast<double*>(out + l * stride + 8 * j), lo[l]);
        _mm256_store_pd(reinterpret_cast<double*>(out + (l + 4) * stride + 8 * j), hi[l]);
      }
    }
  }
  /// Integers held exactly in double lanes as int64 words.
  static D int64s(const D& v) { return _mm512_castsi512_pd(_mm512_cvtpd_epi64(v)); }
  /// Each lane's word: float(lo) in its low 32 bits, float(hi) in its high 32 bits.
  static D pack_floats(const D& lo, const D& hi) {
    return pack(_mm256_castps_si256(_mm512_cvtpd_ps(lo)), _mm256_castps_si256(_mm512_cvtpd_ps(hi)));
  }
  /// The same with int32 lo and hi (integers held exactly).
  static D pack_ints(const D& lo, const D& hi) {
    return pack(_mm512_cvttpd_epi32(lo), _mm512_cvttpd_epi32(hi));
  }

 private:
  static __m256d load(const void* p) { return _mm256_load_pd(static_cast<const double*>(p)); }
  static __m128 head(const void* p) { return _mm_load_ps(static_cast<const float*>(p)); }
  static D pack(__m256i lo, __m256i hi) {
    return _mm512_castsi512_pd(_mm512_or_si512(_mm512_cvtepu32_epi64(lo),
                                               _mm512_slli_epi64(_mm512_cvtepu32_epi64(hi), 32)));
  }
};
#endif

#if XSIMD_WITH_AVX2
template <>
struct Records<xsimd::avx2> {
  using D = xsimd::batch<double, xsimd::avx2>;
  using F = xsimd::batch<float, xsimd::avx2>;
  /// col[j] lane l: 32-bit word j of record rows[l] (16-byte aligned), as float bits.
  static void heads(const void* const (&rows)[8], F (&col)[4]) {
    __m256 r[4];
    for (int l = 0; l < 4; ++l)  // the low half holds record l, the high half record l + 4
      r[l] = _mm256_insertf128_ps(_mm256_castps128_ps256(head(rows[l])), head(rows[l + 4]), 1);
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    col[0] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    col[1] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    col[2] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
    col[3] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  }
  /// col[j] lane l: word j of record rows[l] (32-byte aligned), its bits as they are.
  static void columns(const void* const (&rows)[4], D (&col)[4]) {
    __m256d c[4];
    detail::transpose4(load(rows[0]), load(rows[1]), load(rows[2]), load(rows[3]), c);
    for (int j = 0; j < 4; ++j) col[j] = c[j];
  }
  /// Each lane's low (first in memory) or high 32 bits, as a float widened to double.
  static D low_floats(const D& v) {
    const __m256i even = _mm256_setr_epi32(0, 2, 4, 6, 0, 0, 0, 0);
    return _mm256_cvtps_pd(
        _mm256_castps256_ps128(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), even)));
  }
  static D high_floats(const D& v) {
    const __m256i odd = _mm256_setr_epi32(1, 3, 5, 7, 0, 0, 0, 0);
    return _mm256_cvtps_pd(
        _mm256_castps256_ps128(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), odd)));
  }
  /// Record l gets words col[0][l] .. col[words - 1][l], at base + l * stride (32-byte aligned);
  /// `words` a multiple of 4.
  static void rows(const D* col, int words, void* base, std::size_t stride) {
    char* out = static_cast<char*>(base);
    for (int j = 0; j < words; j += 4) {
      __m256d r[4];
      detail::transpose4(col[j], col[j + 1], col[j + 2], col[j + 3], r);
      for (int l = 0; l < 4; ++l)
        _mm256_store_pd(reinterpret_cast<double*>(out + l * stride + 8 * j), r[l]);
    }
  }
  /// Integers held exactly in double lanes (below 2^51 in magnitude) as int64 words: added to
  /// 1.5 * 2^52, the integer is the low bits of the sum's mantissa.
  static D int64s(const D& v) {
    const __m256d magic = _mm256_set1_pd(0x1.8p52);
    return _mm256_castsi256_pd(
        _mm256_sub_epi64(_mm256_castpd_si256(_mm256_add_pd(v, magic)), _mm256_castpd_si256(magic)));
  }
  /// Each lane's word: float(lo) in its low 32 bits, float(hi) in its high 32 bits.
  static D pack_floats(const D& lo, const D& hi) {
    return pack(_mm_castps_si128(_mm256_cvtpd_ps(lo)), _mm_castps_si128(_mm256_cvtpd_ps(hi)));
  }
  /// The same with int32 lo and hi (integers held exactly).
  static D pack_ints(const D& lo, const D& hi) {
    return pack(_mm256_cvttpd_epi32(lo), _mm256_cvttpd_epi32(hi));
  }

 private:
  static __m256d load(const void* p) { return _mm256_load_pd(static_cast<const double*>(p)); }
  static __m128 head(const void* p) { return _mm_load_ps(static_cast<const float*>(p)); }
  static D pack(__m128i lo, __m128i hi) {
    return _mm256_castsi256_pd(_mm256_or_si256(_mm256_cvtepu32_epi64(lo),
                                               _mm256_slli_epi64(_mm256_cvtepu32_epi64(hi), 32)));
  }
};
#endif

#if XSIMD_WITH_SSE4_1
template <>
struct Records<xsimd::sse4_1> {
  using D = xsimd::batch<double, xsimd::sse4_1>;
  using F = xsimd::batch<float, xsimd::sse4_1>;
  /// col[j] lane l: 32-bit word j of record rows[l] (16-byte aligned), as float bits.
  static void heads(const void* const (&rows)[4], F (&col)[4]) {
    __m128 r0 = head(rows[0]), r1 = head(rows[1]), r2 = head(rows[2]), r3 = head(rows[3]);
    _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
    col[0] = r0;
    col[1] = r1;
    col[2] = r2;
    col[3] = r3;
  }
  /// col[j] lane l: word j of record rows[l] (32-byte aligned), its bits as they are.
  static void columns(const void* const (&rows)[2], D (&col)[4]) {
    const double* r0 = static_cast<const double*>(rows[0]);
    const double* r1 = static_cast<const double*>(rows[1]);
    const __m128d a0 = _mm_load_pd(r0), b0 = _mm_load_pd(r0 + 2);
    const __m128d a1 = _mm_load_pd(r1), b1 = _mm_load_pd(r1 + 2);
    col[0] = _mm_unpacklo_pd(a0, a1);
    col[1] = _mm_unpackhi_pd(a0, a1);
    col[2] = _mm_unpacklo_pd(b0, b1);
    col[3] = _mm_unpackhi_pd(b0, b1);
  }
  /// Each lane's low (first in memory) or high 32 bits, as a float widened to double.
  static D low_floats(const D& v) {
    const __m128 f = _mm_castpd_ps(v);
    return _mm_cvtps_pd(_mm_shuffle_ps(f, f, _MM_SHUFFLE(2, 0, 2, 0)));
  }
  static D high_floats(const D& v) {
    const __m128 f = _mm_castpd_ps(v);
    return _mm_cvtps_pd(_mm_shuffle_ps(f, f, _MM_SHUFFLE(3, 1, 3, 1)));
  }
  /// Record l gets words col[0][l] .. col[words - 1][l], at base + l * stride (16-byte aligned);
  /// `words` a multiple of 2.
  static void rows(const D* col, int words, void* base, std::size_t stride) {
    char* out = static_cast<char*>(base);
    for (int j = 0; j < words; j += 2) {
      _mm_store_pd(reinterpret_cast<double*>(out + 8 * j), _mm_unpacklo_pd(col[j], col[j + 1]));
      _mm_store_pd(reinterpret_cast<double*>(out + stride + 8 * j),
                   _mm_unpackhi_pd(col[j], col[j + 1]));
    }
  }
  /// Integers held exactly in double lanes (below 2^51 in magnitude) as int64 words: added to
  /// 1.5 * 2^52, the integer is the low bits of the sum's mantissa.
  static D int64s(const D& v) {
    const __m128d magic = _mm_set1_pd(0x1.8p52);
    return _mm_castsi128_pd(
        _mm_sub_epi64(_mm_castpd_si128(_mm_add_pd(v, magic)), _mm_castpd_si128(magic)));
  }
  /// Each lane's word: float(lo) in its low 32 bits, float(hi) in its high 32 bits.
  static D pack_floats(const D& lo, const D& hi) {
    return _mm_castps_pd(_mm_unpacklo_ps(_mm_cvtpd_ps(lo), _mm_cvtpd_ps(hi)));
  }
  /// The same with int32 lo and hi (integers held exactly).
  static D pack_ints(const D& lo, const D& hi) {
    return _mm_castsi128_pd(_mm_unpacklo_epi32(_mm_cvttpd_epi32(lo), _mm_cvttpd_epi32(hi)));
  }

 private:
  static __m128 head(const void* p) { return _mm_load_ps(static_cast<const float*>(p)); }
};
#endif

}  // namespace mosaic::simd
