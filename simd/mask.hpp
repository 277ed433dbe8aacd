// simd/mask.hpp — lane masks as integers, for each instruction set mosaic compiles.
//
// xsimd 8 has no portable batch_bool <-> bit-mask conversion, so this is where the
// instructions are named: movmskps on SSE and AVX2, k-registers on AVX-512. Lane i is bit i.
// Also here, for the same reason: rounding double lanes to float precision (to_float()).
#pragma once

#include <cstdint>
#include <xsimd/xsimd.hpp>

namespace mosaic::simd {

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
  static xsimd::batch_bool<std::int32_t, A> ints(std::uint32_t b) {
    return xsimd::batch_bool<std::int32_t, A>(static_cast<__mmask16>(b));
  }
  static xsimd::batch_bool<float, A> floats(std::uint32_t b) {
    return xsimd::batch_bool<float, A>(static_cast<__mmask16>(b));
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
  static __m256i expand(std::uint32_t b) {
    const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(b)), lane_bit),
                              lane_bit);
  }
  static xsimd::batch_bool<std::int32_t, A> ints(std::uint32_t b) { return expand(b); }
  static xsimd::batch_bool<float, A> floats(std::uint32_t b) {
    return _mm256_castsi256_ps(expand(b));
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
  static __m128i expand(std::uint32_t b) {
    const __m128i lane_bit = _mm_setr_epi32(1, 2, 4, 8);
    return _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(static_cast<int>(b)), lane_bit), lane_bit);
  }
  static xsimd::batch_bool<std::int32_t, A> ints(std::uint32_t b) { return expand(b); }
  static xsimd::batch_bool<float, A> floats(std::uint32_t b) { return _mm_castsi128_ps(expand(b)); }
};
#endif

}  // namespace mosaic::simd
